// critical's product (docs/analysis.md, "Formats"): its parameters and notes, the
// layout of its tables and their rows, from what the estimation in critical_study.cpp
// found. Nothing here estimates: a row is written as the estimation hands it over.
#include "critical_study_tables.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <tuple>

namespace cdpile::analysis {

std::vector<std::string> critical_table_names(const CriticalOptions& opt) {
  if (opt.step_table)
    return {"runs", "steps", "frames", "events", "ensemble", "envelope", "mobilisation", "windows"};
  return {"runs", "frames", "events", "ensemble", "envelope", "mobilisation", "windows"};
}

namespace critical_parts {

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

namespace {

using Columns = std::initializer_list<std::tuple<const char*, const char*, ColumnKind>>;

void add_columns(Table& t, Columns columns) {
  for (auto [n, u, k] : columns) t.add_column(n, u, k);
}

}  // namespace

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

void write_run_row(Table& t, const RunRecord& r, std::int64_t run, std::size_t events,
                   std::optional<double> theta_c, double nu_max) {
  t.column("run").add_int(run);
  t.column("name").add_text(r.name);
  t.column("grains").add_int(r.free_grains);
  t.column("diameter").add(r.diameter);
  t.column("steps").add_int(static_cast<std::int64_t>(r.steps.step.size()));
  t.column("frames").add_int(static_cast<std::int64_t>(r.frames.size()));
  t.column("events").add_int(static_cast<std::int64_t>(events));
  t.column("theta_c").add(theta_c);
  t.column("theta_c_recorded").add(r.recorded_avalanche);
  t.column("nu_max").add(nu_max);
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

void write_frame_rows(Table& t, const RunRecord& r, std::int64_t run, double cut,
                      const RestRule& rest) {
  const RunSteps& s = r.steps;
  const double scale = r.mean_mass * r.gravity * r.diameter;  // m g D
  const double v_scale = std::sqrt(r.gravity * r.diameter);
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
    t.column("loading").add_int(f.theta <= cut);
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
    // static or moving (docs/analysis.md, "Static and moving states")
    const std::optional<bool> still = static_frame(r, f, rest);
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
    t.column("nu_rest").add(nu_at_rest(f));
  }
}

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

void write_ensemble_rows(Table& t, const Grid& g, const Reading& all, const Reading& still,
                         const Reading& rest) {
  for (std::size_t b = 0; b < g.count; ++b) {
    if (all.ens[b].n == 0) continue;
    t.column("theta").add(g.centre(b));
    t.column("theta_lo").add(g.lower(b));
    t.column("theta_hi").add(g.upper(b));
    t.column("runs").add_int(all.ens[b].n);
    t.column("nu").add(all.ens[b].mean);
    t.column("nu_se").add(all.ens[b].se);
    t.column("runs_static").add_int(still.ens[b].n);
    t.column("nu_static").add(still.ens[b].mean);
    t.column("nu_static_se").add(still.ens[b].se);
    t.column("runs_rest").add_int(rest.ens[b].n);
    t.column("nu_rest").add(rest.ens[b].mean);
    t.column("nu_rest_se").add(rest.ens[b].se);
  }
}

void write_envelope_rows(Table& t, const Grid& w, const Reading& all, const Reading& still,
                         const Reading& rest) {
  for (std::size_t b = 0; b < w.count; ++b) {
    if (all.env[b].n == 0) continue;
    t.column("theta").add(all.env_at[b].mean.value_or(w.centre(b)));
    t.column("theta_lo").add(w.lower(b));
    t.column("theta_hi").add(w.upper(b));
    t.column("runs").add_int(all.env[b].n);
    t.column("envelope").add(all.env[b].mean);
    t.column("envelope_se").add(all.env[b].se);
    t.column("fit").add(all.fit[b]);
    t.column("in_fit").add_int(all.in_fit[b]);
    t.column("theta_static").add(still.env[b].n ? still.env_at[b].mean : std::nullopt);
    t.column("runs_static").add_int(still.env[b].n);
    t.column("envelope_static").add(still.env[b].mean);
    t.column("envelope_static_se").add(still.env[b].se);
    t.column("fit_static").add(still.fit[b]);
    t.column("in_fit_static").add_int(still.in_fit[b]);
    t.column("theta_rest").add(rest.env[b].n ? rest.env_at[b].mean : std::nullopt);
    t.column("runs_rest").add_int(rest.env[b].n);
    t.column("envelope_rest").add(rest.env[b].mean);
    t.column("envelope_rest_se").add(rest.env[b].se);
    t.column("fit_rest").add(rest.fit[b]);
    t.column("in_fit_rest").add_int(rest.in_fit[b]);
  }
}

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

}  // namespace critical_parts

Product critical_contacts(const std::vector<RunRecord>& runs, const CriticalOptions& opt) {
  Product p;
  p.kind = "critical_contacts";
  p.parameters = {{"eps", opt.rule.eps},
                  {"include_walls", std::int64_t{opt.rule.include_walls}},
                  {"floor_grains_are_walls", std::int64_t{opt.rule.floor_grains_are_walls}},
                  {"slip_speed_sqrt_gD", opt.slip_speed}};
  p.notes = {
      "one row per counted contact of every frame (active, f_n > 0; grain-grain unless "
      "include_walls), in the frame's order; run: the input's index, as in critical's tables",
      "critical: f_n > 0 and |f_t| >= (1 - eps) mu f_n; sliding: the solver's status slide "
      "(NA without a status); slip: |u_t| above slip_speed sqrt(g D) (NA without velocities, "
      "g or D)"};
  Table& t = p.add_table("contacts", "one row per counted contact of a frame");
  critical_parts::add_columns(t, {{"run", "", ColumnKind::integer},
                                  {"frame", "", ColumnKind::integer},
                                  {"theta", "deg", ColumnKind::real},
                                  {"i", "", ColumnKind::integer},
                                  {"j", "", ColumnKind::integer},
                                  {"critical", "", ColumnKind::integer},
                                  {"sliding", "", ColumnKind::integer},
                                  {"slip", "", ColumnKind::integer}});
  // NA, not 0, where the input says nothing (a flag absent for the whole frame)
  auto flag = [](const std::optional<std::vector<std::uint8_t>>& v, std::size_t q) {
    return v ? std::optional<double>((*v)[q]) : std::nullopt;
  };
  for (std::size_t run = 0; run < runs.size(); ++run)
    for (const FrameRecord& f : runs[run].frames) {
      if (!f.contacts)
        throw std::logic_error("critical_contacts: a frame read without its contacts");
      const FrameContacts& c = *f.contacts;
      for (std::size_t q = 0; q < c.i.size(); ++q) {
        t.column("run").add_int(static_cast<std::int64_t>(run));
        t.column("frame").add_int(f.frame);
        t.column("theta").add(f.theta);
        t.column("i").add_int(c.i[q]);
        t.column("j").add_int(c.j[q]);
        t.column("critical").add_int(c.critical[q]);
        t.column("sliding").add(flag(c.sliding, q));
        t.column("slip").add(flag(c.slip, q));
      }
    }
  return p;
}

}  // namespace cdpile::analysis
