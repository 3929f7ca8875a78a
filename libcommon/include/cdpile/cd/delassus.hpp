/// 2D frictional contact problems in Delassus form, as other codes exchange them, solved
/// by the engine's non-smooth Gauss-Seidel with the same exact local solver
/// (local_solver.hpp). Used to compare the solver with Siconos on its own test data
/// (numerics/src/FrictionContact/test/data/fc2d_granularflowonwall_*.dat in the Siconos
/// repository), which io/siconos.hpp reads and writes.
///
/// The problem: find impulses r and local velocities u = W r + q such that, for each
/// contact a (components 2a normal, 2a+1 tangent), Signorini and Coulomb hold with mu_a.
#pragma once

#include "cdpile/cd/contact_system.hpp"

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <string>

namespace cdpile::cd {

struct DelassusProblem {
  Eigen::SparseMatrix<double, Eigen::RowMajor> W;  ///< 2m x 2m Delassus operator
  Eigen::VectorXd q;                               ///< 2m free local velocities
  Eigen::VectorXd mu;                              ///< m friction coefficients
  Eigen::Index contacts() const { return mu.size(); }
};

/// The problem of a step's contact system (the engine's stage 6, docs/method.md "The
/// scheme"): W = H M^-1 H^T over its rows, with the compliance C = 1/(k h^2) on the
/// diagonal, and q the local velocities less W R of its bodies and impulses, with the gap
/// term and -C R0 (the bodies must hold v = v_free + M^-1 H^T R). One contact per row,
/// in the rows' order; the solvers that factorise the step (admm.hpp) and the export of
/// steps (Engine::delassus_problem) share it.
DelassusProblem delassus_problem(const ContactSystem& s);

/// Siconos' natural-map residual (its fc2d_compute_error; docs/method.md, "Delassus
/// problems from other codes"):
///   || r - Proj_K(r - u_hat) || / ||q||,   u = W r + q,  u_hat = (u_n + mu |u_t|, u_t),
/// K the product of the 2D Coulomb cones. Zero exactly at a solution. The division by
/// ||q|| is what Siconos' fc2d_nsgs passes (it skips it when ||q|| ~ 0).
double natural_map_residual(const DelassusProblem& p, const Eigen::VectorXd& r);

struct NsgsOptions {
  double tolerance = 1e-5;  ///< on natural_map_residual
  int max_sweeps = 10000;
};

struct NsgsReport {
  int sweeps = 0;
  double residual = 0.0;  ///< natural_map_residual at the end
  bool converged = false;
  double seconds = 0.0;  ///< wall-clock time of the solve
};

/// Non-smooth Gauss-Seidel on a Delassus problem, from the initial guess in `r` (resized
/// to 2m and zeroed if it has the wrong size): the engine's own pass (nsgs.hpp,
/// sweep_rows) with the full 2x2 local solve, stopped by Siconos' measure instead of a
/// Criterion of solver.hpp (those measure a ContactSystem's bodies, which a Delassus
/// problem has not). Contacts in file order; the residual is evaluated after every sweep. The velocities u = W r + q are kept current through the
/// sweep (each impulse change added through its 2x2 column blocks of W), so a sweep and
/// its residual cost one pass over W; convergence, and the reported residual, are taken
/// on u recomputed as W r + q.
NsgsReport solve_nsgs(const DelassusProblem& p, Eigen::VectorXd& r, const NsgsOptions& options);

}  // namespace cdpile::cd
