// NSGS alternating with preconditioned conjugate-gradient rounds on the active face
// (pcg.hpp; docs/method.md, "The pcg solver").
#include "cdpile/cd/pcg.hpp"

#include "cdpile/cd/face_newton.hpp"
#include "cdpile/cd/nsgs.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

namespace cdpile::cd {

namespace {

/// A value per contact: its normal and tangential components.
using Local = FaceValue;

/// A row of the face: its normal component is free; its tangential one too when the
/// contact sticks (in a gradient round a sliding contact keeps its R_t, or in a following
/// round and a Newton step its R_t follows s mu R_n, face_newton.hpp).
using FreeRow = FaceRow;

/// The local velocity H_a v of row r from the bodies' velocities v.
Local relative_velocity(const std::vector<Body>& bodies, const ContactRow& r) {
  const Body& a = bodies[static_cast<std::size_t>(r.bi)];
  const Body& b = bodies[static_cast<std::size_t>(r.bj)];
  const double dvx = a.vx - b.vx, dvy = a.vy - b.vy;
  return {dvx * r.nx + dvy * r.ny, -dvx * r.ny + dvy * r.nx - a.w * r.ri - b.w * r.rj};
}

/// Runs job(u, threads) on every thread u of the team, or job(0, 1) on the calling thread
/// where `n` positions are too few to share (for_each_range's rule): a pcg iteration's
/// elementwise updates of several vectors, in one meeting of the team.
void on_threads(std::size_t n, Team* team,
                const std::function<void(std::size_t, std::size_t)>& job) {
  if (!team || team->size() == 1 || n < team->smallest_shared()) {
    job(0, 1);
    return;
  }
  const auto threads = static_cast<std::size_t>(team->size());
  team->run([&](int t) { job(static_cast<std::size_t>(t), threads); });
}

/// Thread u's equal part [first, last) of [0, n), as for_each_range cuts it.
struct Part {
  std::size_t first, last;
  Part(std::size_t n, std::size_t u, std::size_t threads)
      : first(n * u / threads), last(n * (u + 1) / threads) {}
};

/// The largest component. A maximum is the same numbers in any order, so each thread
/// takes a range and the ranges' maxima are combined.
double largest(const std::vector<Local>& a, Team* team) {
  std::vector<double> part(team ? static_cast<std::size_t>(team->size()) : 1, 0.0);
  on_threads(a.size(), team, [&](std::size_t u, std::size_t threads) {
    const Part range(a.size(), u, threads);
    double m = 0.0;
    for (std::size_t k = range.first; k < range.last; ++k)
      m = std::max({m, std::abs(a[k].n), std::abs(a[k].t)});
    part[u] = m;
  });
  return *std::max_element(part.begin(), part.end());
}

/// What the rounds of one step reuse (a step builds a face every few sweeps): the scratch
/// bodies, with the grains' masses (their velocities are set by every use), the rows in
/// pair order (for a plan without colours, whose face is in pair order whatever the
/// scramble), and the storage of the face and of its vectors.
struct FaceSpace {
  FaceSpace(const ContactSystem& s, const Schedule& plan) {
    scratch.bodies = s.bodies;
    preconditioner.bodies = s.bodies;
    if (!plan.coloured) pair_plan = row_schedule(s, SweepOrder::pair, {});
  }
  ContactSystem scratch;         // bodies only: the products'
  ContactSystem preconditioner;  // bodies only: the preconditioner's passes
  Schedule pair_plan;     // for an uncoloured plan
  Schedule schedule;
  std::vector<std::uint32_t> kept;
  std::vector<FreeRow> rows;
  std::vector<double> slope;
  std::vector<Local> res, z, p, q;
};

/// The linear problem of the face the last sweep left: A = W + C on the free components,
/// applied without being formed (A x = H M^-1 H^T x + c x, scratch bodies carrying
/// M^-1 H^T x as the system's bodies carry M^-1 H^T R). Its rows are the active rows of
/// the sweeps' schedule, in its blocks and colours when it has them (schedule.hpp): the
/// Gauss-Seidel pass and the scatter of a product then share a colour among the team's
/// threads, and the dot products are summed per block, so that a round gives the same
/// numbers on any number of threads.
class Face {
 public:
  Face(ContactSystem& s, const Schedule& plan, FaceSpace& space, bool follow = false)
      : s_(s),
        scratch_(space.scratch),
        passes_(space.preconditioner),
        rows_(space.rows),
        slope_(space.slope),
        schedule_(space.schedule) {
    // In pair order the face is the active rows in pair order, whatever the scramble.
    const std::vector<std::uint32_t>& kept = space.kept;
    sub_schedule(plan.coloured ? plan : space.pair_plan,
                 [&](std::uint32_t a) { return s.rows[a].rn > 0.0; }, s.team, space.kept,
                 schedule_);
    rows_.resize(kept.size());
    slope_.resize(kept.size());
    for_each_range(kept.size(), s.team, [&](std::size_t first, std::size_t last) {
      for (std::size_t k = first; k < last; ++k) {
        const ContactRow& r = s.rows[kept[k]];
        const bool t = r.status == ContactStatus::stick;
        rows_[k] = {kept[k], t};
        slope_[k] = follow && !t ? (r.rt < 0.0 ? -r.mu : r.mu) : 0.0;
      }
    });
  }
  std::size_t size() const { return rows_.size(); }

  /// -(A R + q) on the free components: minus the law's velocity u'_a = W_aa R_a + b_a.
  void residual(std::vector<Local>& out) const {
    for_each_range(rows_.size(), s_.team, [&](std::size_t first, std::size_t last) {
      for (std::size_t k = first; k < last; ++k) {
        const ContactRow& r = s_.rows[rows_[k].row];
        double b_n, b_t;
        s_.free_local_velocity(r, b_n, b_t);
        out[k] = {-(b_n + r.w_nn * r.rn), rows_[k].t ? -(b_t + r.w_tt * r.rt) : 0.0};
      }
    });
  }

  // A gradient round's iteration meets the team 7 times (4 barriers more inside the
  // passes): every elementwise update rides on the pass or the job that needs it, and the
  // dot products are summed per block inside the passes (docs/performance.md, "Fewer
  // meetings per iteration"). Each number is the same as with one job per operation.

  /// Zeroes both scratch bodies' velocities and z: what product_dot() and
  /// precondition_dot() start from.
  void clear(std::vector<Local>& z) {
    on_threads(std::max(rows_.size(), s_.bodies.size()), s_.team,
               [&](std::size_t u, std::size_t threads) { clear_part(z, u, threads); });
  }

  /// z = P^-1 res with P one symmetric Gauss-Seidel pass over the face from z = 0
  /// (forward, then backward): symmetric positive definite with A, so a CG preconditioner.
  /// Starts from clear(); returns res . z, each block's sum made once its backward pass
  /// has left its z final.
  double precondition_dot(const std::vector<Local>& res, std::vector<Local>& z) {
    std::vector<double> partial(schedule_.blocks(), 0.0);
    for (const bool backward : {false, true})
      for_each_block(
          schedule_, s_.team, backward, [&](std::size_t first, std::size_t last, std::size_t blk) {
            for (std::size_t q = first; q < last; ++q) {
              const std::size_t k = schedule_.positions[backward ? last - 1 - (q - first) : q];
              const ContactRow& r = s_.rows[rows_[k].row];
              const Local u = relative_velocity(passes_.bodies, r);
              const double dn = (res[k].n - u.n - s_.compliance_n * z[k].n) / r.w_nn;
              const double dt =
                  rows_[k].t ? (res[k].t - u.t - s_.compliance_t * z[k].t) / r.w_tt : 0.0;
              z[k].n += dn;
              z[k].t += dt;
              passes_.apply_impulse(r, dn, rows_[k].t ? dt : slope_[k] * dn);
            }
            if (backward) partial[blk] = block_dot(res, z, first, last);
          });
    return sum_in_block_order(partial);
  }

  /// q = A p and p . q, with p = z + beta p made in the same pass (beta: none for p = z,
  /// the round's first direction), leaving M^-1 H^T p in the scratch bodies for move().
  /// Starts from clear().
  double product_dot(std::vector<Local>& p, const std::vector<Local>& z, std::optional<double> beta,
                     std::vector<Local>& q) {
    for_each_block(schedule_, s_.team, false, [&](std::size_t first, std::size_t last, std::size_t) {
      for (std::size_t i = first; i < last; ++i) {
        const std::size_t k = schedule_.positions[i];
        p[k] = beta ? Local{z[k].n + *beta * p[k].n, z[k].t + *beta * p[k].t} : z[k];
        scratch_.apply_impulse(s_.rows[rows_[k].row], p[k].n, rows_[k].t ? p[k].t : slope_[k] * p[k].n);
      }
    });
    std::vector<double> partial(schedule_.blocks(), 0.0);
    for_all_blocks(schedule_, s_.team, [&](std::size_t first, std::size_t last, std::size_t blk) {
      for (std::size_t i = first; i < last; ++i) {
        const std::size_t k = schedule_.positions[i];
        const ContactRow& r = s_.rows[rows_[k].row];
        const Local u = relative_velocity(scratch_.bodies, r);
        q[k] = {u.n + s_.compliance_n * p[k].n, rows_[k].t ? u.t + s_.compliance_t * p[k].t : 0.0};
      }
      partial[blk] = block_dot(p, q, first, last);
    });
    return sum_in_block_order(partial);
  }

  /// R += alpha p and v += alpha M^-1 H^T p (the scratch bodies of the last product_dot()).
  void move(const std::vector<Local>& p, double alpha) {
    on_threads(std::max(rows_.size(), s_.bodies.size()), s_.team,
               [&](std::size_t u, std::size_t threads) {
                 const Part rows(rows_.size(), u, threads), bodies(s_.bodies.size(), u, threads);
                 for (std::size_t k = rows.first; k < rows.last; ++k) {
                   ContactRow& r = s_.rows[rows_[k].row];
                   r.rn += alpha * p[k].n;
                   r.rt += alpha * (rows_[k].t ? p[k].t : slope_[k] * p[k].n);
                 }
                 for (std::size_t b = bodies.first; b < bodies.last; ++b) {
                   s_.bodies[b].vx += alpha * scratch_.bodies[b].vx;
                   s_.bodies[b].vy += alpha * scratch_.bodies[b].vy;
                   s_.bodies[b].w += alpha * scratch_.bodies[b].w;
                 }
               });
  }

  /// res -= alpha q, and clear() for the next iteration in the same job; returns the
  /// largest component of res (a maximum: the same in any order).
  double update_residual(std::vector<Local>& res, const std::vector<Local>& q, double alpha,
                         std::vector<Local>& z) {
    const std::size_t threads = s_.team ? static_cast<std::size_t>(s_.team->size()) : 1;
    std::vector<double> part(threads, 0.0);
    on_threads(std::max(rows_.size(), s_.bodies.size()), s_.team,
               [&](std::size_t u, std::size_t n) {
                 const Part rows(rows_.size(), u, n);
                 double m = 0.0;
                 for (std::size_t i = rows.first; i < rows.last; ++i) {
                   res[i].n -= alpha * q[i].n;
                   res[i].t -= alpha * q[i].t;
                   m = std::max({m, std::abs(res[i].n), std::abs(res[i].t)});
                 }
                 part[u] = m;
                 clear_part(z, u, n);
               });
    return *std::max_element(part.begin(), part.end());
  }

  /// The Newton step of the face to a residual of `target` (face_newton.hpp); false
  /// when it could not be made.
  bool newton_step(const std::vector<Local>& res, FaceFactor& factor, double target) {
    return newton_face_step(s_, rows_, res, factor, target);
  }

  /// Projects every face row into the cone (R_n >= 0, then |R_t| <= mu R_n), the bodies'
  /// velocities following, a row that moved taking the status it was projected to (open
  /// or sliding: the face of a next Newton step; the sweeps set statuses anew); returns
  /// whether any row moved.
  bool project() {
    std::vector<char> moved(schedule_.blocks(), 0);
    for_each_block(schedule_, s_.team, false, [&](std::size_t first, std::size_t last, std::size_t blk) {
      for (std::size_t i = first; i < last; ++i) {
        ContactRow& r = s_.rows[rows_[schedule_.positions[i]].row];
        const double rn = std::max(0.0, r.rn);
        const double rt = std::clamp(r.rt, -r.mu * rn, r.mu * rn);
        if (rn == r.rn && rt == r.rt) continue;
        moved[blk] = 1;
        s_.apply_impulse(r, rn - r.rn, rt - r.rt);
        r.rn = rn;
        r.rt = rt;
        r.status = rn == 0.0 ? ContactStatus::open : ContactStatus::slide;
      }
    });
    return std::find(moved.begin(), moved.end(), 1) != moved.end();
  }

 private:
  /// Thread u's part of clear().
  void clear_part(std::vector<Local>& z, std::size_t u, std::size_t threads) {
    const Part rows(rows_.size(), u, threads), bodies(s_.bodies.size(), u, threads);
    std::fill(z.begin() + static_cast<std::ptrdiff_t>(rows.first),
              z.begin() + static_cast<std::ptrdiff_t>(rows.last), Local{});
    for (std::size_t b = bodies.first; b < bodies.last; ++b) {
      scratch_.bodies[b].vx = scratch_.bodies[b].vy = scratch_.bodies[b].w = 0.0;
      passes_.bodies[b].vx = passes_.bodies[b].vy = passes_.bodies[b].w = 0.0;
    }
  }

  /// sum_k a_k . b_k over the block's positions [first, last), in their order.
  double block_dot(const std::vector<Local>& a, const std::vector<Local>& b, std::size_t first,
                   std::size_t last) const {
    double sum = 0.0;
    for (std::size_t i = first; i < last; ++i) {
      const std::size_t k = schedule_.positions[i];
      sum += a[k].n * b[k].n + a[k].t * b[k].t;
    }
    return sum;
  }

  /// The blocks' sums added in block order: the same number on any team.
  static double sum_in_block_order(const std::vector<double>& partial) {
    double total = partial.empty() ? 0.0 : partial[0];
    for (std::size_t blk = 1; blk < partial.size(); ++blk) total += partial[blk];
    return total;
  }

  ContactSystem& s_;
  ContactSystem& scratch_;  // bodies only: the products'
  ContactSystem& passes_;   // bodies only: the preconditioner's
  std::vector<FreeRow>& rows_;
  // dR_t / dR_n of each row: s mu for a sliding row whose friction follows its normal
  // impulse (a following round), else 0
  std::vector<double>& slope_;
  Schedule& schedule_;  // positions are indices into rows_
};

/// One round of conjugate gradients on the face the last sweep left (pcg.hpp); returns
/// its iterations. It ends at the first iterate that leaves the cone (projected onto
/// it), when the face's residual is at most `target` [m/s], or after `budget` iterations.
/// With `follow` a sliding contact's friction follows its normal impulse along its cone
/// (R_t = s mu R_n, SolverSettings::following_until): the face's operator is then not
/// symmetric, so the iterates are conjugate-gradient steps of no optimality, which the
/// projection and the sweeps after the round judge.
int gradient_round(ContactSystem& s, const Schedule& plan, FaceSpace& space, double target,
                   int budget, bool follow = false) {
  Face face(s, plan, space, follow);
  const std::size_t f = face.size();
  if (f == 0 || budget <= 0) return 0;
  std::vector<Local>& res = space.res;
  std::vector<Local>& z = space.z;
  std::vector<Local>& p = space.p;
  std::vector<Local>& q = space.q;
  res.resize(f);
  z.resize(f);
  p.resize(f);
  q.resize(f);
  face.residual(res);
  if (largest(res, s.team) <= target) return 0;
  face.clear(z);
  double rz = face.precondition_dot(res, z);
  std::optional<double> beta;  // none: p = z
  int k = 0;
  while (k < budget) {
    ++k;
    const double pq = face.product_dot(p, z, beta, q);
    if (!(pq > 0.0) || !(rz > 0.0)) break;  // nothing left that A sees
    const double alpha = rz / pq;
    face.move(p, alpha);
    // Stopping at the cone instead (where the first contact reaches it) moved 1-10 % of
    // alpha in a rearrangement, and was no faster than NSGS (docs/performance.md).
    if (face.project()) break;
    if (face.update_residual(res, q, alpha, z) <= target) break;
    const double rz_next = face.precondition_dot(res, z);
    beta = rz_next / rz;
    rz = rz_next;
  }
  return k;
}

/// What a round did: its iterations, and whether it was undone (NewtonSolver).
struct RoundResult {
  int iterations = 0;
  bool undone = false;
};

RoundResult gradient_rounds(ContactSystem& s, const Schedule& plan, FaceSpace& space,
                            double target, int budget) {
  return {gradient_round(s, plan, space, target, budget), false};
}

/// A round whose sliding contacts' friction follows their normal impulse (pcg.hpp).
RoundResult following_rounds(ContactSystem& s, const Schedule& plan, FaceSpace& space,
                             double target, int budget) {
  return {gradient_round(s, plan, space, target, budget, true), false};
}

/// The impulses, statuses and velocities a round starts from, to undo it.
struct SavedIterate {
  std::vector<ContactRow> rows;
  std::vector<Body> bodies;
};

/// A round of Newton steps (pcg.hpp, NewtonSolver): the exact step of the face the last
/// sweep left, projected onto the cones; while the projection moved rows, the exact step
/// of the face it left (those rows open or sliding), at most `budget` steps. On the
/// paper's pile at k = 1e6 a round takes 2 steps on average, the first moving 1 to 4 rows
/// of 6500 (docs/performance.md, "The newton solver"). Where the statuses are far from the
/// solution's (a stack loaded from zero forces) the steps can carry the iterate away
/// from the solution: a round that leaves the law's residual (its root mean square,
/// law_residual) higher than it found it is undone.
RoundResult newton_round(ContactSystem& s, const Schedule& plan, FaceSpace& space, double target,
                         int budget, FaceFactor& factor) {
  const SavedIterate start{s.rows, s.bodies};
  const double before = law_residual(s, 1.0).rms;
  RoundResult out;
  while (out.iterations < budget) {
    Face face(s, plan, space);
    if (face.size() == 0) break;
    std::vector<Local> res(face.size());
    face.residual(res);
    if (largest(res, s.team) <= target) break;
    // The linear solve to the round's target in its 2-norm, which bounds every
    // component. A looser one (the 2-norm at 100 times the target, about its root mean
    // square) left a step at 12 degrees with its residual in a few contacts, and 180
    // sweeps of one-step rounds followed (docs/performance.md, "The newton solver").
    if (!face.newton_step(res, factor, target)) break;  // J not factorised: the sweeps go on alone
    ++out.iterations;
    if (!face.project()) break;  // in the cones: the sweeps check the statuses
  }
  if (out.iterations > 0 && !(law_residual(s, 1.0).rms <= before)) {
    s.rows = start.rows;
    s.bodies = start.bodies;
    out.undone = true;
  }
  return out;
}

using Round =
    std::function<RoundResult(ContactSystem&, const Schedule&, FaceSpace&, double, int)>;

/// A kind of round and the most iterations it takes.
struct RoundKind {
  Round round;
  int budget;
};

/// NSGS sweeps, and after `settings.krylov_after` sweeps without convergence a round
/// every `settings.sweeps_between_rounds` sweeps: `early` ones, and `late` ones once the
/// step has done `late_after` sweeps and iterations, until a late round is undone.
/// `bodies_in_strips`: the bodies stored strip by strip during the solve
/// (RowsInScheduleOrder), for rounds that do not number unknowns by body.
SolveReport sweeps_and_rounds(const SolverSettings& settings, ContactSystem& system,
                              double gravity_velocity, RoundKind early, RoundKind late,
                              int late_after, bool bodies_in_strips) {
  SolveReport report;
  if (system.rows.empty()) return report;
  Schedule plan = sweep_schedule(system, settings);
  const RowsInScheduleOrder in_order(system, plan, bodies_in_strips);
  std::optional<FaceSpace> space;  // made at the first round: most steps need none
  int work = 0, sweeps = 0, since_round = 0;
  bool late_ok = true;
  while (work < settings.max_sweeps) {
    if (system.cancel && system.cancel()) throw StepCancelled();
    const bool backward = settings.symmetric_sweeps && (sweeps % 2 == 1);
    const SweepSums sums = nsgs_sweep(system, backward, plan);
    measure_sweep(sums, gravity_velocity, report);
    ++sweeps;
    ++work;
    ++since_round;
    report.sweeps = work;
    if (sweeps % settings.check_every == 0 &&
        criterion_met(settings, report, system, gravity_velocity))
      return report;
    if (sweeps < settings.krylov_after || since_round < settings.sweeps_between_rounds) continue;
    // The round's target: a tenth of the tolerance in the velocity scale of the sweeps'
    // measures (measure_sweep), so that a round never stops short of what a sweep checks.
    const double unit =
        std::max(gravity_velocity,
                 sums.active > 0 ? sums.scale_sum / static_cast<double>(sums.active) : 0.0);
    const double target = 0.1 * settings.tolerance * (unit > 0.0 ? unit : 1.0);
    // at most max_sweeps - work - 1 iterations: the step always ends on a sweep
    const RoundKind& r = late_ok && work >= late_after ? late : early;
    const RoundResult done =
        r.round(system, plan, space ? *space : space.emplace(system, plan), target,
                std::min(r.budget, settings.max_sweeps - work - 1));
    work += done.iterations;
    if (done.undone) late_ok = false;
    since_round = 0;
  }
  report.converged = false;
  return report;
}

}  // namespace

SolveReport NewtonSolver::solve(ContactSystem& system, double gravity_velocity) const {
  const RoundKind gradient{gradient_rounds, PcgSolver::iterations_per_round};
  // Woodbury's identity needs C > 0: rigid contacts get pcg's gradient rounds only.
  if (!(system.compliance_n > 0.0 && system.compliance_t > 0.0))
    return sweeps_and_rounds(settings_, system, gravity_velocity, gradient, gradient,
                             settings_.max_sweeps, false);
  const Round newton = [this](ContactSystem& s, const Schedule& plan, FaceSpace& space,
                              double target, int budget) {
    return newton_round(s, plan, space, target, budget, factor_);
  };
  return sweeps_and_rounds(settings_, system, gravity_velocity, gradient, {newton, steps_per_round},
                           settings_.newton_after, false);
}

SolveReport PcgSolver::solve(ContactSystem& system, double gravity_velocity) const {
  const RoundKind gradient{gradient_rounds, iterations_per_round};
  const RoundKind following{following_rounds, iterations_per_round};
  return sweeps_and_rounds(settings_, system, gravity_velocity, following, gradient,
                           settings_.following_until, true);
}

}  // namespace cdpile::cd
