/// Time series of a tilt run as a function of the tilt angle theta: rearrangement events
/// (Fig 2), averages on a common theta grid across runs (inset of Fig 1a), the envelope of
/// maxima (Fig 1c) and the avalanche angle theta_c.
///
/// Angles are in degrees, as in the paper. Every function takes plain arrays, so it works
/// on per-step observables and on per-frame values alike.
#pragma once

#include "cdpile/analysis/stats.hpp"

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace cdpile::analysis {

// ---------------------------------------------------------------------------------
// Rearrangement events (Fig 2)

/// How events are read from the contact count N(step).
///
/// An event runs from a local maximum of N to the next local minimum. Turning points are
/// confirmed only when N has moved back by at least `hysteresis` contacts, so a rise of
/// fewer contacts inside a drop does not split it. An event is kept if it loses at least
/// `min_drop` contacts.
struct EventRule {
  std::int64_t hysteresis = 1;  ///< contacts; 1 = plain local max to next local min
  std::int64_t min_drop = 1;    ///< contacts
};

struct Event {
  std::size_t peak = 0;    ///< index of the last sample at the maximum (the state "just before")
  std::size_t trough = 0;  ///< index of the first sample at the following minimum
  std::int64_t n_peak = 0, n_trough = 0;
  double loss = 0.0;  ///< Delta N / N = (n_peak - n_trough) / n_peak
  bool open = false;  ///< the series ended while N was still falling
};

/// Events of a contact-count series. Throws cdpile::Error on a bad rule.
std::vector<Event> rearrangements(std::span<const std::int64_t> n, const EventRule& rule);

// ---------------------------------------------------------------------------------
// A common theta grid

/// Bins [start + k step, start + (k+1) step), k = 0..count-1; a value exactly at the
/// upper end of the grid falls in the last bin.
struct Grid {
  double start = 0.0, step = 0.1;
  std::size_t count = 0;
  double lower(std::size_t k) const { return start + static_cast<double>(k) * step; }
  double upper(std::size_t k) const { return start + static_cast<double>(k + 1) * step; }
  double centre(std::size_t k) const { return start + (static_cast<double>(k) + 0.5) * step; }
  /// The bin holding x, or empty outside the grid.
  std::optional<std::size_t> bin(double x) const;
};

/// The grid of bins of width `step` from `start` that covers [start, stop].
Grid make_grid(double start, double stop, double step);

/// The mean of the values falling in each bin (empty bins are empty optionals).
std::vector<std::optional<double>> bin_mean(std::span<const double> theta,
                                            std::span<const double> value, const Grid& grid);
/// The maximum of the values in each bin (per-run envelope of Fig 1c); `at`, if given,
/// receives the theta where each maximum occurs (the first, if repeated).
std::vector<std::optional<double>> bin_max(std::span<const double> theta,
                                           std::span<const double> value, const Grid& grid,
                                           std::vector<std::optional<double>>* at = nullptr);

/// Across runs: per bin, the summary (n, mean, se) of the runs that have a value there.
std::vector<Summary> across_runs(const std::vector<std::vector<std::optional<double>>>& per_run,
                                 std::size_t bins);

// ---------------------------------------------------------------------------------
// The avalanche angle

/// The avalanche rule (docs/method.md, "Avalanche"), and its defaults, for every code that
/// applies it: the simulator as a run goes (sim::AvalancheDetector, tilt-cd's
/// --avalanche-ek and --avalanche-hold) and the analyses over a recorded series
/// (avalanche_index; critical and localnu). theta_c of a run is the first sample where the
/// agitation, the mean translational kinetic energy per grain in units of m g D (m the mean
/// grain mass), reaches `threshold` and stays at or above it for the next `hold` degrees of
/// tilt (or, over a recorded series, until the run ends).
struct AvalancheRule {
  double threshold = 1e-3;  ///< E_k / (m g D)
  double hold = 0.2;        ///< deg
};

/// The rule's test of one sample: the agitation is at or above the threshold. A NaN
/// agitation is not, so it breaks a sustained interval.
inline bool avalanche_agitated(double agitation, double threshold) {
  return agitation >= threshold;
}

/// Index of the sample at theta_c, or empty if the run never avalanches by the rule.
std::optional<std::size_t> avalanche_index(std::span<const double> theta,
                                           std::span<const double> energy,
                                           const AvalancheRule& rule);

}  // namespace cdpile::analysis
