/// The exact solution of one 2D contact with Signorini and Coulomb's law, the other
/// contacts frozen: the kernel of non-smooth Gauss-Seidel (docs/method.md, "The local
/// solver": the cases, and where they come from).
///
/// Unknowns are impulses over the step, R = (R_n, R_t) [N s/m]; the contact's local
/// velocity is u = W R + b, with W the 2x2 diagonal block of the Delassus operator and b
/// the free local velocity including the other contacts' impulses and the gap term.
/// The law: 0 <= R_n  _|_  u_n >= 0 and |R_t| <= mu R_n with R_t opposing u_t when
/// |R_t| = mu R_n. In 2D the cone is two half-lines, so the solution is found by cases
/// (no contact / stick / slide forward / slide backward), not by iteration.
#pragma once

#include "cdpile/model.hpp"

#include <cmath>

namespace cdpile::cd {

/// Result of a local solve.
struct LocalImpulse {
  double rn = 0.0, rt = 0.0;
  ContactStatus status = ContactStatus::open;
};

/// Local solve when the block is diagonal (W_nt = W_tn = 0): two disks, or a disk and a
/// wall, whose normal passes through both centres (docs/method.md, "The local solver"). Then
///   R_n = max(0, -b_n / W_nn),  R_t = clamp(-b_t / W_tt, -mu R_n, mu R_n).
/// A sliding contact lies exactly on the cone: |R_t| == mu R_n in floating point.
inline LocalImpulse local_solve_diagonal(double w_nn, double w_tt, double mu, double b_n,
                                         double b_t) {
  LocalImpulse r;
  if (b_n >= 0.0) return r;  // separating or resting without need of a force: open
  r.rn = -b_n / w_nn;
  const double stick = -b_t / w_tt;  // impulse that cancels the tangential velocity
  const double bound = mu * r.rn;
  if (stick > bound) {
    r.rt = bound;
    r.status = ContactStatus::slide;
  } else if (stick < -bound) {
    r.rt = -bound;
    r.status = ContactStatus::slide;
  } else {
    r.rt = stick;
    r.status = ContactStatus::stick;
  }
  return r;
}

/// Local solve with a full 2x2 block (w_nt = W(n,t), w_tn = W(t,n)), for Delassus
/// problems from other codes. Cases as in LMGC90's mu_SC_std_solver (docs/method.md):
/// stick R = -W^-1 b if inside the cone; otherwise slide forward (u_t >= 0,
/// R_t = -mu R_n, R_n = -b_n / (W_nn - mu W_nt)) or backward (u_t <= 0, R_t = +mu R_n,
/// R_n = -b_n / (W_nn + mu W_nt)), whichever is consistent.
inline LocalImpulse local_solve(double w_nn, double w_nt, double w_tn, double w_tt, double mu,
                                double b_n, double b_t) {
  if (w_nt == 0.0 && w_tn == 0.0) return local_solve_diagonal(w_nn, w_tt, mu, b_n, b_t);
  LocalImpulse r;
  if (b_n >= 0.0) return r;
  const double det = w_nn * w_tt - w_nt * w_tn;
  const double sn = (-w_tt * b_n + w_nt * b_t) / det;
  const double st = (w_tn * b_n - w_nn * b_t) / det;
  if (sn >= 0.0 && std::abs(st) <= mu * sn) {
    r.rn = sn;
    r.rt = st;
    r.status = ContactStatus::stick;
    return r;
  }
  const double forward = w_nn - mu * w_nt;  // R_t = -mu R_n
  if (forward > 0.0) {
    const double rn = -b_n / forward;
    const double ut = b_t + (w_tn - mu * w_tt) * rn;
    if (ut >= 0.0) {
      r.rn = rn;
      r.rt = -mu * rn;
      r.status = ContactStatus::slide;
      return r;
    }
  }
  const double backward = w_nn + mu * w_nt;  // R_t = +mu R_n
  if (backward > 0.0) {
    r.rn = -b_n / backward;
    r.rt = mu * r.rn;
    r.status = ContactStatus::slide;
  }
  return r;
}

}  // namespace cdpile::cd
