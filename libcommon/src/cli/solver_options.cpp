// The solver's options (solver_options.hpp; docs/method.md).
#include "cdpile/cli/solver_options.hpp"

#include <cstdint>
#include <limits>
#include <string>

namespace cdpile::cli {

cd::Settings tool_defaults() {
  cd::Settings d;
  d.solver = cd::SolverKind::pcg;
  d.tolerance = 1e-6;
  d.max_substeps = 64;
  d.substep_after = 1000;
  return d;
}

void declare_solver_options(Usage& u) {
  const cd::Settings d = tool_defaults();
  u.group("Solver");
  u.real("time-step", d.time_step, "time step h (h sqrt(g/D) = 0.0099 at D = 1 mm)", "s", 1e-12,
         1.0);
  u.real("theta-method", d.theta,
         "theta-method parameter of the Moreau-Jean scheme (theta, the tilt, is another)", "", 0.5,
         1.0);
  u.real("tolerance", d.tolerance,
         "NSGS convergence threshold of --criterion, relative to the velocity scale", "", 1e-15,
         1.0);
  u.integer("max-sweeps", d.max_sweeps,
            "cap of NSGS sweeps per step (hitting it is counted and reported)", 1, 100000000);
  u.text("criterion", cd::criterion_name(d.criterion),
         "when NSGS stops: 'maxm', every contact's velocity correction <= tolerance; "
         "'quad', their root mean square <= tolerance; 'qm16', quad and every correction "
         "<= 16.66 tolerance (LMGC90's names); 'law', the contact law's residual "
         "<= tolerance g h, whatever the solver; 'err', the error estimated from the largest "
         "correction and the measured contraction per sweep <= tolerance (docs/method.md)",
         {"maxm", "quad", "qm16", "law", "err"});
  u.integer("check-every", d.check_every,
            "sweeps between two tests of --criterion (LMGC90 tests every 50)", 1, 100000000);
  u.text("solver", cd::solver_name(d.solver),
         "contact solver: 'nsgs', non-smooth Gauss-Seidel; 'nncg', NSGS with a nonlinear "
         "conjugate-gradient step after each sweep; 'pcg', NSGS alternating with conjugate "
         "gradients on the contacts' active set, for compliant contacts; 'newton', NSGS "
         "alternating with exact Newton steps on the active set by a sparse LU, for compliant "
         "contacts (docs/method.md)",
         {"nsgs", "nncg", "pcg", "newton"});
  u.real("stiffness", default_stiffness_mg_D,
         "contact stiffness k of the force-selection rule, in m g / D (m the mean grain mass, "
         "D the mean diameter): the compliance 1/(k h^2) anchored at the previous step's "
         "impulses picks the step's forces near the previous ones; 0 for rigid contacts, "
         "with --tolerance 1e-4 --solver nsgs as the rigid studies (docs/method.md, "
         "\"Force selection\")",
         "m g/D", 0.0, 1e300);
  u.integer("max-substeps", d.max_substeps,
            "adaptive sub-steps: a step not converged after --substep-after sweeps is done again "
            "as two half steps under the same gravity, recursively, down to h / this (a power of "
            "two; 1: none) (docs/method.md, \"Sub-steps\")",
            1, cd::max_substeps_limit);
  u.integer("substep-after", d.substep_after,
            "sweeps a step may take before it is split into two (with --max-substeps > 1)", 1,
            100000000);
  u.integer("scramble", 0,
            "0: sweeps in pair order; else the seed of a random sweep order drawn anew every "
            "step (LMGC90's quick scramble): another solver path through the same steps",
            0, std::numeric_limits<std::int64_t>::max());
  u.text("sweep-order", cd::sweep_order_name(d.sweep_order),
         "the order of the sweeps: 'pair', the contacts in pair order (or --scramble's); "
         "'strips', the box cut into vertical strips two largest diameters wide or more, the "
         "even strips then the odd ones, which --threads share (docs/method.md, \"Threads\")",
         {"pair", "strips"});
  u.integer("threads", d.threads,
            "threads that share the strips of a sweep (with --sweep-order strips): the run is "
            "the same, bit for bit, on any number; not recorded, so a run resumes or branches "
            "on any (docs/method.md, \"Threads\")",
            1, cd::max_threads);
  u.real("alert", 0.1, "alert distance: contact candidates within this gap", "D", 0.0, 10.0);
  u.alias("theta", "theta-method");  // the old spelling, beside theta the tilt everywhere else
}

cd::Settings solver_settings(const Args& a, double diameter, double mass, double gravity) {
  cd::Settings s;
  s.time_step = a.real("time-step");
  s.theta = a.real("theta-method");
  s.tolerance = a.real("tolerance");
  s.max_sweeps = static_cast<int>(a.integer("max-sweeps"));
  s.criterion = cd::criterion_from_name(a.text("criterion"));
  s.alert_distance = a.real("alert") * diameter;
  s.check_every = static_cast<int>(a.integer("check-every"));
  s.solver = cd::solver_from_name(a.text("solver"));
  s.contact_stiffness = a.real("stiffness") * mass * gravity / diameter;
  s.scramble = static_cast<std::uint64_t>(a.integer("scramble"));
  s.max_substeps = static_cast<int>(a.integer("max-substeps"));
  if ((s.max_substeps & (s.max_substeps - 1)) != 0)
    throw UsageError("--max-substeps: expected a power of two in [1, " +
                     std::to_string(cd::max_substeps_limit) + "], got '" +
                     std::to_string(s.max_substeps) + "'");
  s.substep_after = static_cast<int>(a.integer("substep-after"));
  s.sweep_order = cd::sweep_order_from_name(a.text("sweep-order"));
  s.threads = static_cast<int>(a.integer("threads"));
  return s;
}

}  // namespace cdpile::cli
