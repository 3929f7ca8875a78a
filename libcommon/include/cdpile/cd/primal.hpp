/// The primal solver (docs/method.md, "The primal solver"; docs/performance.md, "Newton on
/// the grains' velocities"): Newton's method on the step's problem written in the grains'
/// velocities v, where it is the minimum of a convex function, with De Saxce's shift
/// moved between the minimisations.
///
/// A compliant contact (c_n, c_t = 1/(k h^2)) obeys Coulomb's law on its law velocity
/// w = z + C R, z = (u_n + gap/h - c_n R0_n + s, u_t - c_t R0_t), u = H_a v, s the De
/// Saxce shift mu |w_t| (contact_system.hpp). With the shift held, R in the cone K, w in
/// its dual and R.w = 0 is Moreau's decomposition of -z: R = C^-1/2 Proj_K'(-C^-1/2 z),
/// K' the cone of C^1/2 K (mu' = mu sqrt(c_t / c_n)). That R is minus the gradient of
/// phi(z) = |Proj_K'(-C^-1/2 z)|^2 / 2, which is convex, so with M (v - v_free) = H^T R the
/// step's velocities minimise
///
///     E(v) = (v - v_free)^T M (v - v_free) / 2 + sum_a phi_a(H_a v + d_a),
///
/// the grains' system of Todorov's convex contact (2014) and of Castro et al.'s SAP (2022),
/// here with Coulomb's law exact once the shift is consistent. E is strictly convex and
/// piecewise quadratic; its Hessian M + sum H_a^T C^-1/2 J_a C^-1/2 H_a (J_a the
/// projection's Jacobian: 0 open, I sticking, e e^T sliding on the face e) is positive
/// definite at any stiffness, one sparse Cholesky factor per Newton step. Newton's
/// direction descends E and an exact line search along it keeps every step a decrease:
/// the global convergence the contacts' Newton methods lacked (docs/performance.md).
///
/// Rigid contacts (c = 0) take the compliance `rigid_compliance` around an anchor that
/// moves to each minimiser (a proximal point on the impulses): at its fixed point the
/// compliance term vanishes and the law is the rigid one.
#pragma once

#include "cdpile/cd/contact_system.hpp"
#include "cdpile/cd/solver.hpp"

#include <functional>

namespace cdpile::cd {

struct PrimalOptions {
  /// The law's residual (law_residual, relative to velocity_floor) at which it stops.
  double tolerance = 1e-6;
  double velocity_floor = 1.0;  ///< g h [m/s]
  int max_factorisations = 60;  ///< Newton steps (one Cholesky factor each) at most
  /// Newton steps on one shift (and anchor) before they are moved; they move sooner when
  /// a step keeps every contact's status with a full step (the minimum of that E). One,
  /// the default, moves them after every step: on the paper pile's steps at k = 1e6 that
  /// reached 6e-5 in 60 factorisations where 4 left 5e-3 (docs/performance.md).
  int inner_steps = 1;
  /// The compliance of rigid contacts, relative to the step's mean W_nn; its anchor moves
  /// to each iterate's impulses, so at a fixed point the compliance term is zero.
  double rigid_compliance = 1e-4;
  std::function<bool()> cancel;
  /// After every Newton step (for measuring): the step, the shifts moved so far, the
  /// law's residual, the line search's step length.
  std::function<void(int, int, double, double)> on_iteration;
};

struct PrimalReport {
  int factorisations = 0;
  int shifts = 0;  ///< moves of the shift (and anchor)
  double residual = 0.0;
  bool converged = false;
};

/// Solves the system's step from the impulses and velocities it holds; on return the rows
/// hold the impulses reached and the bodies v_free + M^-1 H^T R.
PrimalReport solve_primal(ContactSystem& s, const PrimalOptions& o);

/// The solver behind `--solver primal`: solve_primal within a budget of factorisations,
/// then pcg from its impulses, whose sweeps test the engine's criterion.
class PrimalSolver final : public ContactSolver {
 public:
  static constexpr int primal_budget = 200;
  explicit PrimalSolver(const SolverSettings& settings) : settings_(settings) {}
  SolverKind kind() const override { return SolverKind::primal; }
  SolveReport solve(ContactSystem& system, double gravity_velocity) const override;

 private:
  SolverSettings settings_;
};

}  // namespace cdpile::cd
