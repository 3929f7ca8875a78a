// critical: the state of the pile nu(theta) (eq 1), z and lambda (eq 2), rearrangement
// events (Fig 2), the ensemble mean (inset of Fig 1a), the envelope of maxima and its
// limit nu_c (Fig 1c), the avalanche angle: the estimation. The product's parameters,
// notes and tables are laid out and written in critical_study_tables.cpp.
#include "cdpile/analysis/fit.hpp"
#include "cdpile/analysis/critical_study.hpp"

#include "cdpile/error.hpp"
#include "cdpile/fields.hpp"
#include "cdpile/parameter_keys.hpp"

#include "critical_study_tables.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace cdpile::analysis {

using namespace critical_parts;

const char* source_name(SeriesSource s) {
  switch (s) {
    case SeriesSource::steps: return "steps";
    case SeriesSource::frames: return "frames";
    case SeriesSource::sliding: return "sliding";
    default: return "auto";
  }
}

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

/// Four significant digits, for notes read by people.
std::string format_short(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

void check_steps(const RunRecord& r) {
  const std::size_t n = r.steps.step.size();
  auto same = [&](std::size_t m, const char* what, bool optional) {
    if ((optional && m == 0) || m == n) return;
    throw Error(r.name, "/observables",
                std::string(what) + " has " + std::to_string(m) + " rows, the step series " +
                    std::to_string(n));
  };
  same(r.steps.theta.size(), "tilt_angle", false);
  same(r.steps.contacts.size(), "the contact count", false);
  same(r.steps.critical.size(), "the critical count", true);
  same(r.steps.sliding.size(), "sliding", true);
  same(r.steps.kinetic_energy.size(), "kinetic_energy", true);
  same(r.steps.rotational_energy.size(), "rotational_energy", true);
  same(r.steps.converged.size(), "converged", true);
  same(r.steps.max_speed.size(), "max_speed", true);
  same(r.steps.grains_without_contact.size(), "grains_without_contact", true);
  same(r.steps.sweeps.size(), "sweeps", true);
  same(r.steps.substeps.size(), "substeps", true);
}

// Whether each step is static (RestRule; docs/analysis.md, "Static and moving states"):
// 1 or 0, or empty when the run lacks an observable the rule needs (files made before
// max_speed and grains_without_contact were recorded).
std::vector<std::int64_t> static_steps(const RunRecord& r, const RestRule& rest) {
  const RunSteps& s = r.steps;
  const std::size_t n = s.step.size();
  const double scale = r.mean_mass * r.gravity * r.diameter;  // m g D
  const double v_scale = std::sqrt(r.gravity * r.diameter);   // sqrt(g D)
  if (n == 0 || s.kinetic_energy.size() != n || s.rotational_energy.size() != n ||
      s.converged.size() != n || s.max_speed.size() != n || s.grains_without_contact.size() != n ||
      r.free_grains <= 0 || !(scale > 0.0))
    return {};
  std::vector<std::int64_t> out(n);
  const double np = static_cast<double>(r.free_grains);
  for (std::size_t k = 0; k < n; ++k)
    out[k] = s.converged[k] == 1 &&
             (s.kinetic_energy[k] + s.rotational_energy[k]) / np / scale < rest.energy &&
             s.max_speed[k] / v_scale < rest.speed && s.grains_without_contact[k] == 0;
  return out;
}

}  // namespace

namespace critical_parts {

std::optional<double> ratio(std::int64_t a, std::int64_t b) {
  if (b <= 0) return std::nullopt;
  return static_cast<double>(a) / static_cast<double>(b);
}

std::optional<bool> static_frame(const RunRecord& r, const FrameRecord& f, const RestRule& rest) {
  const RunSteps& s = r.steps;
  const double scale = r.mean_mass * r.gravity * r.diameter;
  const double v_scale = std::sqrt(r.gravity * r.diameter);
  if (s.converged.size() != s.step.size() || !f.agitation || !f.max_speed || !(scale > 0.0))
    return std::nullopt;
  const auto it = std::lower_bound(s.step.begin(), s.step.end(), f.step);
  if (it == s.step.end() || *it != f.step) {
    // frame 0 of a run is the pile before the first tilt step: static if at rest
    if (f.step != 0) return std::nullopt;
    return *f.agitation / scale < rest.energy && *f.max_speed / v_scale < rest.speed &&
           f.grains_without_contact == 0;
  }
  const auto k = static_cast<std::size_t>(it - s.step.begin());
  return s.converged[k] == 1 && *f.agitation / scale < rest.energy &&
         *f.max_speed / v_scale < rest.speed && f.grains_without_contact == 0;
}

std::optional<double> nu_at_rest(const FrameRecord& f) {
  return f.contacts_at_rest && f.critical_at_rest ? ratio(*f.critical_at_rest, *f.contacts_at_rest)
                                                  : std::nullopt;
}

}  // namespace critical_parts

namespace {

/// The shortest text that reads back to the same double: a message comparing two rules
/// must not print 0.5 for 0.5000001.
std::string exact(double v) {
  char buf[32];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return ec == std::errc() ? std::string(buf, end) : format_short(v);
}

// Parameters written as text and read back, or given as 1e-3 and 0.001, are the same.
bool same_value(double a, double b) {
  return std::abs(a - b) <= 1e-12 * std::max(std::abs(a), std::abs(b));
}

std::string join(const std::vector<std::string>& parts, const char* sep) {
  std::string s;
  for (const std::string& x : parts) s += (s.empty() ? "" : sep) + x;
  return s;
}

// For each run, how its recorded per-step critical count departs from the rule asked for
// (empty when it follows it, or when the run records no count).
std::vector<std::optional<StepRuleMismatch>> step_rule_mismatches(
    const std::vector<RunRecord>& runs, const CriticalRule& rule) {
  std::vector<std::optional<StepRuleMismatch>> out(runs.size());
  for (std::size_t k = 0; k < runs.size(); ++k)
    if (!runs[k].steps.critical.empty())
      out[k] = step_rule_mismatch(runs[k].recorded_rule, rule, runs[k].mu);
  return out;
}

// Notes on the runs whose per-step series is missing or not used.
void note_step_series(Product& p, const std::vector<RunRecord>& runs,
                      const std::vector<std::optional<StepRuleMismatch>>& mismatch) {
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const std::string& name = runs[k].name;
    if (runs[k].steps.step.empty())
      p.omit(name + ": no per-step observables: no steps, events or theta_c from this run");
    if (!mismatch[k]) continue;
    p.notes.push_back(name +
                      (mismatch[k]->unknown
                           ? " does not record the rule of its per-step critical count ("
                           : " recorded its per-step critical count with another rule (") +
                      mismatch[k]->why +
                      "): its per-step Nc, nu and lambda are NA and nu(theta) comes from "
                      "its frames unless " +
                      field("series") + " sliding");
  }
}

// Whether nu_c comes from frames above their static bound (docs/analysis.md, "Static
// bound"). nu_c is the limit of the envelope fitted over `windows` of grid `w`; each of its
// points is a mean over runs of the maximum of the run's nu in the window. The frame behind
// a run's maximum is the run's last frame at or before the maximum's step inside the same
// window: the maximum itself with --series frames, the state just before it otherwise (as
// an event's nu_before). A maximum with no such frame, or one whose frame has no bound, is
// not judged. Records the counts and, when any judged frame is above its bound, a warning.
void judge_static_bound(Product& p, const std::vector<RunRecord>& runs,
                        const std::vector<Curve>& curves,
                        const std::vector<std::vector<std::int64_t>>& steps, const Grid& w,
                        const std::vector<std::size_t>& windows, std::int64_t frames,
                        std::int64_t above) {
  std::int64_t judged = 0, judged_above = 0;
  for (std::size_t ri = 0; ri < runs.size(); ++ri) {
    const Curve& cv = curves[ri];
    for (std::size_t b : windows) {
      std::optional<std::size_t> at;  // the first maximum, as bin_max
      for (std::size_t k = 0; k < cv.theta.size(); ++k)
        if (w.bin(cv.theta[k]) == b && (!at || cv.nu[k] > cv.nu[*at])) at = k;
      if (!at) continue;
      const FrameRecord* frame = nullptr;
      for (const FrameRecord& f : runs[ri].frames)
        if (f.step <= steps[ri][*at] && w.bin(f.theta) == b && (!frame || f.step > frame->step))
          frame = &f;
      if (!frame || !frame->bound) continue;
      ++judged;
      judged_above += frame->bound->above();
    }
  }
  p.results["nu_c_maxima_judged"] = judged;
  p.results["nu_c_maxima_above_static_bound"] = judged_above;
  if (judged_above == 0) return;
  p.notes.push_back(
      std::string(warning_prefix) +
      "nu_c comes from frames above the static bound: " + std::to_string(judged_above) +
      " of the " + std::to_string(judged) + " envelope maxima in the fit [" +
      format_short(w.lower(windows.front())) + ", " + format_short(w.upper(windows.back())) +
      "] deg are at frames with more critical contacts than a static pile can hold "
      "(Nc > 2M - 3N: the pile was moving or the step unconverged), and " +
      std::to_string(above) + " of " + std::to_string(frames) +
      " frames of the runs are; for the pile at rest read nu_c_static (static frames only; a "
      "slower --rate gives it more) (docs/analysis.md, \"Static bound\")");
}

// Result names of a reading: "nu_c" + suffix + tail (nu_c_static_se), and the envelope's
// parameters "envelope" + suffix + tail (envelope_static_tau_deg).
std::string key(const char* base, const std::string& suffix, const char* tail = "") {
  return std::string(base) + suffix + tail;
}

Reading read_envelope(Product& p, const std::vector<Curve>& curves, const Grid& g, const Grid& w,
                      const CriticalOptions& opt, const std::string& suffix,
                      const std::string& label, std::optional<double> z_mean) {
  Reading rd;
  std::vector<std::vector<std::optional<double>>> means, maxima, argmax;
  for (const Curve& c : curves) {
    means.push_back(bin_mean(c.theta, c.nu, g));
    argmax.emplace_back();
    maxima.push_back(bin_max(c.theta, c.nu, w, &argmax.back()));
  }
  rd.ens = across_runs(means, g.count);
  rd.env = across_runs(maxima, w.count);
  rd.env_at = across_runs(argmax, w.count);
  rd.in_fit.assign(w.count, 0);
  rd.fit.assign(w.count, nan);
  if (std::all_of(curves.begin(), curves.end(), [](const Curve& c) { return c.theta.empty(); })) {
    p.omit(label + "not determined: no state in the loading phase (no ensemble, no envelope)");
    return rd;
  }
  const auto nruns = static_cast<std::int64_t>(curves.size());
  std::vector<double> ft, fv, fs;
  bool all_se = true;
  for (std::size_t b = 0; b < w.count; ++b) {
    if (rd.env[b].n == 0) continue;
    // the envelope's abscissa: the mean over runs of where the maxima occur (the maximum
    // of a rising nu sits at the window's end, not at its centre)
    const double c = rd.env_at[b].mean.value_or(w.centre(b));
    const bool in = opt.envelope_fit ? opt.envelope_fit->contains(c) : rd.env[b].n == nruns;
    if (!in) continue;
    rd.in_fit[b] = 1;
    rd.windows_in_fit.push_back(b);
    ft.push_back(c);
    fv.push_back(*rd.env[b].mean);
    fs.push_back(rd.env[b].se && *rd.env[b].se > 0 ? *rd.env[b].se : 0.0);
    all_se = all_se && fs.back() > 0.0;
  }
  if (ft.size() < 4) {
    p.omit(label + "not determined: fewer than 4 envelope windows in the fit range");
    return rd;
  }
  try {
    EnvelopeFit ef =
        fit_envelope(ft, fv, all_se ? std::span<const double>(fs) : std::span<const double>());
    // The limit nu_c is determined only when the envelope bends over inside the fitted
    // range: at least one relaxation length tau within it, and a limit that is a
    // fraction. A near-linear envelope (a small or fast-tilted pile) fits with a huge
    // tau and B, whose "limit" is an extrapolation far outside the data.
    const double span = ft.back() - ft.front();
    rd.saturates = ef.fit.converged && ef.tau() > 0.0 && ef.tau() < span && ef.nu_c() > 0.0 &&
                   ef.nu_c() <= 1.0;
    if (ef.fit.converged)
      p.results[key("envelope", suffix, "_saturates")] = std::int64_t{rd.saturates};
    if (ef.fit.converged && !rd.saturates)
      p.omit(label + "not determined: the envelope does not saturate in the fitted range [" +
             format_short(ft.front()) + ", " + format_short(ft.back()) + "] deg (tau = " +
             format_short(ef.tau()) + " deg, limit = " + format_short(ef.nu_c()) + ")");
    if (!ef.fit.converged)
      p.omit(label + "not determined: the envelope fit did not converge: " + ef.fit.status);
    if (!rd.saturates) return rd;
    p.results[key("nu_c", suffix)] = ef.nu_c();
    if (auto e = ef.fit.se(0)) p.results[key("nu_c", suffix, "_se")] = *e;
    p.results[key("envelope", suffix, "_b")] = ef.b();
    if (auto e = ef.fit.se(1)) p.results[key("envelope", suffix, "_b_se")] = *e;
    p.results[key("envelope", suffix, "_tau_deg")] = ef.tau();
    if (auto e = ef.fit.se(2)) p.results[key("envelope", suffix, "_tau_se_deg")] = *e;
    p.results[key("envelope", suffix, "_chi2")] = ef.fit.chi2;
    p.results[key("envelope", suffix, "_dof")] = static_cast<std::int64_t>(ef.fit.dof);
    p.results[key("envelope", suffix, "_points")] = static_cast<std::int64_t>(ft.size());
    p.results[key("envelope", suffix, "_weighted")] = std::int64_t{all_se};
    p.results[key("envelope", suffix, "_theta_lo_deg")] = ft.front();
    p.results[key("envelope", suffix, "_theta_hi_deg")] = ft.back();
    for (std::size_t b = 0; b < w.count; ++b) {
      if (rd.env[b].n == 0) continue;
      const double c = rd.env_at[b].mean.value_or(w.centre(b));
      rd.fit[b] = ef.nu_c() - ef.b() * std::exp(-c / ef.tau());
    }
    if (z_mean && ef.nu_c() > 0)
      if (auto l = critical_spacing(*z_mean, ef.nu_c(), 1.0))
        p.results[key("lambda_c", suffix, "_D")] = *l;
  } catch (const Error& e) {
    p.omit(label + "not determined: the envelope fit failed: " + e.what());
  }
  return rd;
}

}  // namespace

std::vector<std::string> product_warnings(const Product& p) {
  std::vector<std::string> out;
  const std::string prefix = warning_prefix;
  for (const std::string& n : p.notes)
    if (n.rfind(prefix, 0) == 0) out.push_back(n.substr(prefix.size()));
  return out;
}

std::string critical_readings(const Product& p) {
  auto six = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return std::string(buf);
  };
  std::string line;
  if (auto t = p.result("theta_c_deg")) line = "theta_c = " + six(*t) + " deg; ";
  std::string found, missing;
  for (const auto& [key, what] :
       {std::pair{"nu_c", "every state"}, std::pair{"nu_c_static", "static states"},
        std::pair{"nu_c_rest", "contacts at rest"}}) {
    if (auto v = p.result(key)) {
      const std::optional<double> se = p.result(std::string(key) + "_se");
      found += (found.empty() ? "" : ", ") + std::string(key) + " = " + six(*v) +
               (se ? " +- " + six(*se) : std::string()) + " (" + what + ")";
    } else {
      missing += (missing.empty() ? "" : ", ") + std::string(key);
    }
  }
  line += found;
  if (!missing.empty()) line += (found.empty() ? "" : "; ") + missing + " not determined";
  return line;
}

std::optional<StepRuleMismatch> step_rule_mismatch(const RecordedRule& rec,
                                                   const CriticalRule& rule, const Friction& mu) {
  std::vector<std::string> differ, missing;
  auto compare = [&](const char* what, const char* parameter, double asked,
                     std::optional<double> recorded) {
    if (!recorded)
      missing.push_back(std::string("no ") + parameter + " in /parameters");
    else if (!same_value(asked, *recorded))
      differ.push_back(std::string(what) + " " + exact(asked) + " asked, " + exact(*recorded) +
                       " recorded");
  };
  compare("eps", keys::critical_eps, rule.eps, rec.eps);
  compare("mu", keys::mu_grain, mu.grain, rec.mu_grain);
  if (rule.include_walls)
    compare("mu_wall", keys::mu_wall, mu.wall, rec.mu_wall);
  else if (!rule.floor_grains_are_walls)
    differ.push_back("floor grains counted as grains, not in critical_grain");
  // A known difference says more than a missing parameter.
  if (!differ.empty()) return StepRuleMismatch{false, join(differ, "; ")};
  if (!missing.empty()) return StepRuleMismatch{true, join(missing, ", ")};
  return std::nullopt;
}

void require_step_rule(const std::string& name, const RecordedRule& rec, const CriticalRule& rule,
                       const Friction& mu) {
  const auto m = step_rule_mismatch(rec, rule, mu);
  if (!m || m->unknown) return;
  throw UsageError(field("series") + " steps: " + name +
                   " recorded its per-step critical count with another rule (" + m->why +
                   "); use " + field("series") + " frames or auto");
}

std::optional<double> avalanche_angle(const RunRecord& r, const AvalancheRule& rule) {
  const RunSteps& s = r.steps;
  const double scale = r.mean_mass * r.gravity * r.diameter;  // m g D
  if (s.kinetic_energy.empty() || s.kinetic_energy.size() != s.theta.size() || r.free_grains <= 0 ||
      !(scale > 0.0))
    return std::nullopt;
  std::vector<double> e(s.theta.size());
  for (std::size_t k = 0; k < e.size(); ++k)
    e[k] = s.kinetic_energy[k] / static_cast<double>(r.free_grains) / scale;
  if (auto k = avalanche_index(s.theta, e, rule)) return s.theta[*k];
  return std::nullopt;
}

// ---------------------------------------------------------------------------------------
// The stages of critical_study, in the order it runs them.

namespace {

// Which nu(theta) series the study reads: the one asked for, or with auto the per-step
// critical count when every run records it by the rule asked for, else the frames. A
// per-step count recorded with another eps or mu counts other contacts. Refuses a series
// a run cannot give.
struct SeriesChoice {
  SeriesSource source = SeriesSource::frames;
  std::vector<std::optional<StepRuleMismatch>> mismatch;  // per run
};

SeriesChoice choose_series(const std::vector<RunRecord>& runs, const CriticalOptions& opt) {
  bool all_critical = !runs.empty(), all_sliding = !runs.empty();
  for (const RunRecord& r : runs) {
    check_steps(r);
    all_critical =
        all_critical && !r.steps.step.empty() && r.steps.critical.size() == r.steps.step.size();
    all_sliding =
        all_sliding && !r.steps.step.empty() && r.steps.sliding.size() == r.steps.step.size();
  }
  SeriesChoice c;
  c.mismatch = step_rule_mismatches(runs, opt.rule);
  const bool all_follow = std::none_of(c.mismatch.begin(), c.mismatch.end(),
                                       [](const auto& m) { return m.has_value(); });
  SeriesSource src = opt.source;
  if (src == SeriesSource::automatic)
    src = all_critical && all_follow ? SeriesSource::steps : SeriesSource::frames;
  if (src == SeriesSource::steps && !all_critical && !runs.empty())
    throw Error(field("series") +
                " steps: a run does not record a per-step critical count "
                "(observable critical_grain or critical); use " +
                field("series") + " frames or sliding");
  for (std::size_t k = 0; src == SeriesSource::steps && k < runs.size(); ++k) {
    require_step_rule(runs[k].name, runs[k].recorded_rule, opt.rule, runs[k].mu);
    if (c.mismatch[k])  // not recorded: the counts may follow any rule
      throw Error(runs[k].name, "",
                  field("series") +
                      " steps: the rule of the per-step critical count is not recorded (" +
                      c.mismatch[k]->why + "); use " + field("series") + " frames");
  }
  if (src == SeriesSource::sliding && !all_sliding && !runs.empty())
    throw Error(field("series") + " sliding: a run does not record the per-step sliding count");
  c.source = src;
  return c;
}

StepFractions step_fractions(const RunRecord& r, bool have_nc) {
  const RunSteps& s = r.steps;
  const std::size_t n = s.step.size();
  const double np = static_cast<double>(r.free_grains);
  const bool have_ek = !s.kinetic_energy.empty() && r.free_grains > 0;
  const double scale = r.mean_mass * r.gravity * r.diameter;  // m g D
  StepFractions q;
  q.have_nc = have_nc;
  q.nu_c.assign(n, nan);
  q.nu_s.assign(n, nan);
  q.ekn.assign(n, nan);
  for (std::size_t k = 0; k < n; ++k) {
    if (have_nc) q.nu_c[k] = ratio(s.critical[k], s.contacts[k]).value_or(nan);
    if (!s.sliding.empty()) q.nu_s[k] = ratio(s.sliding[k], s.contacts[k]).value_or(nan);
    if (have_ek && scale > 0.0) q.ekn[k] = s.kinetic_energy[k] / np / scale;
  }
  return q;
}

// The run's loading frames (at or below `cut`) added to the loading totals: z, the static
// bound, the static frames, and per tilt window the critical, slipping and mobilised
// contacts; the frames' nu of the contacts at rest go to `rest_curve`.
void tally_loading_frames(const RunRecord& r, double cut, const CriticalOptions& opt,
                          LoadingTotals& tot, Curve& rest_curve) {
  auto window_of = [&](double theta) -> std::optional<std::size_t> {
    if (!(theta >= 0.0)) return std::nullopt;
    return static_cast<std::size_t>(std::floor(theta / opt.mobilisation_window + 1e-9));
  };
  for (const FrameRecord& f : r.frames) {
    const PileState& st = f.state;
    const bool loading = f.theta <= cut;
    if (loading && st.z) {
      tot.z_sum += *st.z;
      ++tot.z_n;
    }
    if (f.bound) {
      ++tot.bound_frames;
      tot.bound_above += f.bound->above();
    }
    const std::optional<bool> still = static_frame(r, f, opt.rest);
    if (const std::optional<double> nu_rest = nu_at_rest(f); nu_rest && f.theta <= cut) {
      rest_curve.theta.push_back(f.theta);
      rest_curve.nu.push_back(*nu_rest);
    }
    if (f.z_paper && f.frame == 0) {
      tot.zp_initial_sum = tot.zp_initial_sum.value_or(0.0) + *f.z_paper;
      ++tot.zp_initial_n;
    }
    if (loading && f.z_paper) {
      tot.zp_sum += *f.z_paper;
      ++tot.zp_n;
    }
    if (loading && still && *still) {
      ++tot.frames_static;
      if (f.bound) tot.frames_static_above += f.bound->above();
    }
    if (const auto wi = window_of(f.theta); loading && wi) {
      if (tot.win_all.size() <= *wi) {
        tot.win_all.resize(*wi + 1);
        tot.win_static.resize(*wi + 1);
      }
      for (WindowCounts* wc :
           {&tot.win_all[*wi], (still && *still) ? &tot.win_static[*wi] : nullptr}) {
        if (!wc) continue;
        ++wc->frames;
        wc->contacts += st.contacts;
        wc->critical += st.critical;
        wc->slipping += f.slipping.value_or(0);
        wc->critical_slipping += f.critical_slipping.value_or(0);
        for (std::size_t b = 0; b < f.mobilisation.size() && b < mobilisation_bins; ++b)
          wc->mobilisation[b] += f.mobilisation[b];
      }
    }
  }
}

// The run's nu(theta) series by the chosen source, with the step of each point.
Curve nu_series(const RunRecord& r, SeriesSource src, const StepFractions& q,
                std::vector<std::int64_t>& steps) {
  const RunSteps& s = r.steps;
  Curve cv;
  if (src == SeriesSource::frames) {
    for (const FrameRecord& f : r.frames)
      if (f.state.nu) {
        cv.theta.push_back(f.theta);
        cv.nu.push_back(*f.state.nu);
        steps.push_back(f.step);
      }
  } else {
    const std::vector<double>& v = src == SeriesSource::steps ? q.nu_c : q.nu_s;
    for (std::size_t k = 0; k < s.step.size(); ++k)
      if (std::isfinite(v[k])) {
        cv.theta.push_back(s.theta[k]);
        cv.nu.push_back(v[k]);
        steps.push_back(s.step[k]);
      }
  }
  return cv;
}

// The run's static states of the loading phase: the series at the static steps when every
// run says which steps are static, else the static frames.
Curve static_series(const RunRecord& r, SeriesSource src, const StepFractions& q,
                    bool static_steps_known, const std::vector<std::int64_t>& st_static, double cut,
                    const RestRule& rest) {
  const RunSteps& s = r.steps;
  Curve sv;
  if (static_steps_known) {
    const std::vector<double>& v = src == SeriesSource::steps ? q.nu_c : q.nu_s;
    for (std::size_t k = 0; k < s.step.size(); ++k)
      if (std::isfinite(v[k]) && st_static[k] == 1 && s.theta[k] <= cut) {
        sv.theta.push_back(s.theta[k]);
        sv.nu.push_back(v[k]);
      }
  } else {
    for (const FrameRecord& f : r.frames) {
      const std::optional<double> v =
          src == SeriesSource::sliding ? f.state.nu_sliding : f.state.nu;
      const std::optional<bool> still = static_frame(r, f, rest);
      if (v && still && *still && f.theta <= cut) {
        sv.theta.push_back(f.theta);
        sv.nu.push_back(*v);
      }
    }
  }
  return sv;
}

// The paper's reading: nu "rises to a maximum value at theta_c", the mean of the run's
// static states in the last envelope window before its avalanche.
std::optional<double> nu_at_theta_c(const Curve& sv, double theta_c, double window) {
  double sum = 0.0;
  std::int64_t m = 0;
  for (std::size_t k = 0; k < sv.theta.size(); ++k)
    if (sv.theta[k] >= theta_c - window && sv.theta[k] <= theta_c) {
      sum += sv.nu[k];
      ++m;
    }
  if (m == 0) return std::nullopt;
  return sum / static_cast<double>(m);
}

// The loading phase of the series (theta <= cut), for the ensemble and the envelope, with
// the step of each kept point in `kept_steps`; returns the run's largest nu in it.
double keep_loading_phase(Curve& cv, const std::vector<std::int64_t>& cv_step, double cut,
                          std::vector<std::int64_t>& kept_steps) {
  Curve kept;
  double nu_max = nan;
  for (std::size_t k = 0; k < cv.theta.size(); ++k) {
    if (cv.theta[k] > cut) continue;
    kept.theta.push_back(cv.theta[k]);
    kept.nu.push_back(cv.nu[k]);
    kept_steps.push_back(cv_step[k]);
    nu_max = std::isfinite(nu_max) ? std::max(nu_max, cv.nu[k]) : cv.nu[k];
  }
  cv = std::move(kept);
  return nu_max;
}

// The runs' nu(theta) in their loading phases: every state, the static ones, the contacts
// at rest; and the step of each point of `all`.
struct Readings {
  std::vector<Curve> all, still, rest;
  std::vector<std::vector<std::int64_t>> all_steps;
};

// The ensemble results of the loading phases: theta_c, z, the static states and nu at
// theta_c. Returns the mean z of the loading frames (for lambda_c).
std::optional<double> write_loading_results(Product& p, std::size_t runs,
                                            const LoadingTotals& tot) {
  p.results["runs"] = static_cast<std::int64_t>(runs);
  if (!tot.theta_cs.empty()) {
    Summary s = summarize(tot.theta_cs);
    p.results["theta_c_runs"] = s.n;
    p.results["theta_c_deg"] = *s.mean;
    if (s.se) p.results["theta_c_se_deg"] = *s.se;
  }
  const std::optional<double> z_mean =
      tot.z_n > 0 ? std::optional<double>(tot.z_sum / static_cast<double>(tot.z_n)) : std::nullopt;
  if (z_mean) p.results["z_loading_mean"] = *z_mean;
  if (tot.zp_n > 0) p.results["z_paper_loading_mean"] = tot.zp_sum / static_cast<double>(tot.zp_n);
  if (tot.zp_initial_n > 0)
    p.results["z_paper_initial"] = *tot.zp_initial_sum / static_cast<double>(tot.zp_initial_n);
  if (tot.bound_frames > 0) {
    p.results["static_bound_frames"] = tot.bound_frames;
    p.results["static_bound_frames_above"] = tot.bound_above;
  }
  if (tot.steps_loading > 0) {
    p.results["static_steps"] = tot.steps_static;
    p.results["static_steps_fraction"] =
        static_cast<double>(tot.steps_static) / static_cast<double>(tot.steps_loading);
  }
  p.results["static_frames"] = tot.frames_static;
  p.results["static_frames_above_static_bound"] = tot.frames_static_above;
  if (!tot.nu_theta_c.empty()) {
    const Summary s = summarize(tot.nu_theta_c);
    p.results["nu_theta_c_runs"] = s.n;
    p.results["nu_theta_c"] = *s.mean;
    if (s.se) p.results["nu_theta_c_se"] = *s.se;
  }
  if (tot.frames_static_above > 0)
    p.notes.push_back(
        std::string(warning_prefix) + std::to_string(tot.frames_static_above) + " of the " +
        std::to_string(tot.frames_static) +
        " static frames of the loading phase hold more critical "
        "contacts than their static bound 2M - 3N: at rest and converged, yet not rigid-static "
        "(a contact stiffness, or the tolerance of the critical test)");
  return z_mean;
}

// Ensemble and envelope on common grids, every state and the static ones, and nu_c (Fig 1c).
void write_envelopes(Product& p, const StudyTables& t, const std::vector<RunRecord>& runs,
                     const Readings& rd, const CriticalOptions& opt, std::optional<double> z_mean,
                     const LoadingTotals& tot) {
  double tmin = inf, tmax = -inf;
  for (const Curve& c : rd.all)
    for (double x : c.theta) {
      tmin = std::min(tmin, x);
      tmax = std::max(tmax, x);
    }
  if (!(tmin <= tmax)) {
    p.omit("no nu(theta) data: the ensemble and envelope tables are empty");
    return;
  }
  auto grid_of = [&](double step) {
    const double start = std::floor(tmin / step + 1e-9) * step;
    return make_grid(start, std::max(tmax, start + step * 0.5), step);
  };
  const Grid g = grid_of(opt.grid_step);
  const Grid w = grid_of(opt.envelope_window);
  // the static readings first: notes on the reading of every state come last, as before
  const Reading rest =
      read_envelope(p, rd.rest, g, w, opt, "_rest", "nu_c_rest (contacts at rest) ", z_mean);
  const Reading still =
      read_envelope(p, rd.still, g, w, opt, "_static", "nu_c_static (static states) ", z_mean);
  const Reading all = read_envelope(p, rd.all, g, w, opt, "", "nu_c (every state) ", z_mean);
  if (all.saturates)
    judge_static_bound(p, runs, rd.all, rd.all_steps, w, all.windows_in_fit, tot.bound_frames,
                       tot.bound_above);
  write_ensemble_rows(t.ensemble, g, all, still, rest);
  write_envelope_rows(t.envelope, w, all, still, rest);
}

}  // namespace

Product critical_study(const std::vector<RunRecord>& runs, const CriticalOptions& opt) {
  validate(opt.rule, Friction{});
  if (!(opt.grid_step > 0.0)) throw Error("ensemble grid step must be > 0 deg");
  if (!(opt.envelope_window > 0.0)) throw Error("envelope window must be > 0 deg");
  const SeriesChoice choice = choose_series(runs, opt);
  const SeriesSource src = choice.source;
  Product p = describe_study(opt, src);
  note_step_series(p, runs, choice.mismatch);
  const StudyTables t = add_study_tables(p, opt.step_table);

  // The static reading takes the series asked for at the static steps when every run says
  // which steps are static, else the frames' (docs/analysis.md, "Static and moving states").
  bool static_steps_known = src != SeriesSource::frames;
  for (const RunRecord& r : runs)
    static_steps_known = static_steps_known && !static_steps(r, opt.rest).empty();
  if (src != SeriesSource::frames && !static_steps_known && !runs.empty())
    p.notes.push_back(
        "static states: not every run records which steps are static (observables max_speed, "
        "grains_without_contact, rotational_energy, converged): the static reading uses the "
        "frames");

  Readings rd;
  rd.all.resize(runs.size());
  rd.still.resize(runs.size());
  rd.rest.resize(runs.size());
  rd.all_steps.resize(runs.size());
  LoadingTotals tot;
  for (std::size_t ri = 0; ri < runs.size(); ++ri) {
    const RunRecord& r = runs[ri];
    const RunSteps& s = r.steps;
    const auto run = static_cast<std::int64_t>(ri);
    const StepFractions q = step_fractions(r, !s.critical.empty() && !choice.mismatch[ri]);
    const std::optional<double> theta_c = avalanche_angle(r, opt.avalanche);
    if (theta_c) tot.theta_cs.push_back(*theta_c);
    const double cut = !opt.cut_at_avalanche ? inf
                       : theta_c             ? *theta_c
                                             : r.recorded_avalanche.value_or(inf);
    const std::vector<std::int64_t> st_static = static_steps(r, opt.rest);
    for (std::size_t k = 0; k < st_static.size(); ++k)
      if (s.theta[k] <= cut) {
        ++tot.steps_loading;
        tot.steps_static += st_static[k];
      }

    std::vector<std::optional<bool>> frame_static;  // each frame, static or moving, once
    for (const FrameRecord& f : r.frames) frame_static.push_back(static_frame(r, f, opt.rest));
    if (t.steps) write_step_rows(*t.steps, r, run, q, st_static);
    write_frame_rows(t.frames, r, run, cut, frame_static);
    tally_loading_frames(r, cut, opt, tot, rd.rest[ri]);
    std::vector<std::int64_t> cv_step;
    rd.all[ri] = nu_series(r, src, q, cv_step);
    rd.still[ri] = static_series(r, src, q, static_steps_known, st_static, cut, opt.rest);
    if (theta_c)
      if (const auto nu = nu_at_theta_c(rd.still[ri], *theta_c, opt.envelope_window))
        tot.nu_theta_c.push_back(*nu);
    const std::size_t events =
        write_events(t.events, r, run, rd.all[ri], cv_step, q, cut, opt.events);
    const double nu_max = keep_loading_phase(rd.all[ri], cv_step, cut, rd.all_steps[ri]);

    write_run_row(t.runs, r, run, events, theta_c, nu_max);
  }

  const std::optional<double> z_mean = write_loading_results(p, runs.size(), tot);
  write_envelopes(p, t, runs, rd, opt, z_mean, tot);
  write_distributions(p, tot, opt);
  return p;
}

}  // namespace cdpile::analysis
