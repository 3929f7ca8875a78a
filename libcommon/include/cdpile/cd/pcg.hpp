/// NSGS sweeps that settle the active set, alternating with preconditioned gradient
/// rounds on it (docs/method.md, "The pcg solver").
///
/// Between status changes the step's problem is linear: with the open contacts at R = 0
/// and the sliding ones at their tangential impulse, the rest solves
/// (W + C)_FF R_F = -q_F on the free components F (both of a sticking contact, the
/// normal one of a sliding contact). Gauss-Seidel damps that system's smooth modes in a
/// number of sweeps of the order of its condition number, about W_aa / c with the
/// compliance c = 1/(k h^2) (1e3 at k = 1e6 on the paper's scales); conjugate gradients
/// need its square root. So the solver sweeps as NSGS does and, once a step has taken
/// SolverSettings::krylov_after sweeps without converging, every
/// SolverSettings::sweeps_between_rounds sweeps runs a round of conjugate gradients on the
/// face the last sweep left, preconditioned by one symmetric Gauss-Seidel pass over it.
/// A round ends at the first iterate that leaves the Coulomb cone: that iterate is
/// projected onto the cone (R_n >= 0, |R_t| <= mu R_n) and the sweeps take over, which
/// settle the statuses it changed. In a rearrangement that is mostly after one
/// iteration, an exactly line-searched step along the preconditioned gradient of the
/// face. The rounds before SolverSettings::following_until sweeps and iterations hold a
/// sliding contact's friction on its cone as its normal impulse changes
/// (R_t = s mu R_n) rather than its R_t, so that the projection does not cut them short
/// where R_n falls; the later ones hold R_t.
///
/// The local solves are NSGS's and the criterion is tested after sweeps only: the solver
/// returns the impulses of a sweep (admissible, the law measured as for NSGS), and a step
/// whose sweeps converge before krylov_after is NSGS's to the bit.
#pragma once

#include "cdpile/cd/face_newton.hpp"
#include "cdpile/cd/solver.hpp"

namespace cdpile::cd {

class PcgSolver final : public ContactSolver {
 public:
  /// Conjugate-gradient iterations per round at most; a round also ends when the face's
  /// residual is below a tenth of the tolerance.
  static constexpr int iterations_per_round = 100;

  explicit PcgSolver(const SolverSettings& settings) : settings_(settings) {}
  SolverKind kind() const override { return SolverKind::pcg; }
  /// SolveReport::sweeps counts the NSGS sweeps and the conjugate-gradient iterations
  /// (each about two sweeps' work), and the sweep cap bounds their sum.
  SolveReport solve(ContactSystem& system, double gravity_velocity) const override;

 private:
  SolverSettings settings_;
};

/// NSGS sweeps alternating with Newton steps on the active face (docs/method.md, "The
/// newton solver"), on the schedule of PcgSolver's rounds (SolverSettings::krylov_after,
/// SolverSettings::sweeps_between_rounds).
///
/// A gradient round ends on the Coulomb cone after one iteration in nearly every round:
/// its face holds a sliding contact's R_t while R_n changes, and the projection cuts
/// R_t wherever R_n fell (docs/performance.md, "A Cholesky factor as the rounds'
/// preconditioner"). The Newton step instead solves the face exactly with a sliding
/// contact's friction following its normal impulse, R_t = s mu R_n (face_newton.hpp): a
/// non-symmetric linear system, solved by GMRES preconditioned with a sparse LU of the
/// grains' J, the LU kept through the time step (FaceFactor). A round
/// projects the step onto the cones and, while that moved rows, solves the face they
/// leave (the projected rows open or sliding), up to steps_per_round steps; then the
/// sweeps take over, check the statuses and the criterion. For rigid contacts (no
/// compliance, so no J) its rounds are PcgSolver's.
class NewtonSolver final : public ContactSolver {
 public:
  /// Newton steps per round at most; each counts as one sweep in SolveReport::sweeps
  /// (its cost is that of 5 to 80 sweeps at 4000 grains, docs/performance.md).
  static constexpr int steps_per_round = 6;

  explicit NewtonSolver(const SolverSettings& settings) : settings_(settings) {}
  SolverKind kind() const override { return SolverKind::newton; }
  SolveReport solve(ContactSystem& system, double gravity_velocity) const override;

 private:
  SolverSettings settings_;
  /// The step's factor of J. It is scratch, not state: made anew in each time step, so a
  /// step's solution depends on that step's start alone, and a run resumed from a
  /// checkpoint is the run never interrupted, bit for bit.
  mutable FaceFactor factor_;
};

}  // namespace cdpile::cd
