/// The engine's numerical settings as command-line options, shared by deposit and tilt-cd
/// so both tools name, document and check them alike (docs/method.md gives each default's
/// reason); the solver's bundle, as analysis_options.hpp is the analysis tools'.
#pragma once

#include "cdpile/cd/engine.hpp"
#include "cdpile/cli/command.hpp"

namespace cdpile::cli {

/// The tools' contact stiffness by default, in m g / D (docs/method.md, "Defaults and their
/// reasons"): compliant contacts, whose steps converge; --stiffness 0 gives rigid ones.
inline constexpr double default_stiffness_mg_D = 1e6;

/// The engine's settings the tools start from: the library's (cd::Settings), with the
/// solver that converges the compliant steps (pcg), the tolerance at which their critical
/// contacts converge (1e-6), and sub-steps that rescue the rare step pcg leaves
/// unconverged after 1000 sweeps (docs/method.md, "Defaults and their reasons").
cd::Settings tool_defaults();

/// The "Solver" group: --time-step, --theta-method, --tolerance, --max-sweeps,
/// --criterion, --check-every, --solver, --stiffness, --scramble, --alert.
void declare_solver_options(Usage& u);

/// The settings from the options; `diameter` [m] converts the alert distance, and with
/// `mass` [kg/m] (the mean grain mass per unit thickness) the stiffness, m g / D -> N/m^2.
cd::Settings solver_settings(const Args& a, double diameter, double mass, double gravity);

}  // namespace cdpile::cli
