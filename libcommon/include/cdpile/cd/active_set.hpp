/// The active-set Newton on a step's problem in Delassus form (docs/method.md, "Finishing a
/// step by its active set"): the statuses of the contacts (open, sticking, sliding either
/// way) read from the impulses by Alart and Curnier's projection, then the linear system
/// those statuses make solved exactly by one sparse LU, until the statuses repeat. On a
/// fixed set of statuses Coulomb's law is linear (open R = 0; sticking u = 0; sliding
/// u_n = 0 and R_t = -+mu R_n), so a repeat is a solution of the law, to the LU's rounding.
/// Its basin is narrow (docs/performance.md, "The active-set Newton's basin"): it is
/// started from a solver's impulses that are already near the solution, and its result is
/// kept only if it meets the law's residual.
#pragma once

#include "cdpile/cd/contact_system.hpp"
#include "cdpile/cd/delassus.hpp"

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <functional>
#include <vector>

namespace cdpile::cd {

/// A contact's face of the law: open, sticking, or sliding with R_t = -mu R_n (slip_plus,
/// u_t > 0) or R_t = +mu R_n (slip_minus).
enum class LawStatus : unsigned char { open, stick, slip_plus, slip_minus };

/// Alart and Curnier's statuses of impulses r (rho_a = 1 / W_aa): open where
/// R_n - rho u_n <= 0, else sticking where R - rho u lies in the cone, else sliding on the
/// side of its R_t.
std::vector<LawStatus> law_statuses(const DelassusProblem& p, const Eigen::VectorXd& r);

/// The linear system A R = b of a set of statuses: an open contact's rows R = 0, a sticking
/// one's W R = -q, a sliding one's normal row W R = -q and R_t -+ mu R_n = 0.
void status_system(const DelassusProblem& p, const std::vector<LawStatus>& st,
                   Eigen::SparseMatrix<double>& a, Eigen::VectorXd& b);

struct ActiveSetOptions {
  /// The law's residual (admm_law_residual, in the engine's velocity scale) that a
  /// solution must meet.
  double tolerance = 1e-6;
  double velocity_floor = 1.0;  ///< g h [m/s], the floor of that scale
  int max_factorisations = 10;
  /// Stop when a set differs from the last one solved by more than this many contacts:
  /// near its solution the Newton changes a few statuses a set (at most 8 on the loose
  /// pile's hard steps at 1e6, 14 at 1e8), and one that changes dozens has left its
  /// basin and fails (docs/performance.md, "Finishing the hard steps by their active set").
  int max_status_changes = 20;
  /// A proximal term for the sets whose system is singular (rigid contacts sticking in a
  /// hyperstatic network), relative to the diagonal of W on the rows that carry u: such a
  /// set is solved by the proximal point on its system A R = b from the Newton's impulses,
  /// R <- R + (A + proximal D)^-1 (b - A R), proximal_iterations back-solves of one LU
  /// (1: that one step is the set's solution; more: they must settle, or the Newton stops).
  /// 0 (the default): a singular set stops the Newton. Measured on rigid steps and not
  /// kept in the engine (docs/performance.md, "A proximal term on the rigid sets"); the
  /// benchmark admm_on_steps sets it (--polish-proximal).
  double proximal = 0.0;
  int proximal_iterations = 1;
  /// Called after each factorisation with their count and the law's residual then.
  std::function<void(int, double)> trace;
  std::function<bool()> cancel;  ///< polled before each factorisation (throws StepCancelled)
};

struct ActiveSetReport {
  int factorisations = 0;
  int proximal_solves = 0;  ///< sets solved by the proximal point (singular)
  double residual = 0.0;   ///< admm_law_residual of the impulses returned
  bool converged = false;  ///< residual <= tolerance
};

/// The active-set Newton from the impulses in `r` (2m values), which it replaces by the
/// last solution of a set's linear system; it stops when that solution meets the law's
/// residual, when the statuses repeat, when it comes back to a set it solved before (a
/// cycle), when a set differs from the last by more than max_status_changes contacts, or
/// after max_factorisations. A set whose system is singular (rigid contacts
/// sticking in a hyperstatic network) stops it unconverged, unless options.proximal asks
/// for the proximal point on it.
ActiveSetReport solve_active_set(const DelassusProblem& p, Eigen::VectorXd& r,
                                 const ActiveSetOptions& o);

/// The impulses of a contact system's rows, in delassus_problem's layout (2a normal,
/// 2a + 1 tangent).
Eigen::VectorXd row_impulses(const ContactSystem& s);

/// Gives the rows the impulses r and the bodies the velocities they make
/// (v = v_free + M^-1 H^T R stays true), each row's status from its impulse.
void set_row_impulses(ContactSystem& s, const Eigen::VectorXd& r);

}  // namespace cdpile::cd
