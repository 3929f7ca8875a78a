// critical: the state of the pile nu(theta) (eq 1), z and lambda (eq 2), rearrangement
// events (Fig 2), the ensemble mean (inset of Fig 1a), the envelope of maxima and its
// limit nu_c (Fig 1c), the avalanche angle.
#include "cdpile/analysis/fit.hpp"
#include "cdpile/analysis/studies.hpp"

#include "cdpile/error.hpp"
#include "cdpile/fields.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace cdpile::analysis {

const char* source_name(SeriesSource s) {
  switch (s) {
    case SeriesSource::steps: return "steps";
    case SeriesSource::frames: return "frames";
    case SeriesSource::sliding: return "sliding";
    default: return "auto";
  }
}

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();
constexpr double inf = std::numeric_limits<double>::infinity();

/// Four significant digits, for notes read by people.
std::string format_short(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

std::optional<double> ratio(std::int64_t a, std::int64_t b) {
  if (b <= 0) return std::nullopt;
  return static_cast<double>(a) / static_cast<double>(b);
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

// Whether a frame is static: its step converged (looked up in the run's steps), its grains
// at rest by the same rule and none in flight; empty when unknown.
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

// The nu(theta) series a run contributes to the ensemble and the envelope.
struct Curve {
  std::vector<double> theta, nu;
};

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
      "] deg are at frames with Nc > 2M - 3N (moving "
      "or unconverged, not static); " +
      std::to_string(above) + " of " + std::to_string(frames) +
      " frames of the runs are above their bound");
}

// One reading of nu(theta) over the runs (all states, or static states only): the ensemble
// mean on grid g, the envelope of maxima on windows w and its fit (Fig 1c).
struct Reading {
  std::vector<Summary> ens, env, env_at;
  std::vector<std::uint8_t> in_fit;  // per window
  std::vector<double> fit;           // per window, NaN where not fitted
  std::vector<std::size_t> windows_in_fit;
  bool saturates = false;
};

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
    p.omit(label + "no state in the loading phase: no ensemble, envelope or nu_c");
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
    p.omit(label + "envelope fit not done: fewer than 4 windows in the fit range");
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
      p.omit(label + "envelope does not saturate in the fitted range [" + format_short(ft.front()) +
             ", " + format_short(ft.back()) + "] deg (tau = " + format_short(ef.tau()) +
             " deg, limit = " + format_short(ef.nu_c()) + "): nu_c is not determined");
    if (!ef.fit.converged) p.omit(label + "envelope fit did not converge: " + ef.fit.status);
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
    p.omit(label + "envelope fit failed: " + e.what());
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
  compare("eps", "critical_eps", rule.eps, rec.eps);
  compare("mu", "mu_grain", mu.grain, rec.mu_grain);
  if (rule.include_walls)
    compare("mu_wall", "mu_wall", mu.wall, rec.mu_wall);
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

std::vector<std::string> critical_table_names(const CriticalOptions& opt) {
  if (opt.step_table)
    return {"runs", "steps", "frames", "events", "ensemble", "envelope", "mobilisation", "windows"};
  return {"runs", "frames", "events", "ensemble", "envelope", "mobilisation", "windows"};
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

// The product's kind, its parameters and the notes that define its columns.
Product describe_study(const CriticalOptions& opt, SeriesSource src) {
  Product p;
  p.kind = "critical";
  p.parameters = {
      {"eps", opt.rule.eps},
      {"include_walls", std::int64_t{opt.rule.include_walls}},
      {"floor_grains_are_walls", std::int64_t{opt.rule.floor_grains_are_walls}},
      {"rattlers", std::string(opt.rattlers == RattlerRule::exclude ? "exclude" : "include")},
      {"event_hysteresis", opt.events.hysteresis},
      {"event_min_drop", opt.events.min_drop},
      {"avalanche_threshold", opt.avalanche.threshold},
      {"avalanche_hold_deg", opt.avalanche.hold},
      {"cut_at_avalanche", std::int64_t{opt.cut_at_avalanche}},
      {"grid_step_deg", opt.grid_step},
      {"envelope_window_deg", opt.envelope_window},
      {"rest_energy_mgD", opt.rest.energy},
      {"rest_speed_sqrt_gD", opt.rest.speed},
      {"slip_speed_sqrt_gD", opt.slip_speed},
      {"mobilisation_window_deg", opt.mobilisation_window},
      {"series", std::string(source_name(src))}};
  // The envelope's fitted range decides nu_c where the envelope keeps rising
  // (docs/reproduction.md, "Sensitivity"): a range asked for is part of the product.
  if (opt.envelope_fit && std::isfinite(opt.envelope_fit->lo))
    p.parameters["envelope_fit_from_deg"] = opt.envelope_fit->lo;
  if (opt.envelope_fit && std::isfinite(opt.envelope_fit->hi))
    p.parameters["envelope_fit_to_deg"] = opt.envelope_fit->hi;
  p.notes = {
      "critical: f_n > 0 and |f_t| >= (1 - eps) mu f_n; N counts active contacts (f_n > 0), "
      "grain-grain unless include_walls",
      "nu = Nc/N (eq 1); z = 2N/Np' with Np' the free grains with >= 2 counted contacts "
      "(rattlers excluded) or all free grains (z_all); lambda = sqrt(2/(z nu)) D (eq 2), in D",
      "per-step z and lambda use z_all = 2N/Np (the per-step series has no per-grain counts)",
      "Ek: mean translational kinetic energy per free grain [J/m], per step from the observable "
      "kinetic_energy, per frame from the grains' velocities and masses; ek_norm = Ek/(m g D)",
      "theta_c: first step where ek_norm >= avalanche_threshold and stays so for "
      "avalanche_hold_deg (or to the end of the run); ensemble theta_c = mean over runs",
      "event: from a local maximum of N to the next local minimum (turning points confirmed "
      "after event_hysteresis contacts); loss = Delta N/N; nu_before = nu of the series at "
      "or before the maximum",
      "ensemble: per run the mean of nu in each theta bin, then mean and standard error over "
      "runs; envelope: per run the maximum of nu in each window, then mean and se over runs, "
      "placed at the mean theta where the maxima occur",
      "envelope fit: nu_c - B exp(-theta/tau) by Levenberg-Marquardt, weighted by the se when "
      "every window has one; uncertainties from the covariance (scaled by chi2/dof if > 1)",
      "missing values (NA): nu with N = 0, lambda with Nc = 0 (infinite), se from one run"};
  return p;
}

using Columns = std::initializer_list<std::tuple<const char*, const char*, ColumnKind>>;

void add_columns(Table& t, Columns columns) {
  for (auto [n, u, k] : columns) t.add_column(n, u, k);
}

// The per-run tables and the ensemble's, in the product's order, with their columns.
struct StudyTables {
  Table& runs;
  Table* steps;  // only with CriticalOptions::step_table
  Table& frames;
  Table& events;
  Table& ensemble;
  Table& envelope;
};

StudyTables add_study_tables(Product& p, bool step_table) {
  StudyTables t{p.add_table("runs", "one row per run"),
                step_table ? &p.add_table("steps", "one row per time step of each run") : nullptr,
                p.add_table("frames", "one row per saved frame of each run"),
                p.add_table("events", "rearrangement events: a drop of the contact count N"),
                p.add_table("ensemble", "nu(theta) averaged over runs on a common theta grid"),
                p.add_table("envelope", "mean over runs of the maximum of nu in theta windows")};
  add_columns(t.runs, {{"run", "", ColumnKind::integer},
                       {"name", "", ColumnKind::text},
                       {"grains", "", ColumnKind::integer},
                       {"diameter", "m", ColumnKind::real},
                       {"steps", "", ColumnKind::integer},
                       {"frames", "", ColumnKind::integer},
                       {"events", "", ColumnKind::integer},
                       {"theta_c", "deg", ColumnKind::real},
                       {"theta_c_recorded", "deg", ColumnKind::real},
                       {"nu_max", "", ColumnKind::real}});
  if (t.steps)
    add_columns(*t.steps, {{"run", "", ColumnKind::integer},
                           {"step", "", ColumnKind::integer},
                           {"theta", "deg", ColumnKind::real},
                           {"N", "", ColumnKind::integer},
                           {"Nc", "", ColumnKind::integer},
                           {"nu", "", ColumnKind::real},
                           {"sliding", "", ColumnKind::integer},
                           {"nu_sliding", "", ColumnKind::real},
                           {"z_all", "", ColumnKind::real},
                           {"lambda", "D", ColumnKind::real},
                           {"Ek", "J m-1", ColumnKind::real},
                           {"ek_norm", "", ColumnKind::real},
                           {"static", "", ColumnKind::integer}});
  add_columns(t.frames, {{"run", "", ColumnKind::integer},
                         {"frame", "", ColumnKind::integer},
                         {"step", "", ColumnKind::integer},
                         {"theta", "deg", ColumnKind::real},
                         {"N", "", ColumnKind::integer},
                         {"Nc", "", ColumnKind::integer},
                         {"nu", "", ColumnKind::real},
                         {"sliding", "", ColumnKind::integer},
                         {"nu_sliding", "", ColumnKind::real},
                         {"z", "", ColumnKind::real},
                         {"z_all", "", ColumnKind::real},
                         {"loaded_grains", "", ColumnKind::integer},
                         {"lambda", "D", ColumnKind::real},
                         {"Ek", "J m-1", ColumnKind::real},
                         {"ek_norm", "", ColumnKind::real},
                         {"loading", "", ColumnKind::integer},
                         {"contacts_load_bearing", "", ColumnKind::integer},
                         {"grains_load_bearing", "", ColumnKind::integer},
                         {"critical_load_bearing", "", ColumnKind::integer},
                         {"static_bound", "", ColumnKind::integer},
                         {"above_static_bound", "", ColumnKind::integer},
                         {"agitation_norm", "", ColumnKind::real},
                         {"max_speed_norm", "", ColumnKind::real},
                         {"grains_without_contact", "", ColumnKind::integer},
                         {"converged", "", ColumnKind::integer},
                         {"static", "", ColumnKind::integer},
                         {"slipping", "", ColumnKind::integer},
                         {"critical_slipping", "", ColumnKind::integer},
                         {"z_paper", "", ColumnKind::real},
                         {"N_rest", "", ColumnKind::integer},
                         {"Nc_rest", "", ColumnKind::integer},
                         {"nu_rest", "", ColumnKind::real}});
  add_columns(t.events, {{"run", "", ColumnKind::integer},
                         {"event", "", ColumnKind::integer},
                         {"peak_step", "", ColumnKind::integer},
                         {"trough_step", "", ColumnKind::integer},
                         {"theta", "deg", ColumnKind::real},
                         {"theta_end", "deg", ColumnKind::real},
                         {"n_peak", "", ColumnKind::integer},
                         {"n_trough", "", ColumnKind::integer},
                         {"loss", "", ColumnKind::real},
                         {"nu_before", "", ColumnKind::real},
                         {"nu_before_step", "", ColumnKind::integer},
                         {"nu_sliding_before", "", ColumnKind::real},
                         {"open", "", ColumnKind::integer},
                         {"after_avalanche", "", ColumnKind::integer}});
  add_columns(t.ensemble, {{"theta", "deg", ColumnKind::real},
                           {"theta_lo", "deg", ColumnKind::real},
                           {"theta_hi", "deg", ColumnKind::real},
                           {"runs", "", ColumnKind::integer},
                           {"nu", "", ColumnKind::real},
                           {"nu_se", "", ColumnKind::real},
                           {"runs_static", "", ColumnKind::integer},
                           {"nu_static", "", ColumnKind::real},
                           {"nu_static_se", "", ColumnKind::real},
                           {"runs_rest", "", ColumnKind::integer},
                           {"nu_rest", "", ColumnKind::real},
                           {"nu_rest_se", "", ColumnKind::real}});
  add_columns(t.envelope, {{"theta", "deg", ColumnKind::real},
                           {"theta_lo", "deg", ColumnKind::real},
                           {"theta_hi", "deg", ColumnKind::real},
                           {"runs", "", ColumnKind::integer},
                           {"envelope", "", ColumnKind::real},
                           {"envelope_se", "", ColumnKind::real},
                           {"fit", "", ColumnKind::real},
                           {"in_fit", "", ColumnKind::integer},
                           {"theta_static", "deg", ColumnKind::real},
                           {"runs_static", "", ColumnKind::integer},
                           {"envelope_static", "", ColumnKind::real},
                           {"envelope_static_se", "", ColumnKind::real},
                           {"fit_static", "", ColumnKind::real},
                           {"in_fit_static", "", ColumnKind::integer},
                           {"theta_rest", "deg", ColumnKind::real},
                           {"runs_rest", "", ColumnKind::integer},
                           {"envelope_rest", "", ColumnKind::real},
                           {"envelope_rest_se", "", ColumnKind::real},
                           {"fit_rest", "", ColumnKind::real},
                           {"in_fit_rest", "", ColumnKind::integer}});
  return t;
}

// Per tilt window of the loading phase: counts pooled over the runs' loading frames.
struct WindowCounts {
  std::int64_t frames = 0, contacts = 0, critical = 0, slipping = 0, critical_slipping = 0;
  std::vector<std::int64_t> mobilisation = std::vector<std::int64_t>(mobilisation_bins, 0);
};

// What the runs' loading phases add up to, run after run.
struct LoadingTotals {
  std::vector<double> theta_cs;    // per run with an avalanche
  std::vector<double> nu_theta_c;  // per run: mean static nu in the last window before theta_c
  std::int64_t steps_loading = 0, steps_static = 0, frames_static = 0, frames_static_above = 0;
  double zp_sum = 0.0;
  std::int64_t zp_n = 0;
  std::optional<double> zp_initial_sum;
  std::int64_t zp_initial_n = 0;
  std::vector<WindowCounts> win_all, win_static;   // all loading frames / static ones
  std::int64_t bound_frames = 0, bound_above = 0;  // frames with a static bound, and above it
  double z_sum = 0.0;
  std::int64_t z_n = 0;
};

// A run's per-step fractions: nu from the recorded critical count (when it follows the
// rule asked for), nu_sliding, and the agitation Ek/(m g D).
struct StepFractions {
  bool have_nc = false;
  std::vector<double> nu_c, nu_s, ekn;
};

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

void write_step_rows(Table& t, const RunRecord& r, std::int64_t run, const StepFractions& q,
                     const std::vector<std::int64_t>& st_static) {
  const RunSteps& s = r.steps;
  const double np = static_cast<double>(r.free_grains);
  const bool have_ek = !s.kinetic_energy.empty() && r.free_grains > 0;
  for (std::size_t k = 0; k < s.step.size(); ++k) {
    t.column("run").add_int(run);
    t.column("step").add_int(s.step[k]);
    t.column("theta").add(s.theta[k]);
    t.column("N").add_int(s.contacts[k]);
    t.column("Nc").add(q.have_nc ? static_cast<double>(s.critical[k]) : nan);
    t.column("nu").add(q.nu_c[k]);
    t.column("sliding").add(s.sliding.empty() ? nan : static_cast<double>(s.sliding[k]));
    t.column("nu_sliding").add(q.nu_s[k]);
    const auto z_all = ratio(2 * s.contacts[k], r.free_grains);
    t.column("z_all").add(z_all);
    t.column("lambda").add(z_all && std::isfinite(q.nu_c[k])
                               ? critical_spacing(*z_all, q.nu_c[k], 1.0)
                               : std::nullopt);
    t.column("Ek").add(have_ek ? s.kinetic_energy[k] / np : nan);
    t.column("ek_norm").add(q.ekn[k]);
    t.column("static").add(st_static.empty() ? nan : static_cast<double>(st_static[k]));
  }
}

// The run's frames: their rows, with each frame's classification as loading (at or below
// `cut`) and static or moving (docs/analysis.md, "Static and moving states"), added to the
// loading totals; the frames' nu of the contacts at rest go to `rest_curve`.
void classify_frames(Table& t, const RunRecord& r, std::int64_t run, double cut,
                     const CriticalOptions& opt, LoadingTotals& tot, Curve& rest_curve) {
  const RunSteps& s = r.steps;
  const double scale = r.mean_mass * r.gravity * r.diameter;  // m g D
  const double v_scale = std::sqrt(r.gravity * r.diameter);
  auto window_of = [&](double theta) -> std::optional<std::size_t> {
    if (!(theta >= 0.0)) return std::nullopt;
    return static_cast<std::size_t>(std::floor(theta / opt.mobilisation_window + 1e-9));
  };
  for (const FrameRecord& f : r.frames) {
    const PileState& st = f.state;
    t.column("run").add_int(run);
    t.column("frame").add_int(f.frame);
    t.column("step").add_int(f.step);
    t.column("theta").add(f.theta);
    t.column("N").add_int(st.contacts);
    t.column("Nc").add_int(st.critical);
    t.column("nu").add(st.nu);
    t.column("sliding").add_int(st.sliding);
    t.column("nu_sliding").add(st.nu_sliding);
    t.column("z").add(st.z);
    t.column("z_all").add(st.z_all);
    t.column("loaded_grains").add_int(st.loaded_grains);
    t.column("lambda").add(st.lambda && r.diameter > 0
                               ? std::optional<double>(*st.lambda / r.diameter)
                               : std::nullopt);
    t.column("Ek").add(f.kinetic_energy);
    t.column("ek_norm").add(f.kinetic_energy && scale > 0.0
                                ? std::optional<double>(*f.kinetic_energy / scale)
                                : std::nullopt);
    const bool loading = f.theta <= cut;
    t.column("loading").add_int(loading);
    if (loading && st.z) {
      tot.z_sum += *st.z;
      ++tot.z_n;
    }
    // McNamara & Herrmann 2004 (docs/analysis.md, "Static bound")
    auto count = [&](auto get) {
      return f.bound ? std::optional<double>(static_cast<double>(get(*f.bound))) : std::nullopt;
    };
    t.column("contacts_load_bearing").add(count([](const StaticBound& b) { return b.contacts; }));
    t.column("grains_load_bearing").add(count([](const StaticBound& b) { return b.grains; }));
    t.column("critical_load_bearing").add(count([](const StaticBound& b) { return b.critical; }));
    t.column("static_bound").add(count([](const StaticBound& b) { return b.bound(); }));
    t.column("above_static_bound").add(count([](const StaticBound& b) {
      return std::int64_t{b.above()};
    }));
    if (f.bound) {
      ++tot.bound_frames;
      tot.bound_above += f.bound->above();
    }
    // static or moving (docs/analysis.md, "Static and moving states")
    const std::optional<bool> still = static_frame(r, f, opt.rest);
    t.column("agitation_norm")
        .add(f.agitation && scale > 0.0 ? std::optional<double>(*f.agitation / scale)
                                        : std::nullopt);
    t.column("max_speed_norm")
        .add(f.max_speed && v_scale > 0.0 ? std::optional<double>(*f.max_speed / v_scale)
                                          : std::nullopt);
    t.column("grains_without_contact").add_int(f.grains_without_contact);
    {
      const auto it = std::lower_bound(s.step.begin(), s.step.end(), f.step);
      const bool found = it != s.step.end() && *it == f.step && s.converged.size() == s.step.size();
      t.column("converged")
          .add(found
                   ? static_cast<double>(s.converged[static_cast<std::size_t>(it - s.step.begin())])
                   : nan);
    }
    t.column("static").add(still ? std::optional<double>(*still ? 1.0 : 0.0) : std::nullopt);
    auto count_opt = [](const std::optional<std::int64_t>& v) {
      return v ? std::optional<double>(static_cast<double>(*v)) : std::nullopt;
    };
    t.column("slipping").add(count_opt(f.slipping));
    t.column("critical_slipping").add(count_opt(f.critical_slipping));
    t.column("z_paper").add(f.z_paper);
    t.column("N_rest").add(count_opt(f.contacts_at_rest));
    t.column("Nc_rest").add(count_opt(f.critical_at_rest));
    const std::optional<double> nu_rest = f.contacts_at_rest && f.critical_at_rest
                                              ? ratio(*f.critical_at_rest, *f.contacts_at_rest)
                                              : std::nullopt;
    t.column("nu_rest").add(nu_rest);
    if (nu_rest && f.theta <= cut) {
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

// The run's rearrangement events (Fig 2), each with the state of the series just before.
std::size_t write_events(Table& t, const RunRecord& r, std::int64_t run, const Curve& cv,
                         const std::vector<std::int64_t>& cv_step, const StepFractions& q,
                         double cut, const EventRule& rule) {
  const RunSteps& s = r.steps;
  const auto events = rearrangements(s.contacts, rule);
  std::int64_t e_index = 0;
  for (const Event& e : events) {
    const std::int64_t peak_step = s.step[e.peak];
    // the state just before: the last sample of the series at or before the peak step
    std::optional<double> nu_before;
    std::optional<double> nu_before_step;
    auto it = std::upper_bound(cv_step.begin(), cv_step.end(), peak_step);
    if (it != cv_step.begin()) {
      const auto k = static_cast<std::size_t>(it - cv_step.begin() - 1);
      nu_before = cv.nu[k];
      nu_before_step = static_cast<double>(cv_step[k]);
    }
    t.column("run").add_int(run);
    t.column("event").add_int(e_index++);
    t.column("peak_step").add_int(peak_step);
    t.column("trough_step").add_int(s.step[e.trough]);
    t.column("theta").add(s.theta[e.peak]);
    t.column("theta_end").add(s.theta[e.trough]);
    t.column("n_peak").add_int(e.n_peak);
    t.column("n_trough").add_int(e.n_trough);
    t.column("loss").add(e.loss);
    t.column("nu_before").add(nu_before);
    t.column("nu_before_step").add(nu_before_step);
    t.column("nu_sliding_before").add(q.nu_s.empty() ? nan : q.nu_s[e.peak]);
    t.column("open").add_int(e.open);
    t.column("after_avalanche").add_int(s.theta[e.peak] > cut);
  }
  return events.size();
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
  const Reading rest = read_envelope(p, rd.rest, g, w, opt, "_rest", "contacts at rest: ", z_mean);
  const Reading still = read_envelope(p, rd.still, g, w, opt, "_static", "static states: ", z_mean);
  const Reading all = read_envelope(p, rd.all, g, w, opt, "", "", z_mean);
  if (all.saturates)
    judge_static_bound(p, runs, rd.all, rd.all_steps, w, all.windows_in_fit, tot.bound_frames,
                       tot.bound_above);
  Table& ens_t = t.ensemble;
  for (std::size_t b = 0; b < g.count; ++b) {
    if (all.ens[b].n == 0) continue;
    ens_t.column("theta").add(g.centre(b));
    ens_t.column("theta_lo").add(g.lower(b));
    ens_t.column("theta_hi").add(g.upper(b));
    ens_t.column("runs").add_int(all.ens[b].n);
    ens_t.column("nu").add(all.ens[b].mean);
    ens_t.column("nu_se").add(all.ens[b].se);
    ens_t.column("runs_static").add_int(still.ens[b].n);
    ens_t.column("nu_static").add(still.ens[b].mean);
    ens_t.column("nu_static_se").add(still.ens[b].se);
    ens_t.column("runs_rest").add_int(rest.ens[b].n);
    ens_t.column("nu_rest").add(rest.ens[b].mean);
    ens_t.column("nu_rest_se").add(rest.ens[b].se);
  }
  Table& env_t = t.envelope;
  for (std::size_t b = 0; b < w.count; ++b) {
    if (all.env[b].n == 0) continue;
    env_t.column("theta").add(all.env_at[b].mean.value_or(w.centre(b)));
    env_t.column("theta_lo").add(w.lower(b));
    env_t.column("theta_hi").add(w.upper(b));
    env_t.column("runs").add_int(all.env[b].n);
    env_t.column("envelope").add(all.env[b].mean);
    env_t.column("envelope_se").add(all.env[b].se);
    env_t.column("fit").add(all.fit[b]);
    env_t.column("in_fit").add_int(all.in_fit[b]);
    env_t.column("theta_static").add(still.env[b].n ? still.env_at[b].mean : std::nullopt);
    env_t.column("runs_static").add_int(still.env[b].n);
    env_t.column("envelope_static").add(still.env[b].mean);
    env_t.column("envelope_static_se").add(still.env[b].se);
    env_t.column("fit_static").add(still.fit[b]);
    env_t.column("in_fit_static").add_int(still.in_fit[b]);
    env_t.column("theta_rest").add(rest.env[b].n ? rest.env_at[b].mean : std::nullopt);
    env_t.column("runs_rest").add_int(rest.env[b].n);
    env_t.column("envelope_rest").add(rest.env[b].mean);
    env_t.column("envelope_rest_se").add(rest.env[b].se);
    env_t.column("fit_rest").add(rest.fit[b]);
    env_t.column("in_fit_rest").add_int(rest.in_fit[b]);
  }
}

// Per window of the loading phase: the distribution of the mobilisation of the counted
// contacts, and the contacts that slip beside the critical ones (sliding is motion,
// critical is force).
void write_distributions(Product& p, const LoadingTotals& tot, const CriticalOptions& opt) {
  Table& mob_t = p.add_table("mobilisation",
                             "P(|f_t|/(mu f_n)) of the counted contacts per tilt window, "
                             "loading frames (all and static)");
  Table& win_t = p.add_table("windows",
                             "per tilt window, loading frames pooled over runs: critical and "
                             "slipping contacts, all frames and static ones");
  add_columns(mob_t, {{"theta_lo", "deg", ColumnKind::real},
                      {"theta_hi", "deg", ColumnKind::real},
                      {"m_lo", "", ColumnKind::real},
                      {"m_hi", "", ColumnKind::real},
                      {"contacts", "", ColumnKind::integer},
                      {"pdf", "", ColumnKind::real},
                      {"contacts_static", "", ColumnKind::integer},
                      {"pdf_static", "", ColumnKind::real}});
  add_columns(win_t, {{"theta_lo", "deg", ColumnKind::real},
                      {"theta_hi", "deg", ColumnKind::real},
                      {"frames", "", ColumnKind::integer},
                      {"frames_static", "", ColumnKind::integer},
                      {"nu", "", ColumnKind::real},
                      {"nu_static", "", ColumnKind::real},
                      {"nu_slipping", "", ColumnKind::real},
                      {"nu_slipping_static", "", ColumnKind::real},
                      {"critical_slipping_fraction", "", ColumnKind::real},
                      {"critical_slipping_fraction_static", "", ColumnKind::real}});
  const double width = 1.0 / static_cast<double>(mobilisation_bins);
  for (std::size_t wi = 0; wi < tot.win_all.size(); ++wi) {
    const WindowCounts& a = tot.win_all[wi];
    const WindowCounts& st = tot.win_static[wi];
    if (a.frames == 0) continue;
    const double lo = static_cast<double>(wi) * opt.mobilisation_window,
                 hi = lo + opt.mobilisation_window;
    auto frac = [](std::int64_t x, std::int64_t n) {
      return n > 0 ? static_cast<double>(x) / static_cast<double>(n) : nan;
    };
    win_t.column("theta_lo").add(lo);
    win_t.column("theta_hi").add(hi);
    win_t.column("frames").add_int(a.frames);
    win_t.column("frames_static").add_int(st.frames);
    win_t.column("nu").add(frac(a.critical, a.contacts));
    win_t.column("nu_static").add(frac(st.critical, st.contacts));
    win_t.column("nu_slipping").add(frac(a.slipping, a.contacts));
    win_t.column("nu_slipping_static").add(frac(st.slipping, st.contacts));
    win_t.column("critical_slipping_fraction").add(frac(a.critical_slipping, a.critical));
    win_t.column("critical_slipping_fraction_static").add(frac(st.critical_slipping, st.critical));
    std::int64_t total = 0, total_static = 0;
    for (std::size_t b = 0; b < mobilisation_bins; ++b) {
      total += a.mobilisation[b];
      total_static += st.mobilisation[b];
    }
    for (std::size_t b = 0; b < mobilisation_bins; ++b) {
      mob_t.column("theta_lo").add(lo);
      mob_t.column("theta_hi").add(hi);
      mob_t.column("m_lo").add(static_cast<double>(b) * width);
      mob_t.column("m_hi").add(static_cast<double>(b + 1) * width);
      mob_t.column("contacts").add_int(a.mobilisation[b]);
      mob_t.column("pdf").add(total > 0 ? static_cast<double>(a.mobilisation[b]) /
                                              static_cast<double>(total) / width
                                        : nan);
      mob_t.column("contacts_static").add_int(st.mobilisation[b]);
      mob_t.column("pdf_static")
          .add(total_static > 0 ? static_cast<double>(st.mobilisation[b]) /
                                      static_cast<double>(total_static) / width
                                : nan);
    }
  }
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

    if (t.steps) write_step_rows(*t.steps, r, run, q, st_static);
    classify_frames(t.frames, r, run, cut, opt, tot, rd.rest[ri]);
    std::vector<std::int64_t> cv_step;
    rd.all[ri] = nu_series(r, src, q, cv_step);
    rd.still[ri] = static_series(r, src, q, static_steps_known, st_static, cut, opt.rest);
    if (theta_c)
      if (const auto nu = nu_at_theta_c(rd.still[ri], *theta_c, opt.envelope_window))
        tot.nu_theta_c.push_back(*nu);
    const std::size_t events =
        write_events(t.events, r, run, rd.all[ri], cv_step, q, cut, opt.events);
    const double nu_max = keep_loading_phase(rd.all[ri], cv_step, cut, rd.all_steps[ri]);

    t.runs.column("run").add_int(run);
    t.runs.column("name").add_text(r.name);
    t.runs.column("grains").add_int(r.free_grains);
    t.runs.column("diameter").add(r.diameter);
    t.runs.column("steps").add_int(static_cast<std::int64_t>(s.step.size()));
    t.runs.column("frames").add_int(static_cast<std::int64_t>(r.frames.size()));
    t.runs.column("events").add_int(static_cast<std::int64_t>(events));
    t.runs.column("theta_c").add(theta_c);
    t.runs.column("theta_c_recorded").add(r.recorded_avalanche);
    t.runs.column("nu_max").add(nu_max);
  }

  const std::optional<double> z_mean = write_loading_results(p, runs.size(), tot);
  write_envelopes(p, t, runs, rd, opt, z_mean, tot);
  write_distributions(p, tot, opt);
  return p;
}

}  // namespace cdpile::analysis
