/// The factorised solver (docs/method.md, "The factorised solver"): ADMM on the step's
/// contact problem, in the style of Carpentier, Le Lidec and Montaut ("From compliant to
/// rigid contact simulation: a unified and efficient approach", RSS 2024).
///
/// The step's problem in Delassus form (delassus.hpp): G = W + C (C the compliance
/// 1/(k h^2) on the diagonal, zero for rigid contacts), q the free local velocities with
/// the gap term and -C R0. Find R in K (the product of the 2D Coulomb cones
/// |R_t| <= mu R_n) with the De Saxce velocity u~ = u + (mu |u_t|, 0), u = G R + q, in
/// the dual cone K* and orthogonal to R: Signorini and Coulomb's law, exact (not the
/// associated flow). ADMM splits R into x (unconstrained) and z (in K) with a dual v, a
/// velocity, and the metric D = diag(d_a), d_a the mean of the contact's diagonal block
/// (one scalar per contact, so the metric keeps each cone round):
///
///     s   = (mu |v_t|, 0)                                De Saxce's shift, every iteration
///     x   = (G + rho D)^-1 (rho D z - q - s + v)        one back-solve
///     x  <- alpha x + (1 - alpha) z                      over-relaxation (AdmmOptions)
///     z'  = Proj_K(x - D^-1 v / rho)                     per contact
///     v'  = v + rho D (z' - x)
///
/// At a fixed point x = z, v = G z + q + s = u~ and z = Proj_K(z - D^-1 u~ / rho), which is
/// the law. The shift is taken at the dual velocity v, as Pinocchio's solver takes it; at
/// the impulses' own velocity G z + q the iteration stalled (docs/performance.md, "A
/// factorised solver"). One sparse Cholesky factor (Eigen's SimplicialLDLT) of G + rho D
/// serves every iteration while rho is kept; rho is rebalanced by the ratio of the primal
/// residual D |x - z'| to the dual one rho D |z' - z| and the factor redone when it moves
/// by more than a factor `refactor_ratio`. G + rho D is positive definite even where G is
/// singular (rigid contacts in a hyperstatic network), so every x step is well posed; the
/// proximal term does not make a rigid step's answer unique: the iteration returns the
/// admissible impulses its path from the start reaches (the previous step's impulses,
/// docs/method.md "The factorised solver").
#pragma once

#include "cdpile/cd/delassus.hpp"
#include "cdpile/cd/solver.hpp"

#include <Eigen/Core>

#include <functional>

namespace cdpile::cd {

/// When and how ADMM on a Delassus problem stops and adapts.
struct AdmmOptions {
  /// The law's residual at which the iteration stops (admm_law_residual), relative to
  /// the velocity scale of the engine's maxm measure.
  double tolerance = 1e-6;
  /// The floor of that velocity scale, g h [m/s] (SolveReport::residual).
  double velocity_floor = 1.0;
  int max_iterations = 2000;
  /// The smallest compliance on G's diagonal (0: rigid contacts): with the largest
  /// eigenvalue of D^-1/2 G D^-1/2 it sets the first rho, sqrt(lambda_min lambda_max).
  double compliance = 0.0;
  /// Iterations between two rebalancings of rho (Chrono's ChSolverADMM: 5).
  int rebalance_every = 10;
  /// rho is changed, and G + rho D factorised again, only when the balance asks for a
  /// change by more than this factor.
  double refactor_ratio = 5.0;
  /// Over-relaxation of the x step (x <- alpha x + (1 - alpha) z; 1: none).
  double relaxation = 1.8;
  /// The first rho relative to D; 0: sqrt(lambda_min lambda_max) as above.
  double rho = 0.0;
  /// Polled every iteration (may be empty): true abandons the solve with StepCancelled.
  std::function<bool()> cancel;
  /// Called after every iteration (may be empty) with the iteration, the law's residual,
  /// the primal and dual residuals (velocities, D |x - z| and rho D |z - z_before|, their
  /// largest components) and rho: for measuring, not for the solve.
  std::function<void(int, double, double, double, double)> on_iteration;
};

/// What a solve did.
struct AdmmReport {
  int iterations = 0;      ///< back-solves
  int factorisations = 0;  ///< numeric factorisations of G + rho D
  double residual = 0.0;   ///< admm_law_residual of the impulses returned
  double rho = 0.0;        ///< the last rho, relative to D
  bool converged = false;
};

/// The law's residual of impulses r in a Delassus problem, measured as the engine's maxm
/// measures a sweep (nsgs.hpp, measure_sweep): for each contact the velocity correction
/// max(|G_nn ds_n|, |G_tt ds_t|) that its exact local solve (the others frozen) would make,
/// the largest, divided by max(velocity_floor, mean G_nn R_n over the contacts with
/// R_n > 0). The same numbers as law_residual (solver.hpp) with the engine's scale.
double admm_law_residual(const DelassusProblem& p, const Eigen::VectorXd& r, double velocity_floor);

/// ADMM on a Delassus problem from the impulses in `r` (projected on K first; zeros if
/// `r` has the wrong size), which it replaces by the last z: admissible impulses.
AdmmReport solve_admm(const DelassusProblem& p, Eigen::VectorXd& r, const AdmmOptions& options);

/// The factorised solver behind the seam: ADMM on the step's problem (delassus_problem),
/// warm-started from the impulses the system holds (the previous step's), until its law
/// residual is below half the tolerance or it has made admm_budget iterations; then pcg
/// (pcg.hpp) from its impulses, whose sweeps test the settings' criterion on the impulses
/// of a sweep, as every solver returns, and finish what ADMM left (docs/performance.md,
/// "A factorised solver": on the paper pile ADMM alone stalls above the tolerance from
/// k = 1e7 m g / D on). SolveReport::sweeps counts ADMM's back-solves and pcg's sweeps and
/// iterations, and the sweep cap bounds their sum.
class AdmmSolver final : public ContactSolver {
 public:
  /// ADMM's iterations per step at most.
  static constexpr int admm_budget = 300;

  explicit AdmmSolver(const SolverSettings& settings) : settings_(settings) {}
  SolverKind kind() const override { return SolverKind::admm; }
  SolveReport solve(ContactSystem& system, double gravity_velocity) const override;

 private:
  SolverSettings settings_;
};

}  // namespace cdpile::cd
