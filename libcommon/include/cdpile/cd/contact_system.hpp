/// The contact system of one step, as every solver sees it: data only, kept apart from the
/// algorithms that work on it (Box2D's solver layout). docs/method.md, "The scheme" and
/// "Force selection".
///
/// Per body: the velocity being solved for, v = v_free + M^-1 H^T R (H maps body
/// velocities to local contact velocities, u = H v), and its inverse mass and inertia.
/// Per contact: the two bodies, the frame (unit normal n from j to i, tangent
/// t = (-n_y, n_x)), the lever arms, mu, the gap term, the diagonal Delassus block
/// W_aa = H_a M^-1 H_a^T (diagonal for disks: W_nt = 0), the impulses R_a = (R_n, R_t)
/// [N s/m], the anchor impulses R0_a of the compliance (the previous step's) and the status.
///
/// The law each contact obeys (docs/method.md, eqs. (M1)-(M3)), with c_n, c_t the step's
/// compliances 1/(k h^2) (1/(k h^2 + eta h) with the contact dashpot, (M3'); zero for rigid
/// contacts):
///     u'_n = u_n + max(0, gap/h) + c_n (R_n - R0_n),   0 <= R_n  _|_  u'_n >= 0,
///     u'_t = u_t + c_t (R_t - R0_t),                   Coulomb on (R_n, R_t, u'_t).
#pragma once

#include "cdpile/model.hpp"

#include <cstdint>
#include <exception>
#include <functional>
#include <vector>

namespace cdpile::cd {

class Team;  // team.hpp

/// One rigid body: a disk, or the static body standing for the walls.
struct Body {
  double vx, vy, w;     ///< velocity being solved for (v_free + M^-1 H^T R) [m/s, rad/s]
  double inv_m, inv_i;  ///< zero for a glued grain and for the walls
};

/// Whether a body is written by a local solve (a free grain): the walls and a glued grain
/// have neither inverse mass nor inverse inertia and are never written, so contacts that
/// share only such a body can be solved at once (schedule.hpp).
inline bool moves(const Body& b) { return b.inv_m != 0.0 || b.inv_i != 0.0; }

/// One contact row, contiguous for the sweeps.
struct ContactRow {
  std::int32_t i, j;    ///< grains; j < 0 is a wall
  std::int32_t bi, bj;  ///< body indices (a wall is the static body N)
  double nx, ny;        ///< unit normal from j to i
  double ri, rj;        ///< lever arms (radii; 0 for a wall) [m]
  double w_nn, w_tt;    ///< diagonal Delassus block, compliances included [1/kg per m]
  double mu;
  double gap;           ///< at the predicted configuration [m]
  double gap_velocity;  ///< max(0, gap / h) [m/s], LMGC90 IQS_CLB
  double rn, rt;        ///< impulses [N s/m]
  double rn0, rt0;      ///< anchor of the compliance: the warm-start impulses [N s/m]
  ContactStatus status;
};

/// Thrown by a solver when ContactSystem::cancel says so. The engine's grains, clock and
/// warm-start impulses are still those of the last completed step (Engine::step changes
/// them only after the solve), so a checkpoint written then resumes bit for bit.
struct StepCancelled : std::exception {
  const char* what() const noexcept override { return "step cancelled"; }
};

/// The sort key of a pair (i, j): lexicographic in (i, j) with j signed, so the walls
/// (j < 0) of grain i come before its grain partners.
inline std::uint64_t pair_key(std::int32_t i, std::int32_t j) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(i)) << 32) |
         (static_cast<std::uint32_t>(j) ^ 0x80000000u);
}

/// The step's contact system. Rows are sorted by pair_key(i, j), each pair once.
struct ContactSystem {
  std::vector<Body> bodies;
  std::vector<ContactRow> rows;
  double compliance_n = 0.0;  ///< c_n = 1/(k_n h^2 + eta h) [1/kg per m], 0 for rigid contacts
  double compliance_t = 0.0;  ///< c_t = 1/(k_t h^2 + eta h)
  std::int64_t step = 0;      ///< the step being solved (seeds a scrambled sweep order)
  /// Polled by the solvers before every sweep (may be empty): true abandons the step with
  /// StepCancelled. A signalled tool stops within a second even when one step takes
  /// longer (a large pile at the sweep cap), with its last completed step intact.
  std::function<bool()> cancel;
  /// The threads that share a coloured schedule's colours (schedule.hpp); none: one thread.
  /// Owned by the engine; the numbers do not depend on it.
  Team* team = nullptr;
  /// Per body, the vertical strip of the box its centre lies in (schedule.hpp,
  /// SweepOrder::strips), -1 for a body that does not move; empty: no strips.
  std::vector<std::int32_t> strip;
  /// Scratch for a solver that reorders the rows during a solve (schedule.hpp,
  /// RowsInScheduleOrder): kept between steps so that the step allocates nothing.
  std::vector<ContactRow> spare_rows;
  std::vector<Body> spare_bodies;  ///< the same for the bodies

  bool compliant() const { return compliance_n != 0.0 || compliance_t != 0.0; }

  /// The local velocity of row r with its own impulse removed and the law's constant
  /// terms added: u'_a = W_aa R_a + b_a (the other contacts' impulses frozen in b_a).
  void free_local_velocity(const ContactRow& r, double& b_n, double& b_t) const {
    const Body& a = bodies[static_cast<std::size_t>(r.bi)];
    const Body& b = bodies[static_cast<std::size_t>(r.bj)];
    const double dvx = a.vx - b.vx, dvy = a.vy - b.vy;
    const double u_n = dvx * r.nx + dvy * r.ny;
    const double u_t = -dvx * r.ny + dvy * r.nx - a.w * r.ri - b.w * r.rj;
    b_n = u_n - r.w_nn * r.rn + r.gap_velocity;
    b_t = u_t - r.w_tt * r.rt;
    if (compliant()) {  // the rigid part of W_aa R_a was removed above; add back c R - c R0
      b_n += compliance_n * (r.rn - r.rn0);
      b_t += compliance_t * (r.rt - r.rt0);
    }
  }

  /// Adds M^-1 H_a^T (dn, dt) to the two bodies of row r: the velocity change an impulse
  /// change (dn, dt) at that contact makes. A body that does not move (moves()) is not
  /// written: the change would be zero, and the contacts of one strip share such bodies.
  void apply_impulse(const ContactRow& r, double dn, double dt) {
    Body& a = bodies[static_cast<std::size_t>(r.bi)];
    Body& b = bodies[static_cast<std::size_t>(r.bj)];
    const double px = dn * r.nx - dt * r.ny;  // R = R_n n + R_t t
    const double py = dn * r.ny + dt * r.nx;
    if (moves(a)) {
      a.vx += a.inv_m * px;
      a.vy += a.inv_m * py;
      a.w -= a.inv_i * r.ri * dt;
    }
    if (moves(b)) {
      b.vx -= b.inv_m * px;
      b.vy -= b.inv_m * py;
      b.w -= b.inv_i * r.rj * dt;
    }
  }
};

/// The contact law's violation, independent of the solver that produced the impulses
/// (docs/method.md, "The residual"): for each contact, the velocity correction
/// W_aa (s_a - R_a) that its exact local solve s_a (local_solver.hpp, the other contacts
/// frozen) would make now. It is zero at every contact exactly when R solves the step,
/// is in velocity units, and is divided by g h, the velocity gravity adds in one step.
struct LawResidual {
  double max = 0.0;  ///< max over contacts and components, / (g h)
  double rms = 0.0;  ///< root mean square over the rows of the larger component, / (g h)
};
LawResidual law_residual(const ContactSystem& s, double velocity_scale);

/// Debug-build checks of what the warm start and the solvers rely on (check.hpp): each
/// aborts with a message naming the broken invariant; with NDEBUG they do nothing.
///
/// The rows: strictly increasing pair_key (each pair once; the warm start matches rows to
/// the stored impulses by merging two sorted lists, so a row out of order would silently
/// start from zero), grain pairs with i < j, body indices in range, and a positive
/// diagonal block W_nn, W_tt (the local solver divides by both).
void debug_check_rows(const ContactSystem& s);
/// Every impulse is finite and admissible: R_n >= 0 and |R_t| <= mu R_n. A sweep's local
/// solves leave them so, and every solver returns the impulses of a sweep.
void debug_check_admissible(const ContactSystem& s);
/// The bodies hold v = v_free + M^-1 H^T R: `free_bodies` are the same bodies at v_free,
/// and the velocities that the rows' impulses make from them must equal the bodies' own
/// within 1e-9 of the step's velocity scale: the largest of `velocity_unit` (g h), the
/// free speeds and the velocity jumps W_aa |R_a| (the rounding of many sweeps' updates is
/// relative to the largest of these). Angular velocities are compared times the lever arm.
void debug_check_velocities(const ContactSystem& s, const std::vector<Body>& free_bodies,
                            double velocity_unit);

}  // namespace cdpile::cd
