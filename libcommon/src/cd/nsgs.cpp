// Non-smooth Gauss-Seidel over the solver-neutral contact system (nsgs.hpp).
#include "cdpile/cd/nsgs.hpp"

#include "cdpile/cd/local_solver.hpp"
#include "cdpile/check.hpp"
#include "cdpile/error.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace cdpile::cd {

namespace {

SweepSums& operator+=(SweepSums& a, const SweepSums& b) {
  a.largest = std::max(a.largest, b.largest);
  a.square_sum += b.square_sum;
  a.scale_sum += b.scale_sum;
  a.active += b.active;
  return a;
}

// The local solves of positions [first, last) of the schedule, forward or backward.
SweepSums sweep_block(ContactSystem& s, const Schedule& plan, std::size_t first, std::size_t last,
                      bool backward) {
  return sweep_rows(
      s, [&](std::size_t q) -> ContactRow& { return s.rows[plan.positions[q]]; }, first, last,
      backward);
}

}  // namespace

SweepSums nsgs_sweep(ContactSystem& s, bool backward, const Schedule& plan) {
  CDPILE_DEBUG_CHECK(plan.size() == s.rows.size(), "a sweep schedule covers every row");
  std::vector<SweepSums> blocks(plan.blocks());
  for_each_block(plan, s.team, backward, [&](std::size_t first, std::size_t last, std::size_t b) {
    blocks[b] = sweep_block(s, plan, first, last, backward);
  });
  // Block order, whatever the threads: the sums are the same numbers on any team.
  SweepSums sums;
  for (const SweepSums& b : blocks) sums += b;
  return sums;
}

Schedule sweep_schedule(const ContactSystem& s, const SolverSettings& settings) {
  return row_schedule(s, settings.sweep_order, sweep_order(s, settings.scramble));
}

std::vector<std::uint32_t> sweep_order(const ContactSystem& s, std::uint64_t seed) {
  if (seed == 0) return {};
  const std::size_t m = s.rows.size();
  std::vector<std::uint32_t> order(m);
  for (std::size_t k = 0; k < m; ++k) order[k] = static_cast<std::uint32_t>(k);
  // one stream per (seed, step): the step enters through a large odd multiplier
  std::mt19937_64 random(seed ^ (static_cast<std::uint64_t>(s.step) * 0x9E3779B97F4A7C15ull));
  for (std::size_t k = m; k > 1; --k) {
    const std::uint64_t j = random() % k;  // bias below k / 2^64: nothing for a sweep order
    std::swap(order[k - 1], order[j]);
  }
  return order;
}

// Sweeps until the criterion is met. maxm, quad and qm16 are relative to one velocity
// scale: the mean normal velocity jump of the active contacts, bounded below by g h, the
// velocity gravity adds in one step. 'maxm' bounds every contact, so a contact that has
// just formed is converged on its own and cannot hide in an average (LMGC90's "newcomer
// syndrome", docs/method.md "Convergence"); 'quad' bounds the root mean square, which a
// few slowly converging contacts barely move; 'qm16' is LMGC90's compromise between the
// two; 'law' bounds the residual of the law itself, whatever the sweeps did last.
void measure_sweep(const SweepSums& s, double gravity_velocity, SolveReport& report) {
  const double scale =
      std::max(gravity_velocity, s.active > 0 ? s.scale_sum / static_cast<double>(s.active) : 0.0);
  // Without gravity and without an active contact there is no velocity scale: the
  // measures are then absolute [m/s].
  const double unit = scale > 0.0 ? scale : 1.0;
  report.add_sweep(s.largest / unit);
  report.residual_rms =
      s.active > 0 ? std::sqrt(s.square_sum / static_cast<double>(s.active)) / unit : 0.0;
  if (!std::isfinite(report.residual))
    throw Error("engine: the solver diverged (non-finite impulse)");
}

bool criterion_met(const SolverSettings& settings, const SolveReport& r, const ContactSystem& s,
                   double gravity_velocity) {
  const double tol = settings.tolerance;
  switch (settings.criterion) {
    case Criterion::maxm: return r.residual <= tol;
    case Criterion::quad: return r.residual_rms <= tol;
    case Criterion::qm16: return r.residual_rms <= tol && r.residual <= qm16_max_factor * tol;
    case Criterion::law: return law_residual(s, gravity_velocity).max <= tol;
    case Criterion::err: {
      // A linear iteration contracting by rho per sweep is within rho / (1 - rho) times its
      // last correction of its limit: the bound on the error that the last correction
      // alone underestimates by about the condition number when rho is near 1
      // (docs/method.md, "Convergence"). A sweep that changed nothing is the limit.
      const double rho = r.contraction(err_window(settings));
      return r.residual == 0.0 ||
             (rho >= 0.0 && rho < 1.0 && r.residual * rho <= tol * (1.0 - rho));
    }
  }
  return false;
}

SolveReport NsgsSolver::solve(ContactSystem& system, double gravity_velocity) const {
  SolveReport report;
  if (system.rows.empty()) return report;
  const int every = settings_.check_every;
  Schedule plan = sweep_schedule(system, settings_);
  const RowsInScheduleOrder in_order(system, plan, true);
  for (int k = 0; k < settings_.max_sweeps; ++k) {
    if (system.cancel && system.cancel()) throw StepCancelled();
    const bool backward = settings_.symmetric_sweeps && (k % 2 == 1);
    measure_sweep(nsgs_sweep(system, backward, plan), gravity_velocity, report);
    report.sweeps = k + 1;
    if ((k + 1) % every == 0 && criterion_met(settings_, report, system, gravity_velocity))
      return report;
  }
  report.converged = false;
  return report;
}

SolveReport NncgSolver::solve(ContactSystem& system, double gravity_velocity) const {
  SolveReport report;
  const std::size_t m = system.rows.size();
  if (m == 0) return report;
  std::vector<double> before(2 * m), p(2 * m, 0.0);
  double d2_previous = 0.0;
  const int every = settings_.check_every;
  Schedule plan = sweep_schedule(system, settings_);
  const RowsInScheduleOrder in_order(system, plan, true);
  for (int k = 0; k < settings_.max_sweeps; ++k) {
    if (system.cancel && system.cancel()) throw StepCancelled();
    for (std::size_t a = 0; a < m; ++a) {
      before[2 * a] = system.rows[a].rn;
      before[2 * a + 1] = system.rows[a].rt;
    }
    const bool backward = settings_.symmetric_sweeps && (k % 2 == 1);
    measure_sweep(nsgs_sweep(system, backward, plan), gravity_velocity, report);
    report.sweeps = k + 1;
    if ((k + 1) % every == 0 && criterion_met(settings_, report, system, gravity_velocity))
      return report;
    if (k + 1 == settings_.max_sweeps) break;  // end on a sweep's impulses
    double d2 = 0.0;
    for (std::size_t a = 0; a < m; ++a) {
      const double dn = system.rows[a].rn - before[2 * a],
                   dt = system.rows[a].rt - before[2 * a + 1];
      d2 += dn * dn + dt * dt;
    }
    const double beta = d2_previous > 0.0 ? d2 / d2_previous : 2.0;
    d2_previous = d2;
    if (beta > 1.0) {  // restart: the sweep's change is the new direction
      for (std::size_t a = 0; a < m; ++a) {
        p[2 * a] = system.rows[a].rn - before[2 * a];
        p[2 * a + 1] = system.rows[a].rt - before[2 * a + 1];
      }
      continue;
    }
    for (std::size_t a = 0; a < m; ++a) {
      ContactRow& r = system.rows[a];
      const double sn = beta * p[2 * a], st = beta * p[2 * a + 1];
      p[2 * a] = sn + (r.rn - before[2 * a]);
      p[2 * a + 1] = st + (r.rt - before[2 * a + 1]);
      if (sn == 0.0 && st == 0.0) continue;
      r.rn += sn;
      r.rt += st;
      system.apply_impulse(r, sn, st);
    }
  }
  report.converged = false;
  return report;
}

}  // namespace cdpile::cd
