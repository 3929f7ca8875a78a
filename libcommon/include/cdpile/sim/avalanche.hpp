/// The avalanche rule of the tilt protocol (docs/method.md, "Avalanche"): the first step
/// from which the agitation a = Ek per grain / (m g D) stays at or above a threshold for
/// a number of steps in a row. The rule and its defaults are analysis::AvalancheRule's,
/// and its test of a step analysis::avalanche_agitated, as the analyses apply it to a
/// recorded series; here it is decided as the run goes, the hold counted in steps at the
/// tilt rate (hold_steps), so the run can stop a margin after it.
#pragma once

#include "cdpile/analysis/series.hpp"

#include <cmath>
#include <cstdint>

namespace cdpile::sim {

/// Steps to turn by `deg` at `rate` degrees per step, rounded up (a tiny tolerance keeps
/// 2 / 0.001 at 2000 despite rounding).
inline std::int64_t steps_for(double deg, double rate) {
  return static_cast<std::int64_t>(std::ceil(deg / rate - 1e-9));
}

/// Fed every step's agitation; its whole state is checkpointed (sim/recorder.hpp), so a
/// resumed run confirms the avalanche at the same step as one never interrupted.
struct AvalancheDetector {
  double threshold = 0.0;
  std::int64_t hold = 1;
  std::int64_t since = -1;  ///< first step of the current run above the threshold
  double since_deg = 0.0;
  bool detected = false;
  double angle_deg = 0.0;  ///< tilt at `since` when confirmed
  std::int64_t start_step = -1, confirmed_step = -1;

  /// Step `step` at tilt `angle` [deg] had agitation `a`.
  void update(std::int64_t step, double angle, double a);
};

}  // namespace cdpile::sim
