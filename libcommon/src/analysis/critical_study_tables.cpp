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

// Each table below is one list of columns (ColumnSpec, table.hpp): name, unit, kind and the
// cell a row gives. A row type holds what its getters read.

using K = ColumnKind;

std::optional<double> count(const std::optional<std::int64_t>& v) {
  return v ? std::optional<double>(static_cast<double>(*v)) : std::nullopt;
}

std::int64_t size(std::size_t n) { return static_cast<std::int64_t>(n); }

// --- runs: one row per run
struct RunRow {
  const RunRecord& r;
  std::int64_t run;
  std::size_t events;
  std::optional<double> theta_c;
  double nu_max;
};
const ColumnSpec<RunRow> run_columns[] = {
    {"run", "", K::integer, [](const RunRow& x) -> Cell { return x.run; }},
    {"name", "", K::text, [](const RunRow& x) -> Cell { return x.r.name; }},
    {"grains", "", K::integer, [](const RunRow& x) -> Cell { return x.r.free_grains; }},
    {"diameter", "m", K::real, [](const RunRow& x) -> Cell { return x.r.diameter; }},
    {"steps", "", K::integer, [](const RunRow& x) -> Cell { return size(x.r.steps.step.size()); }},
    {"frames", "", K::integer, [](const RunRow& x) -> Cell { return size(x.r.frames.size()); }},
    {"events", "", K::integer, [](const RunRow& x) -> Cell { return size(x.events); }},
    {"theta_c", "deg", K::real, [](const RunRow& x) -> Cell { return x.theta_c; }},
    {"theta_c_recorded", "deg", K::real,
     [](const RunRow& x) -> Cell { return x.r.recorded_avalanche; }},
    {"nu_max", "", K::real, [](const RunRow& x) -> Cell { return x.nu_max; }},
};

// --- steps: one row per time step of a run
struct StepRow {
  const RunRecord& r;
  const StepFractions& q;
  const std::vector<std::int64_t>& st_static;  // empty: unknown
  std::int64_t run;
  std::size_t k;
  std::optional<double> z_all() const { return ratio(2 * r.steps.contacts[k], r.free_grains); }
};
const ColumnSpec<StepRow> step_columns[] = {
    {"run", "", K::integer, [](const StepRow& x) -> Cell { return x.run; }},
    {"step", "", K::integer, [](const StepRow& x) -> Cell { return x.r.steps.step[x.k]; }},
    {"theta", "deg", K::real, [](const StepRow& x) -> Cell { return x.r.steps.theta[x.k]; }},
    {"N", "", K::integer, [](const StepRow& x) -> Cell { return x.r.steps.contacts[x.k]; }},
    {"Nc", "", K::integer,
     [](const StepRow& x) -> Cell {
       return x.q.have_nc ? static_cast<double>(x.r.steps.critical[x.k]) : nan;
     }},
    {"nu", "", K::real, [](const StepRow& x) -> Cell { return x.q.nu_c[x.k]; }},
    {"sliding", "", K::integer,
     [](const StepRow& x) -> Cell {
       return x.r.steps.sliding.empty() ? nan : static_cast<double>(x.r.steps.sliding[x.k]);
     }},
    {"nu_sliding", "", K::real, [](const StepRow& x) -> Cell { return x.q.nu_s[x.k]; }},
    {"z_all", "", K::real, [](const StepRow& x) -> Cell { return x.z_all(); }},
    {"lambda", "D", K::real,
     [](const StepRow& x) -> Cell {
       const auto z = x.z_all();
       return z && std::isfinite(x.q.nu_c[x.k]) ? critical_spacing(*z, x.q.nu_c[x.k], 1.0)
                                                : std::nullopt;
     }},
    {"Ek", "J m-1", K::real,
     [](const StepRow& x) -> Cell {
       const RunSteps& s = x.r.steps;
       return !s.kinetic_energy.empty() && x.r.free_grains > 0
                  ? s.kinetic_energy[x.k] / static_cast<double>(x.r.free_grains)
                  : nan;
     }},
    {"ek_norm", "", K::real, [](const StepRow& x) -> Cell { return x.q.ekn[x.k]; }},
    {"static", "", K::integer,
     [](const StepRow& x) -> Cell {
       return x.st_static.empty() ? nan : static_cast<double>(x.st_static[x.k]);
     }},
};

// --- frames: one row per saved frame of a run
struct FrameRow {
  const RunRecord& r;
  const FrameRecord& f;
  std::int64_t run;
  bool loading;
  std::optional<bool> still;
  double scale() const { return r.mean_mass * r.gravity * r.diameter; }  // m g D
  double v_scale() const { return std::sqrt(r.gravity * r.diameter); }
  // McNamara & Herrmann 2004 (docs/analysis.md, "Static bound")
  template <class Get>
  std::optional<double> bound(Get get) const {
    return f.bound ? std::optional<double>(static_cast<double>(get(*f.bound))) : std::nullopt;
  }
  // whether the frame's step converged; NA when the run does not say
  std::optional<double> converged() const {
    const RunSteps& s = r.steps;
    const auto it = std::lower_bound(s.step.begin(), s.step.end(), f.step);
    if (it == s.step.end() || *it != f.step || s.converged.size() != s.step.size())
      return std::nullopt;
    return static_cast<double>(s.converged[static_cast<std::size_t>(it - s.step.begin())]);
  }
};
const ColumnSpec<FrameRow> frame_columns[] = {
    {"run", "", K::integer, [](const FrameRow& x) -> Cell { return x.run; }},
    {"frame", "", K::integer, [](const FrameRow& x) -> Cell { return x.f.frame; }},
    {"step", "", K::integer, [](const FrameRow& x) -> Cell { return x.f.step; }},
    {"theta", "deg", K::real, [](const FrameRow& x) -> Cell { return x.f.theta; }},
    {"N", "", K::integer, [](const FrameRow& x) -> Cell { return x.f.state.contacts; }},
    {"Nc", "", K::integer, [](const FrameRow& x) -> Cell { return x.f.state.critical; }},
    {"nu", "", K::real, [](const FrameRow& x) -> Cell { return x.f.state.nu; }},
    {"sliding", "", K::integer, [](const FrameRow& x) -> Cell { return x.f.state.sliding; }},
    {"nu_sliding", "", K::real, [](const FrameRow& x) -> Cell { return x.f.state.nu_sliding; }},
    {"z", "", K::real, [](const FrameRow& x) -> Cell { return x.f.state.z; }},
    {"z_all", "", K::real, [](const FrameRow& x) -> Cell { return x.f.state.z_all; }},
    {"loaded_grains", "", K::integer,
     [](const FrameRow& x) -> Cell { return x.f.state.loaded_grains; }},
    {"lambda", "D", K::real,
     [](const FrameRow& x) -> Cell {
       return x.f.state.lambda && x.r.diameter > 0
                  ? std::optional<double>(*x.f.state.lambda / x.r.diameter)
                  : std::nullopt;
     }},
    {"Ek", "J m-1", K::real, [](const FrameRow& x) -> Cell { return x.f.kinetic_energy; }},
    {"ek_norm", "", K::real,
     [](const FrameRow& x) -> Cell {
       return x.f.kinetic_energy && x.scale() > 0.0
                  ? std::optional<double>(*x.f.kinetic_energy / x.scale())
                  : std::nullopt;
     }},
    {"loading", "", K::integer, [](const FrameRow& x) -> Cell { return std::int64_t{x.loading}; }},
    {"contacts_load_bearing", "", K::integer,
     [](const FrameRow& x) -> Cell {
       return x.bound([](const StaticBound& b) { return b.contacts; });
     }},
    {"grains_load_bearing", "", K::integer,
     [](const FrameRow& x) -> Cell {
       return x.bound([](const StaticBound& b) { return b.grains; });
     }},
    {"critical_load_bearing", "", K::integer,
     [](const FrameRow& x) -> Cell {
       return x.bound([](const StaticBound& b) { return b.critical; });
     }},
    {"static_bound", "", K::integer,
     [](const FrameRow& x) -> Cell {
       return x.bound([](const StaticBound& b) { return b.bound(); });
     }},
    {"above_static_bound", "", K::integer,
     [](const FrameRow& x) -> Cell {
       return x.bound([](const StaticBound& b) { return std::int64_t{b.above()}; });
     }},
    {"agitation_norm", "", K::real,
     [](const FrameRow& x) -> Cell {
       return x.f.agitation && x.scale() > 0.0 ? std::optional<double>(*x.f.agitation / x.scale())
                                               : std::nullopt;
     }},
    {"max_speed_norm", "", K::real,
     [](const FrameRow& x) -> Cell {
       return x.f.max_speed && x.v_scale() > 0.0
                  ? std::optional<double>(*x.f.max_speed / x.v_scale())
                  : std::nullopt;
     }},
    {"grains_without_contact", "", K::integer,
     [](const FrameRow& x) -> Cell { return x.f.grains_without_contact; }},
    {"converged", "", K::integer, [](const FrameRow& x) -> Cell { return x.converged(); }},
    // static or moving (docs/analysis.md, "Static and moving states")
    {"static", "", K::integer,
     [](const FrameRow& x) -> Cell {
       return x.still ? std::optional<double>(*x.still ? 1.0 : 0.0) : std::nullopt;
     }},
    {"slipping", "", K::integer, [](const FrameRow& x) -> Cell { return count(x.f.slipping); }},
    {"critical_slipping", "", K::integer,
     [](const FrameRow& x) -> Cell { return count(x.f.critical_slipping); }},
    {"z_paper", "", K::real, [](const FrameRow& x) -> Cell { return x.f.z_paper; }},
    {"N_rest", "", K::integer,
     [](const FrameRow& x) -> Cell { return count(x.f.contacts_at_rest); }},
    {"Nc_rest", "", K::integer,
     [](const FrameRow& x) -> Cell { return count(x.f.critical_at_rest); }},
    {"nu_rest", "", K::real, [](const FrameRow& x) -> Cell { return nu_at_rest(x.f); }},
};

// --- events: one row per rearrangement event of a run (Fig 2)
struct EventRow {
  const RunSteps& s;
  const StepFractions& q;
  const Event& e;
  std::int64_t run, index;
  std::optional<double> nu_before, nu_before_step;  // the series just before the peak
  double cut;
};
const ColumnSpec<EventRow> event_columns[] = {
    {"run", "", K::integer, [](const EventRow& x) -> Cell { return x.run; }},
    {"event", "", K::integer, [](const EventRow& x) -> Cell { return x.index; }},
    {"peak_step", "", K::integer, [](const EventRow& x) -> Cell { return x.s.step[x.e.peak]; }},
    {"trough_step", "", K::integer, [](const EventRow& x) -> Cell { return x.s.step[x.e.trough]; }},
    {"theta", "deg", K::real, [](const EventRow& x) -> Cell { return x.s.theta[x.e.peak]; }},
    {"theta_end", "deg", K::real, [](const EventRow& x) -> Cell { return x.s.theta[x.e.trough]; }},
    {"n_peak", "", K::integer, [](const EventRow& x) -> Cell { return x.e.n_peak; }},
    {"n_trough", "", K::integer, [](const EventRow& x) -> Cell { return x.e.n_trough; }},
    {"loss", "", K::real, [](const EventRow& x) -> Cell { return x.e.loss; }},
    {"nu_before", "", K::real, [](const EventRow& x) -> Cell { return x.nu_before; }},
    {"nu_before_step", "", K::integer, [](const EventRow& x) -> Cell { return x.nu_before_step; }},
    {"nu_sliding_before", "", K::real,
     [](const EventRow& x) -> Cell { return x.q.nu_s.empty() ? nan : x.q.nu_s[x.e.peak]; }},
    {"open", "", K::integer, [](const EventRow& x) -> Cell { return std::int64_t{x.e.open}; }},
    {"after_avalanche", "", K::integer,
     [](const EventRow& x) -> Cell { return std::int64_t{x.s.theta[x.e.peak] > x.cut}; }},
};

// --- ensemble and envelope: one row per bin of the grid, or window, that a run reaches
struct BinRow {
  const Grid& g;
  std::size_t b;
  const Reading &all, &still, &rest;
};
const ColumnSpec<BinRow> ensemble_columns[] = {
    {"theta", "deg", K::real, [](const BinRow& x) -> Cell { return x.g.centre(x.b); }},
    {"theta_lo", "deg", K::real, [](const BinRow& x) -> Cell { return x.g.lower(x.b); }},
    {"theta_hi", "deg", K::real, [](const BinRow& x) -> Cell { return x.g.upper(x.b); }},
    {"runs", "", K::integer, [](const BinRow& x) -> Cell { return x.all.ens[x.b].n; }},
    {"nu", "", K::real, [](const BinRow& x) -> Cell { return x.all.ens[x.b].mean; }},
    {"nu_se", "", K::real, [](const BinRow& x) -> Cell { return x.all.ens[x.b].se; }},
    {"runs_static", "", K::integer, [](const BinRow& x) -> Cell { return x.still.ens[x.b].n; }},
    {"nu_static", "", K::real, [](const BinRow& x) -> Cell { return x.still.ens[x.b].mean; }},
    {"nu_static_se", "", K::real, [](const BinRow& x) -> Cell { return x.still.ens[x.b].se; }},
    {"runs_rest", "", K::integer, [](const BinRow& x) -> Cell { return x.rest.ens[x.b].n; }},
    {"nu_rest", "", K::real, [](const BinRow& x) -> Cell { return x.rest.ens[x.b].mean; }},
    {"nu_rest_se", "", K::real, [](const BinRow& x) -> Cell { return x.rest.ens[x.b].se; }},
};
// where a reading's maxima occur, on average over runs; none where no run has one
std::optional<double> maxima_at(const Reading& rd, std::size_t b) {
  return rd.env[b].n ? rd.env_at[b].mean : std::nullopt;
}
const ColumnSpec<BinRow> envelope_columns[] = {
    {"theta", "deg", K::real,
     [](const BinRow& x) -> Cell { return x.all.env_at[x.b].mean.value_or(x.g.centre(x.b)); }},
    {"theta_lo", "deg", K::real, [](const BinRow& x) -> Cell { return x.g.lower(x.b); }},
    {"theta_hi", "deg", K::real, [](const BinRow& x) -> Cell { return x.g.upper(x.b); }},
    {"runs", "", K::integer, [](const BinRow& x) -> Cell { return x.all.env[x.b].n; }},
    {"envelope", "", K::real, [](const BinRow& x) -> Cell { return x.all.env[x.b].mean; }},
    {"envelope_se", "", K::real, [](const BinRow& x) -> Cell { return x.all.env[x.b].se; }},
    {"fit", "", K::real, [](const BinRow& x) -> Cell { return x.all.fit[x.b]; }},
    {"in_fit", "", K::integer,
     [](const BinRow& x) -> Cell { return std::int64_t{x.all.in_fit[x.b]}; }},
    {"theta_static", "deg", K::real,
     [](const BinRow& x) -> Cell { return maxima_at(x.still, x.b); }},
    {"runs_static", "", K::integer, [](const BinRow& x) -> Cell { return x.still.env[x.b].n; }},
    {"envelope_static", "", K::real, [](const BinRow& x) -> Cell { return x.still.env[x.b].mean; }},
    {"envelope_static_se", "", K::real,
     [](const BinRow& x) -> Cell { return x.still.env[x.b].se; }},
    {"fit_static", "", K::real, [](const BinRow& x) -> Cell { return x.still.fit[x.b]; }},
    {"in_fit_static", "", K::integer,
     [](const BinRow& x) -> Cell { return std::int64_t{x.still.in_fit[x.b]}; }},
    {"theta_rest", "deg", K::real, [](const BinRow& x) -> Cell { return maxima_at(x.rest, x.b); }},
    {"runs_rest", "", K::integer, [](const BinRow& x) -> Cell { return x.rest.env[x.b].n; }},
    {"envelope_rest", "", K::real, [](const BinRow& x) -> Cell { return x.rest.env[x.b].mean; }},
    {"envelope_rest_se", "", K::real, [](const BinRow& x) -> Cell { return x.rest.env[x.b].se; }},
    {"fit_rest", "", K::real, [](const BinRow& x) -> Cell { return x.rest.fit[x.b]; }},
    {"in_fit_rest", "", K::integer,
     [](const BinRow& x) -> Cell { return std::int64_t{x.rest.in_fit[x.b]}; }},
};

// --- windows and mobilisation: per tilt window of the loading phase, pooled over runs
double fraction(std::int64_t x, std::int64_t n) {
  return n > 0 ? static_cast<double>(x) / static_cast<double>(n) : nan;
}
struct WindowRow {
  double lo, hi;
  const WindowCounts &all, &still;
};
const ColumnSpec<WindowRow> window_columns[] = {
    {"theta_lo", "deg", K::real, [](const WindowRow& x) -> Cell { return x.lo; }},
    {"theta_hi", "deg", K::real, [](const WindowRow& x) -> Cell { return x.hi; }},
    {"frames", "", K::integer, [](const WindowRow& x) -> Cell { return x.all.frames; }},
    {"frames_static", "", K::integer, [](const WindowRow& x) -> Cell { return x.still.frames; }},
    {"nu", "", K::real,
     [](const WindowRow& x) -> Cell { return fraction(x.all.critical, x.all.contacts); }},
    {"nu_static", "", K::real,
     [](const WindowRow& x) -> Cell { return fraction(x.still.critical, x.still.contacts); }},
    {"nu_slipping", "", K::real,
     [](const WindowRow& x) -> Cell { return fraction(x.all.slipping, x.all.contacts); }},
    {"nu_slipping_static", "", K::real,
     [](const WindowRow& x) -> Cell { return fraction(x.still.slipping, x.still.contacts); }},
    {"critical_slipping_fraction", "", K::real,
     [](const WindowRow& x) -> Cell { return fraction(x.all.critical_slipping, x.all.critical); }},
    {"critical_slipping_fraction_static", "", K::real,
     [](const WindowRow& x) -> Cell {
       return fraction(x.still.critical_slipping, x.still.critical);
     }},
};
constexpr double bin_width = 1.0 / static_cast<double>(mobilisation_bins);
struct MobilisationRow {
  const WindowRow& w;
  std::size_t b;
  std::int64_t total, total_static;  // counted contacts of the window, all and static
};
const ColumnSpec<MobilisationRow> mobilisation_columns[] = {
    {"theta_lo", "deg", K::real, [](const MobilisationRow& x) -> Cell { return x.w.lo; }},
    {"theta_hi", "deg", K::real, [](const MobilisationRow& x) -> Cell { return x.w.hi; }},
    {"m_lo", "", K::real,
     [](const MobilisationRow& x) -> Cell { return static_cast<double>(x.b) * bin_width; }},
    {"m_hi", "", K::real,
     [](const MobilisationRow& x) -> Cell { return static_cast<double>(x.b + 1) * bin_width; }},
    {"contacts", "", K::integer,
     [](const MobilisationRow& x) -> Cell { return x.w.all.mobilisation[x.b]; }},
    {"pdf", "", K::real,
     [](const MobilisationRow& x) -> Cell {
       return fraction(x.w.all.mobilisation[x.b], x.total) / bin_width;
     }},
    {"contacts_static", "", K::integer,
     [](const MobilisationRow& x) -> Cell { return x.w.still.mobilisation[x.b]; }},
    {"pdf_static", "", K::real,
     [](const MobilisationRow& x) -> Cell {
       return fraction(x.w.still.mobilisation[x.b], x.total_static) / bin_width;
     }},
};

// --- critical --contacts: one row per counted contact of a frame
struct ContactRow {
  std::int64_t run;
  const FrameRecord& f;
  std::size_t q;
  // NA, not 0, where the input says nothing (a flag absent for the whole frame)
  std::optional<double> flag(const std::optional<std::vector<std::uint8_t>>& v) const {
    return v ? std::optional<double>((*v)[q]) : std::nullopt;
  }
};
const ColumnSpec<ContactRow> contact_columns[] = {
    {"run", "", K::integer, [](const ContactRow& x) -> Cell { return x.run; }},
    {"frame", "", K::integer, [](const ContactRow& x) -> Cell { return x.f.frame; }},
    {"theta", "deg", K::real, [](const ContactRow& x) -> Cell { return x.f.theta; }},
    {"i", "", K::integer,
     [](const ContactRow& x) -> Cell { return std::int64_t{x.f.contacts->i[x.q]}; }},
    {"j", "", K::integer,
     [](const ContactRow& x) -> Cell { return std::int64_t{x.f.contacts->j[x.q]}; }},
    {"critical", "", K::integer,
     [](const ContactRow& x) -> Cell { return std::int64_t{x.f.contacts->critical[x.q]}; }},
    {"sliding", "", K::integer,
     [](const ContactRow& x) -> Cell { return x.flag(x.f.contacts->sliding); }},
    {"slip", "", K::integer,
     [](const ContactRow& x) -> Cell { return x.flag(x.f.contacts->slip); }},
};

}  // namespace

StudyTables add_study_tables(Product& p, bool step_table) {
  StudyTables t{
      declare_columns(p.add_table("runs", "one row per run"), run_columns),
      step_table ? &declare_columns(p.add_table("steps", "one row per time step of each run"),
                                    step_columns)
                 : nullptr,
      declare_columns(p.add_table("frames", "one row per saved frame of each run"), frame_columns),
      declare_columns(p.add_table("events", "rearrangement events: a drop of the contact count N"),
                      event_columns),
      declare_columns(
          p.add_table("ensemble", "nu(theta) averaged over runs on a common theta grid"),
          ensemble_columns),
      declare_columns(
          p.add_table("envelope", "mean over runs of the maximum of nu in theta windows"),
          envelope_columns)};
  return t;
}

void write_run_row(Table& t, const RunRecord& r, std::int64_t run, std::size_t events,
                   std::optional<double> theta_c, double nu_max) {
  add_row(t, run_columns, RunRow{r, run, events, theta_c, nu_max});
}

void write_step_rows(Table& t, const RunRecord& r, std::int64_t run, const StepFractions& q,
                     const std::vector<std::int64_t>& st_static) {
  for (std::size_t k = 0; k < r.steps.step.size(); ++k)
    add_row(t, step_columns, StepRow{r, q, st_static, run, k});
}

void write_frame_rows(Table& t, const RunRecord& r, std::int64_t run, double cut,
                      const std::vector<std::optional<bool>>& frame_static) {
  for (std::size_t k = 0; k < r.frames.size(); ++k)
    add_row(t, frame_columns,
            FrameRow{r, r.frames[k], run, r.frames[k].theta <= cut, frame_static[k]});
}

std::size_t write_events(Table& t, const RunRecord& r, std::int64_t run, const Curve& cv,
                         const std::vector<std::int64_t>& cv_step, const StepFractions& q,
                         double cut, const EventRule& rule) {
  const RunSteps& s = r.steps;
  const auto events = rearrangements(s.contacts, rule);
  std::int64_t index = 0;
  for (const Event& e : events) {
    // the state just before: the last sample of the series at or before the peak step
    EventRow row{s, q, e, run, index++, std::nullopt, std::nullopt, cut};
    auto it = std::upper_bound(cv_step.begin(), cv_step.end(), s.step[e.peak]);
    if (it != cv_step.begin()) {
      const auto k = static_cast<std::size_t>(it - cv_step.begin() - 1);
      row.nu_before = cv.nu[k];
      row.nu_before_step = static_cast<double>(cv_step[k]);
    }
    add_row(t, event_columns, row);
  }
  return events.size();
}

void write_ensemble_rows(Table& t, const Grid& g, const Reading& all, const Reading& still,
                         const Reading& rest) {
  for (std::size_t b = 0; b < g.count; ++b)
    if (all.ens[b].n > 0) add_row(t, ensemble_columns, BinRow{g, b, all, still, rest});
}

void write_envelope_rows(Table& t, const Grid& w, const Reading& all, const Reading& still,
                         const Reading& rest) {
  for (std::size_t b = 0; b < w.count; ++b)
    if (all.env[b].n > 0) add_row(t, envelope_columns, BinRow{w, b, all, still, rest});
}

void write_distributions(Product& p, const LoadingTotals& tot, const CriticalOptions& opt) {
  Table& mob_t = declare_columns(p.add_table("mobilisation",
                                             "P(|f_t|/(mu f_n)) of the counted contacts per tilt "
                                             "window, loading frames (all and static)"),
                                 mobilisation_columns);
  Table& win_t =
      declare_columns(p.add_table("windows",
                                  "per tilt window, loading frames pooled over runs: "
                                  "critical and slipping contacts, all frames and static ones"),
                      window_columns);
  for (std::size_t wi = 0; wi < tot.win_all.size(); ++wi) {
    if (tot.win_all[wi].frames == 0) continue;
    const double lo = static_cast<double>(wi) * opt.mobilisation_window;
    const WindowRow w{lo, lo + opt.mobilisation_window, tot.win_all[wi], tot.win_static[wi]};
    add_row(win_t, window_columns, w);
    std::int64_t total = 0, total_static = 0;
    for (std::size_t b = 0; b < mobilisation_bins; ++b) {
      total += w.all.mobilisation[b];
      total_static += w.still.mobilisation[b];
    }
    for (std::size_t b = 0; b < mobilisation_bins; ++b)
      add_row(mob_t, mobilisation_columns, MobilisationRow{w, b, total, total_static});
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
  Table& t = declare_columns(p.add_table("contacts", "one row per counted contact of a frame"),
                             critical_parts::contact_columns);
  for (std::size_t run = 0; run < runs.size(); ++run)
    for (const FrameRecord& f : runs[run].frames) {
      if (!f.contacts)
        throw std::logic_error("critical_contacts: a frame read without its contacts");
      for (std::size_t q = 0; q < f.contacts->i.size(); ++q)
        add_row(t, critical_parts::contact_columns,
                critical_parts::ContactRow{static_cast<std::int64_t>(run), f, q});
    }
  return p;
}

}  // namespace cdpile::analysis
