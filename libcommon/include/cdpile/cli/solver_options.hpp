/// The engine's numerical settings as command-line options, shared by deposit and tilt-cd
/// so both tools name, document and check them alike (docs/method.md gives each default's
/// reason); the solver's bundle, as analysis_options.hpp is the analysis tools'.
#pragma once

#include "cdpile/cd/engine.hpp"
#include "cdpile/cli/command.hpp"

namespace cdpile::cli {

/// The "Solver" group: --time-step, --theta-method, --tolerance, --max-sweeps,
/// --criterion, --check-every, --solver, --stiffness, --scramble, --alert.
void declare_solver_options(Usage& u);

/// The settings from the options; `diameter` [m] converts the alert distance, and with
/// `mass` [kg/m] (the mean grain mass per unit thickness) the stiffness, m g / D -> N/m^2.
cd::Settings solver_settings(const Args& a, double diameter, double mass, double gravity);

}  // namespace cdpile::cli
