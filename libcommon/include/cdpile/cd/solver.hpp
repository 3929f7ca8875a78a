/// The solver seam: what a contact solver is told (SolverSettings), what it reports
/// (SolveReport), and the interface every solver implements over the solver-neutral
/// ContactSystem (contact_system.hpp). docs/method.md, "Convergence" and "The residual".
#pragma once

#include "cdpile/cd/contact_system.hpp"
#include "cdpile/cd/schedule.hpp"

#include <cstdint>
#include <memory>
#include <string>

namespace cdpile::cd {

/// The solvers behind the seam.
enum class SolverKind {
  nsgs,  ///< non-smooth Gauss-Seidel with the exact 2D local solve (nsgs.hpp)
  nncg,  ///< NSGS with a nonlinear conjugate-gradient step after each sweep (nsgs.hpp)
  pcg,   ///< NSGS alternating with preconditioned conjugate gradients on the active set (pcg.hpp)
  newton,  ///< NSGS alternating with exact Newton steps on the active face (pcg.hpp)
  admm,  ///< ADMM on the step's factorised problem, then pcg from its impulses (admm.hpp)
};
const char* solver_name(SolverKind k);
/// The solver of a name; throws cdpile::UsageError on another name.
SolverKind solver_from_name(const std::string& name);

/// When the sweeps of a step stop (docs/method.md, "Convergence"). maxm, quad and qm16
/// measure the velocity corrections W_aa dR_a that a full sweep made, relative to the
/// velocity scale of SolveReport::residual; the names are LMGC90's. `law` bounds the
/// solver-independent residual of the contact law (LawResidual::max, relative to g h).
enum class Criterion {
  maxm,  ///< every contact's correction <= tolerance
  quad,  ///< root mean square of the corrections over the active contacts <= tolerance
  qm16,  ///< quad, and every correction <= 16.66 tolerance (LMGC90 'QM/16')
  law,   ///< LawResidual::max <= tolerance (any solver's iterate, measured alike)
  /// the estimated error: residual rho / (1 - rho) <= tolerance, rho the mean contraction
  /// per sweep over the last sweeps (SolveReport::contraction, err_window())
  err,
};
/// The criterion's name as on the command line and in files ("maxm", "quad", "qm16", "law",
/// "err").
const char* criterion_name(Criterion c);
/// The criterion of a name; throws cdpile::UsageError on another name.
Criterion criterion_from_name(const std::string& name);

/// LMGC90's 'QM/16' bound on the largest correction, in tolerances.
inline constexpr double qm16_max_factor = 16.66;

/// The most threads a solve takes (SolverSettings::threads).
inline constexpr int max_threads = 1024;
/// The most strips a sweep in strips is cut into (SolverSettings::strips).
inline constexpr int max_strips = 1000000;

/// How a step's contact system is solved; none of these changes the law being solved.
struct SolverSettings {
  SolverKind solver = SolverKind::nsgs;
  double tolerance = 1e-4;                ///< threshold of the criterion (see Criterion)
  int max_sweeps = 2000;                  ///< sweep cap per step; hitting it is reported
  bool symmetric_sweeps = true;           ///< alternate forward and backward sweeps
  Criterion criterion = Criterion::maxm;  ///< when the sweeps stop
  int check_every = 1;  ///< sweeps between two tests of the criterion (LMGC90: 50)
  /// 0: sweeps visit the rows in pair order. Otherwise the seed of a random order of the
  /// rows, drawn anew every step from (seed, step) (LMGC90's "quick scramble"): a solver
  /// path, for measuring how the forces of an indeterminate step depend on it.
  std::uint64_t scramble = 0;
  /// pcg only (pcg.hpp): the sweeps a step takes before the first gradient round, and the
  /// sweeps between two rounds. Neither changes the solution, only the path to it; the
  /// defaults are the fastest of those measured on the paper pile's rearrangement
  /// (docs/performance.md, "The pcg solver").
  int krylov_after = 20;
  int sweeps_between_rounds = 6;
  /// pcg only: the step's rounds before it has taken this many sweeps and iterations hold
  /// a sliding contact's friction on its cone as its normal impulse changes
  /// (R_t = s mu R_n), later ones hold its R_t. The first rounds of a step then go
  /// further before the projection stops them (a quarter fewer sweeps in the paper pile's
  /// quiet and loading windows); in a rearrangement such rounds, whose operator is not
  /// symmetric, cost more than they save (docs/performance.md, "Friction that follows the
  /// normal impulse in the first rounds"). The path only, not the solution.
  int following_until = 30;
  /// newton only (pcg.hpp, NewtonSolver): the sweeps and iterations a step takes with
  /// pcg's gradient rounds before its rounds become Newton steps. A Newton step costs
  /// a sparse LU (some 80 sweeps' worth at 4000 grains), so the quiet steps that pcg
  /// converges in fewer sweeps are left to it (docs/performance.md, "The newton solver").
  /// The path to the solution only, not the solution.
  int newton_after = 100;
  /// A step not converged after this many sweeps and iterations is handed to the
  /// active-set Newton on its problem (active_set.hpp; docs/method.md, "Finishing a step
  /// by its active set"), whose solution is kept only if it meets the law's residual; the
  /// solver then goes on from the impulses kept, to its criterion or its cap. 0: never.
  /// Unlike newton_after it changes which steps converge, so it is a parameter of a run.
  int finish_after = 0;
  /// The order of the sweeps (schedule.hpp; docs/method.md, "Threads"): pair order, or
  /// vertical strips of the box, which threads can share. The order changes the path to
  /// the solution, not the law; a run in strips gives the same numbers on any number of
  /// threads.
  SweepOrder sweep_order = SweepOrder::pair;
  /// The vertical strips of SweepOrder::strips (strip_count, schedule.hpp): this many, or
  /// as many as fit at least 4 r_max wide if fewer do; 0: as many as fit (the rule of the
  /// files made before this parameter). Fewer, wider strips carry a sweep's corrections
  /// across more of the pile (8 to 10 % fewer sweeps with 16 than with 50 on the paper's
  /// pile and with 200 at 16 000 grains in quiet windows; docs/performance.md, "Fewer,
  /// wider strips"); each thread needs a few strips of each parity. A parameter of the
  /// path, not of the law, recorded with the run.
  int strips = 16;
  /// Threads that share the strips of a sweep (docs/method.md, "Threads"): how fast,
  /// never what. Not a parameter of a run: a run resumes or branches on any number. More
  /// than 1 needs SweepOrder::strips (pair order is one thread's).
  int threads = 1;
};

/// The sweeps over which the 'err' criterion measures the contraction: two (a forward and
/// a backward sweep) for NSGS and NNCG; for pcg two cycles of sweeps and gradient rounds,
/// since the sweeps just after a round contract fast (the round took the slow modes) and
/// would promise a rate the next ones do not keep.
int err_window(const SolverSettings& s);

/// Checks a settings value range; throws cdpile::UsageError naming the bad field.
void validate(const SolverSettings& s);

/// What one solve did.
struct SolveReport {
  int sweeps = 0;  ///< sweeps done
  /// The largest velocity correction max_a |W_aa dR_a| made by the last sweep, divided by
  /// max(g h, mean W_nn R_n over active contacts). Zero when no contact.
  double residual = 0.0;
  /// The same corrections' root mean square over the active contacts (the larger
  /// component of each), divided by the same scale: the 'quad' measure.
  double residual_rms = 0.0;
  bool converged = true;  ///< the criterion was met before the sweep cap
  /// The step was finished by the active-set Newton (SolverSettings::finish_after).
  bool finished = false;

  /// Records the residual of a new sweep (`residual` and the history of the last ones).
  void add_sweep(double new_residual);
  /// The mean contraction per sweep of `residual` over the last `over` sweeps,
  /// (r_k / r_{k-over})^(1/over); negative until that many sweeps are recorded.
  double contraction(int over) const;

  /// The most sweeps contraction() looks back over.
  static constexpr int kHistory = 32;

 private:
  double history_[kHistory + 1] = {};  ///< residuals, a ring indexed by the sweep count
  int count_ = 0;                      ///< sweeps recorded
};

/// A contact solver: finds the impulses of a ContactSystem from the ones it holds (the
/// warm start), keeping body velocities equal to v_free + M^-1 H^T R on return.
class ContactSolver {
 public:
  virtual ~ContactSolver() = default;
  virtual SolverKind kind() const = 0;
  /// Solvers hold settings only, no state between steps: solve is const.
  /// `gravity_velocity` is g h [m/s], the floor of the velocity scale of the measures.
  virtual SolveReport solve(ContactSystem& system, double gravity_velocity) const = 0;
};

/// The solver the settings name (validated).
std::shared_ptr<const ContactSolver> make_solver(const SolverSettings& s);

}  // namespace cdpile::cd
