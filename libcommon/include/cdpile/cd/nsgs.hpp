/// Non-smooth Gauss-Seidel over a ContactSystem (docs/method.md, "The scheme", step 6):
/// contact after contact, the exact 2D local solve (local_solver.hpp) with the others
/// frozen, the bodies' velocities updated at once (the ELG layout of LMGC90: each
/// contact's local velocity is read from its two bodies in O(1)).
#pragma once

#include "cdpile/cd/local_solver.hpp"
#include "cdpile/cd/schedule.hpp"
#include "cdpile/cd/solver.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

namespace cdpile::cd {

/// The sums one sweep leaves for the convergence measures (SolveReport).
struct SweepSums {
  double largest = 0.0;     ///< max_a |W_aa dR_a|
  double square_sum = 0.0;  ///< sum over active contacts of the same, squared
  double scale_sum = 0.0;   ///< sum over active contacts of W_nn R_n
  int active = 0;           ///< contacts with R_n > 0 after the sweep
};

/// The local solve of an engine row: the block of two disks, or of a disk and a wall, is
/// diagonal (docs/method.md, "The local solver").
inline LocalImpulse local_solve(const ContactRow& r, double b_n, double b_t) {
  return local_solve_diagonal(r.w_nn, r.w_tt, r.mu, b_n, b_t);
}

/// The Gauss-Seidel pass every NSGS in cdpile makes (the solvers behind solver.hpp over a
/// ContactSystem, and solve_nsgs over a Delassus problem, delassus.hpp): over positions
/// [first, last), forward or backward, contact after contact, the exact local solve with
/// the others frozen (local_solver.hpp), its impulse replaced, and the change pushed to
/// the velocities it moves. `system` gives free_local_velocity(row, b_n, b_t) (the local
/// velocity with the row's own impulse removed) and apply_impulse(row, dn, dt);
/// `row_at(q)` is the row at position q, with w_nn, w_tt, mu, rn, rt and status, and a
/// local_solve(row, b_n, b_t) of its own.
template <class System, class RowAt>
SweepSums sweep_rows(System& system, RowAt row_at, std::size_t first, std::size_t last,
                     bool backward) {
  SweepSums sums;
  for (std::size_t q = first; q < last; ++q) {
    auto& r = row_at(backward ? last - 1 - (q - first) : q);
    double b_n, b_t;
    system.free_local_velocity(r, b_n, b_t);
    const LocalImpulse l = local_solve(r, b_n, b_t);
    const double dn = l.rn - r.rn, dt = l.rt - r.rt;
    r.rn = l.rn;
    r.rt = l.rt;
    r.status = l.status;
    const double correction = std::max(std::abs(r.w_nn * dn), std::abs(r.w_tt * dt));
    if (l.rn > 0.0) {
      sums.scale_sum += r.w_nn * l.rn;
      sums.square_sum += correction * correction;
      ++sums.active;
    }
    if (dn == 0.0 && dt == 0.0) continue;
    sums.largest = std::max(sums.largest, correction);
    system.apply_impulse(r, dn, dt);
  }
  return sums;
}

/// One sweep over the rows in the order of `plan` (schedule.hpp), forward or backward
/// (the last colour first, each in reverse), a coloured plan's colours shared among the
/// threads of s.team. The sums are made per block and added in block order.
SweepSums nsgs_sweep(ContactSystem& s, bool backward, const Schedule& plan);

/// The sweep order of a step: empty (pair order) when `seed` is 0, else a permutation of
/// the rows drawn from (seed, s.step) by Fisher-Yates on std::mt19937_64, whose output the
/// standard fixes: the same on every platform, so a scrambled run resumes bit for bit.
std::vector<std::uint32_t> sweep_order(const ContactSystem& s, std::uint64_t seed);

/// The schedule of a step's sweeps under `settings`: the scramble's order (or pair
/// order), coloured when settings.sweep_order says so.
Schedule sweep_schedule(const ContactSystem& s, const SolverSettings& settings);

/// The convergence measures of a sweep (SolveReport::residual, residual_rms) and whether
/// the settings' criterion is met by them (or, for Criterion::law, by the system).
void measure_sweep(const SweepSums& sums, double gravity_velocity, SolveReport& report);
bool criterion_met(const SolverSettings& settings, const SolveReport& report,
                   const ContactSystem& system, double gravity_velocity);

class NsgsSolver final : public ContactSolver {
 public:
  explicit NsgsSolver(const SolverSettings& settings) : settings_(settings) {}
  SolverKind kind() const override { return SolverKind::nsgs; }
  SolveReport solve(ContactSystem& system, double gravity_velocity) const override;

 private:
  SolverSettings settings_;
};

/// NSGS with a nonlinear conjugate-gradient step after each sweep (NNCG: Silcowitz-Hansen,
/// Niebe and Erleben, The Visual Computer 26:893, 2010). With d_k the change a sweep made
/// to the impulses and beta_k = |d_k|^2 / |d_{k-1}|^2, the impulses are moved on by
/// beta_k p_{k-1} and p_k = beta_k p_{k-1} + d_k; beta_k > 1 restarts (p_k = 0). The
/// local solves are NSGS's, so the law is exact wherever a sweep leaves it; the step
/// only accelerates the slow, nearly linear modes between status changes. The returned
/// impulses are always those of a sweep.
class NncgSolver final : public ContactSolver {
 public:
  explicit NncgSolver(const SolverSettings& settings) : settings_(settings) {}
  SolverKind kind() const override { return SolverKind::nncg; }
  SolveReport solve(ContactSystem& system, double gravity_velocity) const override;

 private:
  SolverSettings settings_;
};

}  // namespace cdpile::cd
