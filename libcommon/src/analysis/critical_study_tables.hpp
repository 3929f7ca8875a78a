// The seam inside critical_study (docs/analysis.md, "Definitions"): what its estimation
// (critical_study.cpp) hands to its product tables (critical_study_tables.cpp), and the
// functions that lay the product out and write its rows. Private to those two units.
#pragma once

#include "cdpile/analysis/critical_study.hpp"

#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

namespace cdpile::analysis::critical_parts {

inline constexpr double nan = std::numeric_limits<double>::quiet_NaN();

/// a / b, none when b <= 0.
std::optional<double> ratio(std::int64_t a, std::int64_t b);

// Whether a frame is static: its step converged (looked up in the run's steps), its grains
// at rest by the same rule and none in flight; empty when unknown.
std::optional<bool> static_frame(const RunRecord& r, const FrameRecord& f, const RestRule& rest);

// The fraction of a frame's contacts at rest that are critical (Nc_rest / N_rest); none
// when the frame does not count them or counts none.
std::optional<double> nu_at_rest(const FrameRecord& f);

// The nu(theta) series a run contributes to the ensemble and the envelope.
struct Curve {
  std::vector<double> theta, nu;
};

// A run's per-step fractions: nu from the recorded critical count (when it follows the
// rule asked for), nu_sliding, and the agitation Ek/(m g D).
struct StepFractions {
  bool have_nc = false;
  std::vector<double> nu_c, nu_s, ekn;
};

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

// One reading of nu(theta) over the runs (all states, or static states only): the ensemble
// mean on grid g, the envelope of maxima on windows w and its fit (Fig 1c).
struct Reading {
  std::vector<Summary> ens, env, env_at;
  std::vector<std::uint8_t> in_fit;  // per window
  std::vector<double> fit;           // per window, NaN where not fitted
  std::vector<std::size_t> windows_in_fit;
  bool saturates = false;
};

// --- the product's layout and rows (critical_study_tables.cpp) -------------------------

// The product's kind, its parameters and the notes that define its columns.
Product describe_study(const CriticalOptions& opt, SeriesSource src);

// The per-run tables and the ensemble's, in the product's order, with their columns.
struct StudyTables {
  Table& runs;
  Table* steps;  // only with CriticalOptions::step_table
  Table& frames;
  Table& events;
  Table& ensemble;
  Table& envelope;
};
StudyTables add_study_tables(Product& p, bool step_table);

// One row of the runs table.
void write_run_row(Table& t, const RunRecord& r, std::int64_t run, std::size_t events,
                   std::optional<double> theta_c, double nu_max);

// The run's steps, with their fractions and whether each is static (empty: unknown).
void write_step_rows(Table& t, const RunRecord& r, std::int64_t run, const StepFractions& q,
                     const std::vector<std::int64_t>& st_static);

// The run's frames, each classified as loading (at or below `cut`) and, as the estimation
// found, static or moving (frame_static, one per frame; docs/analysis.md, "Static and
// moving states").
void write_frame_rows(Table& t, const RunRecord& r, std::int64_t run, double cut,
                      const std::vector<std::optional<bool>>& frame_static);

// The run's rearrangement events (Fig 2), each with the state of the series just before;
// returns how many.
std::size_t write_events(Table& t, const RunRecord& r, std::int64_t run, const Curve& cv,
                         const std::vector<std::int64_t>& cv_step, const StepFractions& q,
                         double cut, const EventRule& rule);

// The ensemble means on grid g and the envelopes on windows w, of every state, the static
// ones and the contacts at rest, with the envelopes' fits.
void write_ensemble_rows(Table& t, const Grid& g, const Reading& all, const Reading& still,
                         const Reading& rest);
void write_envelope_rows(Table& t, const Grid& w, const Reading& all, const Reading& still,
                         const Reading& rest);

// Per window of the loading phase: the distribution of the mobilisation of the counted
// contacts, and the contacts that slip beside the critical ones (sliding is motion,
// critical is force).
void write_distributions(Product& p, const LoadingTotals& tot, const CriticalOptions& opt);

}  // namespace cdpile::analysis::critical_parts
