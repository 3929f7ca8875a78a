/// The warnings of a tilt run (docs/method.md, "Warnings"): its settings' before it starts,
/// its numbers' when it ends.
#pragma once

#include "cdpile/cd/engine.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace cdpile::sim {

/// The run-time warnings of a run (docs/method.md, "Warnings"): what tells a user that the
/// numbers of a run are not to be trusted as they stand. Each is one sentence without the
/// tool name; none when the run is sound.
///  - more than 1 % of the steps hit the sweep cap (forces not converged in those steps);
///  - the run's overlaps grew beyond 1e-3 D (the step lets grains move too far:
///    --time-step; with a stiffness, the compliance).
/// `steps` counts every step of the run, `unconverged` those at the cap,
/// `max_overlap_grown_m` the largest overlap beyond the pile's own at the start
/// (sim/overlap.hpp), `diameter_m` the mean diameter, `contact_stiffness` the settings' k
/// [N/m^2] (0: rigid contacts; with k > 0 an overlap is the contact's compliance),
/// `max_substeps` the settings' (the capped steps' warning names what converges them:
/// more sweeps for rigid contacts, sub-steps with a stiffness).
std::vector<std::string> run_warnings(std::int64_t steps, std::int64_t unconverged,
                                      double max_overlap_grown_m, double diameter_m,
                                      double contact_stiffness = 0.0, int max_substeps = 1);

/// The warnings a run's settings earn before it starts (docs/method.md, "Warnings"), from
/// the stability map (docs/performance.md, "Where the methods fail"); one sentence each,
/// none for sound settings:
///  - h sqrt(g/D) above 0.02 (the map's runs overlapped beyond 1e-3 D from 0.04 on);
///  - a tolerance of 1e-2 or looser (the map's runs overlapped or moved the avalanche).
/// `diameter_m` is the mean diameter.
std::vector<std::string> settings_warnings(const cd::Settings& s, double diameter_m);

}  // namespace cdpile::sim
