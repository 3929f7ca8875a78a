// The engine's numerical settings as command-line options, shared by deposit and tilt-cd
// so both tools name, document and check them alike (docs/method.md gives each default's
// reason).
#pragma once

#include "cdpile/cd/engine.hpp"
#include "cdpile/cli/command.hpp"

#include <unistd.h>

#include <cmath>
#include <string>

namespace cdpile::tools {

inline void declare_solver_options(cli::Usage& u) {
  const cd::Settings d;
  u.group("Solver");
  u.real("time-step", d.time_step, "time step h (h sqrt(g/D) = 0.0099 at D = 1 mm)", "s", 1e-12, 1.0);
  u.real("theta", d.theta, "theta-method parameter of the Moreau-Jean scheme", "", 0.5, 1.0);
  u.real("tolerance", d.tolerance, "NSGS convergence threshold of --criterion, relative to the velocity scale", "", 1e-15, 1.0);
  u.integer("max-sweeps", d.max_sweeps, "cap of NSGS sweeps per step (hitting it is counted and reported)", 1, 100000000);
  u.text("criterion", cd::criterion_name(d.criterion),
         "when NSGS stops: 'maxm', every contact's velocity correction <= tolerance; "
         "'quad', their root mean square <= tolerance; 'qm16', quad and every correction "
         "<= 16.66 tolerance (LMGC90's names; docs/method.md)",
         {"maxm", "quad", "qm16"});
  u.real("alert", 0.1, "alert distance: contact candidates within this gap", "D", 0.0, 10.0);
}

/// The settings from the options; `diameter` [m] converts the alert distance.
inline cd::Settings solver_settings(const cli::Args& a, double diameter) {
  cd::Settings s;
  s.time_step = a.real("time-step");
  s.theta = a.real("theta");
  s.tolerance = a.real("tolerance");
  s.max_sweeps = static_cast<int>(a.integer("max-sweeps"));
  s.criterion = cd::criterion_from_name(a.text("criterion"));
  s.alert_distance = a.real("alert") * diameter;
  return s;
}

/// Whether progress lines go to stderr: a terminal, and no --quiet.
inline bool progress_wanted(const cli::Args& a) { return !a.quiet() && isatty(STDERR_FILENO) != 0; }

}  // namespace cdpile::tools
