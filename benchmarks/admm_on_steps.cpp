// ADMM (cd::solve_admm, admm.hpp) on steps that export_steps wrote, from each step's warm
// start (step-K.r0), to the engine's tolerance in the engine's maxm scale: iterations,
// factorisations, CPU [ms] split into the setup (the power iteration, the ordering and
// the first factorisation) and the iterations, and the natural-map residual reached
// beside the engine's own impulses' (step-K.r). docs/performance.md, "A factorised solver".
//
// Usage: admm_on_steps [--compliance C] [--rho R] [--tolerance T] [--max N] [--trace K]
//                      [--start FILE] [--save FILE] [--ipm-tolerance T]
//                      [--relaxation A] [--ipm | --ipm-st [--ipm-gamma G] | --warm]
//                      [--polish N | --newton N]
//                      [--prox EPS N [--prox-inner M]
//                       [--prox-fb | --prox-anderson K [--prox-uniform]]]
//                      [--fb N [--fb-smooth X] [--fb-lm THETA]]
//                      [--tnnmg N | --tnnmg-stick N | --tnnmg-law N | --tresca N] [--tnnmg-sweeps K]
//                      [--tnnmg-eps E] [--tnnmg-frozen [--tnnmg-refreeze X]
//                       [--tnnmg-qp-tolerance T] [--tnnmg-shift start|previous|zero]]
//                      [--against-engine] STEP.dat...
//   C: the compliance 1/(k h^2) of the step (the smallest on W's diagonal; 0: rigid);
//   R: the first rho relative to D (default: sqrt(lambda_min lambda_max));
//   --trace K: a line every K iterations;
//   --ipm-tolerance T: the interior point stops at the law's residual T (default: the
//   tolerance), to hand its impulses to --polish;
//   --start FILE: start from the impulses in FILE (2m values) instead of step-K.r0;
//   --save FILE: write the impulses reached there (one file: give one step);
//   --ipm: the interior-point prototype below instead of ADMM; --ipm-st: the interior
//   point on Stewart and Trinkle's LCP (below), gamma of its neighbourhood G (default
//   0.01); --warm: neither (the warm start as it is);
//   --nsgs N: then up to N sweeps of NSGS (cd::solve_nsgs), stopped on the law's residual;
//   --polish N: then up to N active-set Newton iterations (cd::solve_active_set, the
//   engine's --finish-after; with --trace the copy below, which prints each iteration);
//   --polish-proximal EPS [--polish-proximal-iterations N]: its proximal term on singular
//   sets (cd::ActiveSetOptions::proximal, proximal_iterations; default 0: a singular set
//   stops it); --polish-trace: the law's residual after each of its factorisations;
//   --polish-max-changes N: its cap on the statuses a set changes (default 20);
//   --newton N: the same with a line search on the natural map's residual;
//   --prox EPS N [--prox-inner M]: then up to N proximal-point iterations around it, each
//   with at most M (default 30) Newton iterations (below); --prox-fb: those iterations
//   are --fb's; --prox-anderson K: the loop at a fixed eps with Anderson's mixing of
//   depth K (below);
//   --fb N: instead of ADMM, up to N semismooth Newton iterations on Fischer and
//   Burmeister's merit from the warm start (below); --fb-smooth X: |u_t| smoothed;
//   --fb-lm THETA: Levenberg and Marquardt's step instead of Newton's;
//   --tnnmg N, --tnnmg-stick N, --tnnmg-law N, --tresca N: from the warm start, up to N
//   iterations of the truncated nonsmooth Newton below and its variants (K sweeps of
//   Gauss-Seidel each, default 5; eps the regularisation, default 1e-10);
//   --against-engine: seven more columns, the impulses reached beside the engine's
//   (compare() below).
#include "cdpile/analysis/critical.hpp"
#include "cdpile/cd/active_set.hpp"
#include "cdpile/cd/admm.hpp"
#include "cdpile/cd/contact_system.hpp"
#include "cdpile/cd/delassus.hpp"
#include "cdpile/io/siconos.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <exception>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace cd = cdpile::cd;

namespace {

// --ipm: a prototype measured beside ADMM, not a solver of the library (docs/performance.md,
// "A factorised solver": it converges at k = 1e6 m g / D and stalls from 1e7 on). Cold
// start; `r` receives the impulses G^-1 y of the last iterate, strictly inside the cones.
//
// An interior point on the step's contact problem with De Saxce's shift inside the
// iteration (the LCP form of the step, docs/performance.md).
//
// In 2D the Coulomb cone |R_t| <= mu R_n is a polyhedron: with y = G R per contact,
// y1 = mu R_n - R_t and y2 = mu R_n + R_t, R is in the cone exactly when y >= 0, and with
// w = G^-T u~ (u~ = u + (mu |u_t|, 0) the De Saxce velocity, u = W R + q) the dual cone is
// w >= 0 and y.w = R.u~. Writing a = G^-T u, linear in y (a = M y + c, M = G^-T W G^-1),
// the shift is (|a2 - a1| / 2)(1, 1) since a2 - a1 = u_t: the step is the nonlinear
// complementarity problem
//
//     y >= 0,  w = F(y) = M y + c + (|a2 - a1| / 2)(1, 1) >= 0,  y.w = 0,
//
// whose solutions are Signorini and Coulomb's law exactly. Mehrotra's predictor-corrector
// follows its central path y w = sigma mu with the generalised Jacobian of F (the sign of
// u_t in the shift's term), one sparse LU of J + diag(w / y) per iteration.

using Vector = Eigen::VectorXd;

struct IpmOptions {
  double tolerance = 1e-6;      ///< on the law's residual (admm_law_residual's measure)
  double velocity_floor = 1.0;  ///< g h [m/s]
  int max_iterations = 100;
  /// Hold the shift at the start impulses' (|u_t| of W r + q) instead of moving it inside:
  /// the step is then the monotone LCP of research note section 7.
  bool fixed_shift = false;
  /// --ipm-st only: gamma of the wide neighbourhood min z_i w_i >= gamma mean(z w) that
  /// each step keeps (0: none).
  double neighbourhood = 0.01;
  std::function<bool()> cancel;
  /// After every iteration (may be empty): the iteration, the law's residual, the mean
  /// complementarity mu and the largest infeasibility |F(y) - w|.
  std::function<void(int, double, double, double)> on_iteration;
};

struct IpmReport {
  int iterations = 0;  ///< factorisations
  double residual = 0.0;
  bool converged = false;
};

using ColMatrix = Eigen::SparseMatrix<double>;

/// G^-T per contact, the map from velocities to the LCP's w: w1 = u_n / (2 mu) - u_t / 2,
/// w2 = u_n / (2 mu) + u_t / 2. Its transpose, G^-1, maps y to R.
ColMatrix inverse_transpose_of_g(const Vector& mu) {
  std::vector<Eigen::Triplet<double>> t;
  for (Eigen::Index a = 0; a < mu.size(); ++a) {
    const double h = 0.5 / mu[a];
    t.emplace_back(2 * a, 2 * a, h);
    t.emplace_back(2 * a, 2 * a + 1, -0.5);
    t.emplace_back(2 * a + 1, 2 * a, h);
    t.emplace_back(2 * a + 1, 2 * a + 1, 0.5);
  }
  ColMatrix g(2 * mu.size(), 2 * mu.size());
  g.setFromTriplets(t.begin(), t.end());
  return g;
}

/// The step in the LCP's variables: y = G R, a = M y + c (M = G^-T W G^-1, c = G^-T q).
struct LcpForm {
  ColMatrix git;  ///< G^-T
  ColMatrix gi;   ///< G^-1
  ColMatrix m;
  Vector c;
};

LcpForm lcp_form(const cd::DelassusProblem& p) {
  LcpForm f;
  f.git = inverse_transpose_of_g(p.mu);
  f.gi = f.git.transpose();
  const ColMatrix w_matrix = p.W;
  f.m = f.git * w_matrix * f.gi;
  f.c = f.git * p.q;
  return f;
}

/// F(y) from a = M y + c: a + (|a2 - a1| / 2)(1, 1) per contact.
void shifted(const Vector& a, Vector& f) {
  for (Eigen::Index k = 0; k < a.size(); k += 2) {
    const double s = 0.5 * std::abs(a[k + 1] - a[k]);
    f[k] = a[k] + s;
    f[k + 1] = a[k + 1] + s;
  }
}

/// J + diag(d): J = (I + N) M, N per contact (sigma / 2)[[-1, 1], [-1, 1]], sigma the
/// sign of a2 - a1 (u_t), +1 at 0; with delta > 0 the derivative of sqrt(u_t^2 + delta^2)
/// instead (--fb-smooth).
ColMatrix newton_matrix(const ColMatrix& m, const Vector& a, const Vector& d, double delta = 0.0) {
  std::vector<Eigen::Triplet<double>> t;
  for (Eigen::Index k = 0; k < a.size(); k += 2) {
    const double du = a[k + 1] - a[k];
    const double s = delta > 0.0 ? 0.5 * du / std::hypot(du, delta) : du >= 0.0 ? 0.5 : -0.5;
    t.emplace_back(k, k, 1.0 - s);
    t.emplace_back(k, k + 1, s);
    t.emplace_back(k + 1, k, -s);
    t.emplace_back(k + 1, k + 1, 1.0 + s);
  }
  ColMatrix p(a.size(), a.size());
  p.setFromTriplets(t.begin(), t.end());
  ColMatrix j = p * m;
  for (Eigen::Index k = 0; k < a.size(); ++k) j.coeffRef(k, k) += d[k];
  return j;
}

/// The largest step in [0, 1] that keeps v + alpha dv >= 0.
double step_to_boundary(const Vector& v, const Vector& dv) {
  double alpha = 1.0;
  for (Eigen::Index k = 0; k < v.size(); ++k)
    if (dv[k] < 0.0) alpha = std::min(alpha, -v[k] / dv[k]);
  return alpha;
}

IpmReport solve_ipm(const cd::DelassusProblem& p, Vector& r, const IpmOptions& o) {
  IpmReport report;
  const Eigen::Index n = 2 * p.contacts();
  if (n == 0) {
    report.converged = true;
    return report;
  }
  if (!(p.mu.minCoeff() > 0.0)) return report;
  const LcpForm lcp = lcp_form(p);
  const ColMatrix& gi = lcp.gi;
  const ColMatrix& m = lcp.m;
  const Vector& c = lcp.c;
  const ColMatrix w_matrix = p.W;
  // Scales of y (an impulse) and w (a velocity): the start's central point.
  const Vector d_w = w_matrix.diagonal();
  const double w_scale = std::max(o.velocity_floor, 1e-300);
  const double y_scale = w_scale / (d_w.mean() > 0.0 ? d_w.mean() : 1.0);
  // The start: y at the impulse scale, w = F(y) where that is above the velocity scale
  // (the open candidates' gap terms), so that only the loaded contacts start infeasible.
  // The fixed shift, from the impulses given (the warm start): (|u_t| / 2)(1, 1).
  Vector shift0 = Vector::Zero(n);
  if (o.fixed_shift && r.size() == n) {
    const Vector u0 = w_matrix * r + p.q;
    for (Eigen::Index k = 0; k < n; k += 2) shift0[k] = shift0[k + 1] = 0.5 * std::abs(u0[k + 1]);
  }
  auto residual_of = [&](const Vector& av, Vector& fv) {
    if (o.fixed_shift)
      fv = av + shift0;
    else
      shifted(av, fv);
  };
  Vector y = Vector::Constant(n, y_scale);
  Vector a(n), f(n), rd(n), rhs(n), dy(n), dw(n), dya(n), dwa(n), rc(n);
  a = m * y + c;
  residual_of(a, f);
  Vector w = f.cwiseMax(w_scale);
  Eigen::SparseLU<ColMatrix, Eigen::COLAMDOrdering<int>> lu;
  for (int k = 1; k <= o.max_iterations; ++k) {
    if (o.cancel && o.cancel()) throw cd::StepCancelled();
    const double mu = y.dot(w) / static_cast<double>(n);
    a = m * y + c;
    residual_of(a, f);
    rd = f - w;
    if (o.fixed_shift) {
      ColMatrix j = m;
      const Vector d = w.cwiseQuotient(y);
      for (Eigen::Index i = 0; i < n; ++i) j.coeffRef(i, i) += d[i];
      lu.compute(j);
    } else {
      lu.compute(newton_matrix(m, a, w.cwiseQuotient(y)));
    }
    if (lu.info() != Eigen::Success) break;
    report.iterations = k;
    // Predictor: the affine step to y w = 0.
    rhs = -rd - w;
    dya = lu.solve(rhs);
    dwa = -w - w.cwiseQuotient(y).cwiseProduct(dya);
    const double alpha_a = std::min(step_to_boundary(y, dya), step_to_boundary(w, dwa));
    const double mu_affine = (y + alpha_a * dya).dot(w + alpha_a * dwa) / static_cast<double>(n);
    const double sigma = std::pow(mu_affine / mu, 3.0);
    // Corrector: centred, with the second-order term of the affine step.
    rc = y.cwiseProduct(w) + dya.cwiseProduct(dwa) - Vector::Constant(n, sigma * mu);
    rhs = -rd - rc.cwiseQuotient(y);
    dy = lu.solve(rhs);
    dw = -(rc + w.cwiseProduct(dy)).cwiseQuotient(y);
    const double alpha =
        std::min(1.0, 0.99 * std::min(step_to_boundary(y, dy), step_to_boundary(w, dw)));
    y += alpha * dy;
    w += alpha * dw;
    const Vector impulses = gi * y;
    report.residual = cd::admm_law_residual(p, impulses, o.velocity_floor);
    if (o.on_iteration) o.on_iteration(k, report.residual, mu, rd.lpNorm<Eigen::Infinity>());
    if (report.residual <= o.tolerance) {
      report.converged = true;
      break;
    }
  }
  r = gi * y;
  return report;
}

// --ipm-st: the interior point on the step as Stewart and Trinkle's LCP (Stewart and
// Trinkle 1996; in 2D with the two tangent directions +t and -t it is Coulomb's law
// exactly, not a faceted cone), in place of De Saxce's shift. Per contact four unknowns
// z = (R_n, b1, b2, lambda) >= 0, R_t = b1 - b2, lambda a sliding speed, and
//
//     w_n  = u_n                    >= 0,  R_n    w_n  = 0   (Signorini)
//     w_b1 = lambda + u_t           >= 0,  b1     w_b1 = 0
//     w_b2 = lambda - u_t           >= 0,  b2     w_b2 = 0
//     w_l  = mu R_n - b1 - b2       >= 0,  lambda w_l  = 0   (the cone)
//
// with u = W R + q: a sliding contact has lambda = |u_t| > 0, so b1 + b2 = mu R_n and the
// b on the side of the motion is 0 (R_t = -sign(u_t) mu R_n); a sticking one has
// lambda = 0 and u_t = 0. The |u_t| whose kink held the shifted form at the sticking
// contacts (the --ipm prototype above) is a variable here, and its complementarity is
// strict there (lambda = 0, w_l > 0 inside the cone). The price: w = M z + c with
// M = E^T W E + L, L the local coupling of lambda, not monotone (its mu R_n entry), so
// the central path is not guaranteed; measured, not proved. One sparse LU of
// M + diag(w / z) an iteration, 4 m unknowns.
struct StForm {
  ColMatrix e;  ///< R = E z (2m x 4m)
  ColMatrix m;  ///< E^T W E + L
  Vector c;     ///< E^T q
};

StForm st_form(const cd::DelassusProblem& p) {
  const Eigen::Index nc = p.contacts();
  std::vector<Eigen::Triplet<double>> t;
  for (Eigen::Index a = 0; a < nc; ++a) {
    t.emplace_back(2 * a, 4 * a, 1.0);
    t.emplace_back(2 * a + 1, 4 * a + 1, 1.0);
    t.emplace_back(2 * a + 1, 4 * a + 2, -1.0);
  }
  StForm f;
  f.e.resize(2 * nc, 4 * nc);
  f.e.setFromTriplets(t.begin(), t.end());
  t.clear();
  for (Eigen::Index a = 0; a < nc; ++a) {
    t.emplace_back(4 * a + 1, 4 * a + 3, 1.0);
    t.emplace_back(4 * a + 2, 4 * a + 3, 1.0);
    t.emplace_back(4 * a + 3, 4 * a, p.mu[a]);
    t.emplace_back(4 * a + 3, 4 * a + 1, -1.0);
    t.emplace_back(4 * a + 3, 4 * a + 2, -1.0);
    for (int i = 0; i < 4; ++i) t.emplace_back(4 * a + i, 4 * a + i, 0.0);  // room for diag(w / z)
  }
  ColMatrix l(4 * nc, 4 * nc);
  l.setFromTriplets(t.begin(), t.end());
  const ColMatrix w_matrix = p.W;
  const ColMatrix et = f.e.transpose();
  f.m = et * w_matrix * f.e + l;
  f.c = et * p.q;
  return f;
}

/// x = J^-1 b with two rounds of iterative refinement: near the solution diag(w / z) spans
/// twenty orders of magnitude and one LU solve alone loses the last digits the step needs.
template <class Lu>
Vector refined_solve(const Lu& lu, const ColMatrix& j, const Vector& b) {
  Vector x = lu.solve(b);
  for (int i = 0; i < 2; ++i) x += lu.solve(b - j * x);
  return x;
}

IpmReport solve_ipm_st(const cd::DelassusProblem& p, Vector& r, const IpmOptions& o) {
  IpmReport report;
  const Eigen::Index nc = p.contacts();
  const Eigen::Index n = 4 * nc;
  if (nc == 0) {
    report.converged = true;
    return report;
  }
  StForm st = st_form(p);
  const ColMatrix w_matrix = p.W;
  const Vector d_w = w_matrix.diagonal();
  const double v_scale = std::max(o.velocity_floor, 1e-300);
  const double i_scale = v_scale / (d_w.mean() > 0.0 ? d_w.mean() : 1.0);
  // z's and w's units per row: impulse and velocity, but lambda a velocity and w_l an
  // impulse. The iteration runs on z / s_z and w / s_w, all of order one, so that the
  // LU's pivots compare like with like: M' = S_w^-1 M S_z, c' = S_w^-1 c, E' = E S_z.
  Vector s_z(n), s_w(n);
  for (Eigen::Index a = 0; a < nc; ++a) {
    s_z.segment<4>(4 * a) << i_scale, i_scale, i_scale, v_scale;
    s_w.segment<4>(4 * a) << v_scale, v_scale, v_scale, i_scale;
  }
  st.m = s_w.cwiseInverse().asDiagonal() * st.m * s_z.asDiagonal();
  st.c = st.c.cwiseQuotient(s_w);
  st.e = st.e * s_z.asDiagonal();
  Vector z = Vector::Ones(n), floor_w = Vector::Ones(n);
  Vector w = (st.m * z + st.c).cwiseMax(floor_w);
  Vector rd(n), rhs(n), dz(n), dw(n), dza(n), dwa(n), rc(n);
  Eigen::SparseLU<ColMatrix, Eigen::COLAMDOrdering<int>> lu;
  bool analysed = false;
  for (int k = 1; k <= o.max_iterations; ++k) {
    if (o.cancel && o.cancel()) throw cd::StepCancelled();
    const double mu = z.dot(w) / static_cast<double>(n);
    rd = st.m * z + st.c - w;
    ColMatrix j = st.m;
    const Vector d = w.cwiseQuotient(z);
    for (Eigen::Index i = 0; i < n; ++i) j.coeffRef(i, i) += d[i];
    j.makeCompressed();
    if (!analysed) {
      lu.analyzePattern(j);
      analysed = true;
    }
    lu.factorize(j);
    if (lu.info() != Eigen::Success) break;
    report.iterations = k;
    rhs = -rd - w;
    dza = refined_solve(lu, j, rhs);
    dwa = -w - d.cwiseProduct(dza);
    const double alpha_a = std::min(step_to_boundary(z, dza), step_to_boundary(w, dwa));
    const double mu_affine = (z + alpha_a * dza).dot(w + alpha_a * dwa) / static_cast<double>(n);
    const double sigma = std::pow(mu_affine / mu, 3.0);
    rc = z.cwiseProduct(w) + dza.cwiseProduct(dwa) - Vector::Constant(n, sigma * mu);
    rhs = -rd - rc.cwiseQuotient(z);
    dz = refined_solve(lu, j, rhs);
    dw = -(rc + w.cwiseProduct(dz)).cwiseQuotient(z);
    double alpha =
        std::min(1.0, 0.99 * std::min(step_to_boundary(z, dz), step_to_boundary(w, dw)));
    // M is not monotone, so dz.dw can be negative and the complementarity fall faster than
    // the infeasibility, which falls by exactly (1 - alpha) (the step solves the linear
    // equations): the iterates then stall on the boundary, infeasible. Keep
    // mu(alpha) >= (1 - alpha) mu, mu(alpha) = mu + alpha b + alpha^2 a (Wright 1997,
    // ch. 6: the infeasibility may not outrun the complementarity).
    const double qa = dz.dot(dw) / static_cast<double>(n);
    const double qb = (z.dot(dw) + w.dot(dz)) / static_cast<double>(n);
    if (qa < 0.0 && qb + mu > 0.0) alpha = std::min(alpha, -0.99 * (qb + mu) / qa);
    // And a wide neighbourhood of the central path, min z_i w_i >= gamma mu (Wright 1997,
    // ch. 5): no pair may reach its boundary long before the others.
    if (o.neighbourhood > 0.0)
      for (int b = 0; b < 60; ++b) {
        const Vector zt = z + alpha * dz, wt = w + alpha * dw;
        const Vector zw = zt.cwiseProduct(wt);
        if (zw.minCoeff() >= o.neighbourhood * zw.mean()) break;
        alpha *= 0.8;
      }
    z += alpha * dz;
    w += alpha * dw;
    const Vector impulses = st.e * z;
    report.residual = cd::admm_law_residual(p, impulses, o.velocity_floor);
    if (o.on_iteration) o.on_iteration(k, report.residual, mu, rd.lpNorm<Eigen::Infinity>());
    if (report.residual <= o.tolerance) {
      report.converged = true;
      break;
    }
  }
  r = st.e * z;
  return report;
}

// --fb N: a semismooth Newton on Fischer and Burmeister's reformulation of the step's
// nonlinear complementarity problem (the --ipm form above, De Saxce's shift inside):
//
//     Phi_i(y) = phi(s_i y_i, F_i(y)),  phi(a, b) = sqrt(a^2 + b^2) - a - b,
//
// zero exactly where y >= 0, F(y) >= 0, y.F(y) = 0; s_i = M_ii puts y in velocity units.
// Unlike the natural map's, the merit Psi = |Phi|^2 / 2 is descended by the Newton step
// wherever Phi is differentiable (Psi'(d) = -|Phi|^2), so an Armijo search on Psi
// globalises it (Facchinei and Pang 2003, ch. 9); the shift's kink at u_t = 0 does not
// change the Newton system at a sticking contact (u = 0 on either side). Warm-started
// from the impulses given: y = G r. One sparse LU of diag(Da s) + diag(Db) J_F per
// iteration; the gradient -H^T Phi where the Newton step is not a descent.
IpmReport solve_fb(const cd::DelassusProblem& p, Vector& r, int max_iterations, double tolerance,
                   double velocity_floor, int trace, double smoothing, double levenberg = 0.0) {
  IpmReport report;
  const Eigen::Index n = 2 * p.contacts();
  if (n == 0 || !(p.mu.minCoeff() > 0.0)) return report;
  const LcpForm lcp = lcp_form(p);
  const ColMatrix& gi = lcp.gi;
  const ColMatrix& m = lcp.m;
  const Vector& c = lcp.c;
  const Vector s = m.diagonal();
  // y = G r: G = (G^-1)^-1 per contact, y1 = mu R_n - R_t, y2 = mu R_n + R_t.
  Vector y(n);
  for (Eigen::Index a = 0; a < p.contacts(); ++a) {
    y[2 * a] = p.mu[a] * r[2 * a] - r[2 * a + 1];
    y[2 * a + 1] = p.mu[a] * r[2 * a] + r[2 * a + 1];
  }
  Vector f(n), phi(n), da(n), db(n);
  // --fb-smooth X: |u_t| replaced by sqrt(u_t^2 + delta^2), delta = X times the largest
  // |Phi| (velocity units), never growing: a smoothing Newton whose F is differentiable.
  double delta = 0.0;
  auto evaluate = [&](const Vector& yv, Vector& phiv) {
    const Vector av = m * yv + c;
    for (Eigen::Index k = 0; k < n; k += 2) {
      const double sh = 0.5 * std::hypot(av[k + 1] - av[k], delta);
      f[k] = av[k] + sh;
      f[k + 1] = av[k + 1] + sh;
    }
    for (Eigen::Index i = 0; i < n; ++i) {
      const double x = s[i] * yv[i];
      phiv[i] = std::hypot(x, f[i]) - x - f[i];
    }
    return av;
  };
  Vector a = evaluate(y, phi);
  if (smoothing > 0.0) {
    delta = smoothing * phi.lpNorm<Eigen::Infinity>();
    a = evaluate(y, phi);
  }
  double psi = 0.5 * phi.squaredNorm();
  Eigen::SparseLU<ColMatrix, Eigen::COLAMDOrdering<int>> lu;
  Eigen::SimplicialLDLT<ColMatrix> ldlt;
  double phi0 = -1.0;
  int gradient_steps = 0;
  for (int k = 1; k <= max_iterations; ++k) {
    report.residual = cd::admm_law_residual(p, gi * y, velocity_floor);
    if (report.residual <= tolerance) {
      report.converged = true;
      break;
    }
    for (Eigen::Index i = 0; i < n; ++i) {
      const double x = s[i] * y[i];
      const double norm = std::hypot(x, f[i]);
      if (norm > 1e-300) {
        da[i] = x / norm - 1.0;
        db[i] = f[i] / norm - 1.0;
      } else {
        da[i] = db[i] = std::sqrt(0.5) - 1.0;
      }
    }
    ColMatrix h = db.asDiagonal() * newton_matrix(m, a, Vector::Zero(n), delta);
    for (Eigen::Index i = 0; i < n; ++i) h.coeffRef(i, i) += da[i] * s[i];
    report.iterations = k;
    Vector d;
    const Vector gradient = h.transpose() * phi;
    if (levenberg > 0.0) {
      // --fb-lm THETA: Levenberg and Marquardt's step (H^T H + lambda I) d = -H^T Phi,
      // lambda = THETA mean(diag H^T H) (|Phi| / |Phi_0|)^2 (Yamashita and Fukushima's
      // lambda ~ |Phi|^2: quadratic near a solution under an error bound, without a
      // nonsingular Jacobian), a descent direction of the merit wherever Phi is
      // differentiable.
      ColMatrix normal = ColMatrix(h.transpose()) * h;
      if (phi0 < 0.0) phi0 = phi.norm();
      const double ratio = phi.norm() / phi0;
      const double lambda = levenberg * normal.diagonal().mean() * std::min(1.0, ratio * ratio);
      for (Eigen::Index i = 0; i < n; ++i) normal.coeffRef(i, i) += lambda;
      ldlt.compute(normal);
      if (ldlt.info() == Eigen::Success) d = ldlt.solve(-gradient);
    } else {
      lu.compute(h);
      if (lu.info() == Eigen::Success) d = lu.solve(-phi);
    }
    bool newton = d.size() == n && d.allFinite() && gradient.dot(d) < -1e-12 * gradient.norm() * d.norm();
    if (!newton) {
      d = -gradient;
      ++gradient_steps;
    }
    const double slope = gradient.dot(d);
    double t = 1.0;
    Vector trial = y + d, phi_trial(n);
    Vector a_trial = evaluate(trial, phi_trial);
    while (0.5 * phi_trial.squaredNorm() > psi + 1e-4 * t * slope && t > 1e-12) {
      t *= 0.5;
      trial = y + t * d;
      a_trial = evaluate(trial, phi_trial);
    }
    y = trial;
    phi = phi_trial;
    a = a_trial;
    if (smoothing > 0.0) {
      delta = std::min(delta, smoothing * phi.lpNorm<Eigen::Infinity>());
      a = evaluate(y, phi);
    }
    psi = 0.5 * phi.squaredNorm();
    if (trace > 0 && k % trace == 0)
      std::printf("  fb %4d: %s step %.3e psi %.3e law %.3e\n", k, newton ? "newton" : "gradient", t, psi,
                  cd::admm_law_residual(p, gi * y, velocity_floor));
  }
  r = gi * y;
  report.residual = cd::admm_law_residual(p, r, velocity_floor);
  report.converged = report.residual <= tolerance;
  if (trace > 0) std::printf("  fb: %d gradient steps\n", gradient_steps);
  return report;
}

// --polish N: active-set Newton after the method (or from the warm start alone): the
// semismooth Newton of Alart and Curnier's formulation with unit steps. Each contact's
// status comes from the law's projection with rho = 1 / W_aa (open when R_n - rho u_n <= 0;
// else stick when |R_t - rho u_t| <= mu (R_n - rho u_n), else sliding at the bound on the
// side of R_t - rho u_t); on a fixed set of statuses the law is linear and De Saxce's
// shift drops out (open: R = 0; stick: u = 0; sliding: u_n = 0, R_t = s mu R_n), so one
// sparse LU gives that set's solution. Stops when the statuses repeat, or after N.

struct PolishReport {
  int iterations = 0;  ///< factorisations
  int changed = 0;     ///< statuses changed by the last iteration
  double residual = 0.0;
  bool converged = false;
};

PolishReport polish(const cd::DelassusProblem& p, Vector& r, int max_iterations, double tolerance,
                    double velocity_floor, int trace, bool damped = false) {
  PolishReport report;
  const Eigen::Index n = 2 * p.contacts();
  if (n == 0) return report;
  std::vector<cd::LawStatus> previous;
  bool full_step = true;  // statuses that repeat after a shortened step do not end the Newton
  Eigen::SparseLU<ColMatrix, Eigen::COLAMDOrdering<int>> lu;
  for (int k = 1; k <= max_iterations; ++k) {
    const std::vector<cd::LawStatus> st = cd::law_statuses(p, r);
    report.changed = 0;
    if (!previous.empty())
      for (std::size_t a = 0; a < st.size(); ++a) report.changed += st[a] != previous[a] ? 1 : 0;
    report.residual = cd::admm_law_residual(p, r, velocity_floor);
    if ((!previous.empty() && report.changed == 0 && full_step) || (damped && report.residual <= tolerance)) {
      report.converged = report.residual <= tolerance;
      break;
    }
    ColMatrix a_matrix;
    Vector b;
    cd::status_system(p, st, a_matrix, b);
    lu.compute(a_matrix);
    if (lu.info() != Eigen::Success) {
      std::printf("  polish %d: the LU failed\n", k);
      break;
    }
    if (damped) {
      // --newton: the step to the set's solution shortened until the natural map's
      // residual falls (Armijo on ||r - Proj(r - u_hat)||; a last 1/1024 step is taken as is).
      const Vector full = lu.solve(b);
      const Vector d = full - r;
      const double m0 = cd::natural_map_residual(p, r);
      double step = 1.0;
      Vector trial = full;
      while (step > 1.0 / 1024 && cd::natural_map_residual(p, trial) > (1.0 - 1e-4 * step) * m0) {
        step *= 0.5;
        trial = r + step * d;
      }
      r = trial;
      if (trace > 0) std::printf("  newton %3d: step %.4f\n", k, step);
      full_step = step == 1.0;
    } else {
      r = lu.solve(b);
    }
    report.iterations = k;
    previous = st;
    if (trace > 0) {
      int counts[4] = {0, 0, 0, 0};
      for (cd::LawStatus s : st) ++counts[static_cast<int>(s)];
      std::printf("  polish %3d: changed %d, open %d stick %d slip %d, law before %.3e after %.3e\n", k,
                  report.changed, counts[0], counts[1], counts[2] + counts[3], report.residual,
                  cd::admm_law_residual(p, r, velocity_floor));
    }
  }
  report.residual = cd::admm_law_residual(p, r, velocity_floor);
  return report;
}

// --prox EPS N: the active-set Newton inside a proximal-point loop (Acary, Bremond and
// Huber 2018's proximal point with a nonsmooth Newton inside; solvers.md section 7). Each
// outer iteration solves the step with u replaced by u + eps D (R - R_k), D = diag(W),
// R_k the previous outer iterate: the same law on W + eps D, strongly monotone and better
// conditioned the larger eps, whose solution is R_k's proximal point. At a fixed point
// R = R_k the term vanishes and R solves the step. The inner Newton starts from R_k, and
// eps is halved after an outer iteration whose inner Newton settled, doubled after one
// that did not (the inner iterate is then kept only if the law's residual fell).
PolishReport proximal_newton(const cd::DelassusProblem& p, Vector& r, double eps, int max_outer,
                             int max_inner, double tolerance, double velocity_floor, int trace,
                             bool fb_inner = false) {
  PolishReport report;
  if (p.contacts() == 0) return report;
  const Vector d = p.W.diagonal();
  double law = cd::admm_law_residual(p, r, velocity_floor);
  for (int k = 1; k <= max_outer && law > tolerance; ++k) {
    cd::DelassusProblem sub = p;
    for (Eigen::Index i = 0; i < sub.W.rows(); ++i) sub.W.coeffRef(i, i) += eps * d[i];
    sub.q = p.q - eps * d.cwiseProduct(r);
    Vector trial = r;
    PolishReport inner;
    if (fb_inner) {
      // --prox-fb: the inner solve is the Fischer-Burmeister Newton (solve_fb), settled
      // when it meets the tolerance on the proximal problem.
      const IpmReport i = solve_fb(sub, trial, max_inner, tolerance, velocity_floor, 0, 0.0);
      inner.iterations = i.iterations;
      inner.changed = i.converged ? 0 : 1;
    } else {
      inner = polish(sub, trial, max_inner, 0.0, velocity_floor, 0);
    }
    report.iterations += inner.iterations;
    const bool settled = inner.changed == 0 && inner.iterations < max_inner;
    const double trial_law = cd::admm_law_residual(p, trial, velocity_floor);
    if (trace > 0)
      std::printf("  prox %3d: eps %.3e inner %d (changed %d) law %.3e -> %.3e\n", k, eps, inner.iterations,
                  inner.changed, law, trial_law);
    if (settled || trial_law < law) {
      r = trial;
      law = trial_law;
    }
    eps = settled ? eps * 0.5 : eps * 2.0;
  }
  report.residual = law;
  report.converged = law <= tolerance;
  return report;
}

// --prox-anderson M: the proximal loop above at a fixed eps, its outer iteration
// x -> T(x) (T(x): the active-set Newton's solution of the proximal problem around x)
// accelerated by Anderson's mixing of depth M (type II, Walker and Ni 2011). Near the
// solution the statuses hold and T is affine; its slow part is the self-stress states
// (null space of H^T), on which W = C I, so T contracts them by eps d / (C + eps d): a
// tight cluster of rates that a short mixing removes. --prox-uniform: d = mean(diag W)
// for every row, which makes that cluster one rate. eps doubles, and the history is
// dropped, after an outer iteration whose Newton did not settle or whose residual grew
// tenfold.
PolishReport anderson_proximal(const cd::DelassusProblem& p, Vector& r, double eps, int max_outer,
                               int max_inner, int depth, bool uniform, double tolerance,
                               double velocity_floor, int trace) {
  PolishReport report;
  if (p.contacts() == 0) return report;
  const Eigen::Index n = 2 * p.contacts();
  Vector d = p.W.diagonal();
  if (uniform) d = Vector::Constant(n, d.mean());
  Vector x = r;
  std::vector<Vector> xs, fs;
  double best = cd::admm_law_residual(p, r, velocity_floor);
  double smallest_f = std::numeric_limits<double>::infinity();
  for (int k = 1; k <= max_outer && best > tolerance; ++k) {
    cd::DelassusProblem sub = p;
    for (Eigen::Index i = 0; i < n; ++i) sub.W.coeffRef(i, i) += eps * d[i];
    sub.q = p.q - eps * d.cwiseProduct(x);
    Vector tx = x;
    const PolishReport inner = polish(sub, tx, max_inner, 0.0, velocity_floor, 0);
    report.iterations += inner.iterations;
    const bool settled = inner.changed == 0 && inner.iterations < max_inner;
    const double law = cd::admm_law_residual(p, tx, velocity_floor);
    const Vector f = tx - x;
    const double fn = f.norm();
    if (trace > 0)
      std::printf("  anderson %3d: eps %.3e inner %d (changed %d) history %zu law %.3e |f| %.3e\n", k, eps,
                  inner.iterations, inner.changed, fs.size(), law, fn);
    if (settled && law < best) {
      best = law;
      r = tx;
    }
    if (!settled || fn > 10.0 * smallest_f) {
      if (!settled) eps *= 2.0;
      xs.clear();
      fs.clear();
      smallest_f = std::numeric_limits<double>::infinity();
      if (!settled) continue;
    }
    smallest_f = std::min(smallest_f, fn);
    xs.push_back(x);
    fs.push_back(f);
    if (static_cast<int>(fs.size()) > depth + 1) {
      xs.erase(xs.begin());
      fs.erase(fs.begin());
    }
    if (fs.size() >= 2) {
      const Eigen::Index m = static_cast<Eigen::Index>(fs.size()) - 1;
      Eigen::MatrixXd df(n, m), dx(n, m);
      for (Eigen::Index j = 0; j < m; ++j) {
        df.col(j) = fs[static_cast<std::size_t>(j + 1)] - fs[static_cast<std::size_t>(j)];
        dx.col(j) = xs[static_cast<std::size_t>(j + 1)] - xs[static_cast<std::size_t>(j)];
      }
      const Eigen::VectorXd gamma = df.colPivHouseholderQr().solve(f);
      x = tx - (dx + df) * gamma;
    } else {
      x = tx;
    }
  }
  report.residual = best;
  report.converged = best <= tolerance;
  return report;
}

// One sweep of block Gauss-Seidel on the QP  min x.A x / 2 + rhs.x  over lo <= x <= hi
// (A given by its rows, 2x2 blocks per contact): each block's box QP solved exactly, its
// minimiser being the interior one or the clipped 1D minimiser on one of its faces.
// --tnnmg-frozen (y >= 0) and --tresca (R_n >= 0, |R_t| <= g) use it.
void block_box_sweep(const Eigen::SparseMatrix<double, Eigen::RowMajor>& rows, const Vector& rhs, const Vector& lo,
                     const Vector& hi, Vector& x) {
  for (Eigen::Index i = 0; i < x.size(); i += 2) {
    double g[2], b[2][2] = {{0, 0}, {0, 0}};
    for (int l = 0; l < 2; ++l) {
      double sum = rhs[i + l];
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(rows, i + l); it; ++it) {
        sum += it.value() * x[it.col()];
        if (it.col() == i || it.col() == i + 1) b[l][it.col() - i] = it.value();
      }
      g[l] = sum;
    }
    const double z0[2] = {x[i], x[i + 1]};
    auto local_e = [&](double z1, double z2) {
      const double d1 = z1 - z0[0], d2 = z2 - z0[1];
      return g[0] * d1 + g[1] * d2 + 0.5 * (b[0][0] * d1 * d1 + 2 * b[0][1] * d1 * d2 + b[1][1] * d2 * d2);
    };
    // the 1D minimiser of component l with the other at `other`, clipped to its bounds
    auto along = [&](int l, double other) {
      const int o = 1 - l;
      const double z = z0[l] - (g[l] + b[l][o] * (other - z0[o])) / b[l][l];
      return std::clamp(z, lo[i + l], hi[i + l]);
    };
    double best_e = std::numeric_limits<double>::infinity(), z1 = z0[0], z2 = z0[1];
    auto consider = [&](double c1, double c2) {
      const double e = local_e(c1, c2);
      if (e < best_e) best_e = e, z1 = c1, z2 = c2;
    };
    const double det = b[0][0] * b[1][1] - b[0][1] * b[1][0];
    if (det > 0.0) {
      const double c1 = z0[0] - (b[1][1] * g[0] - b[0][1] * g[1]) / det;
      const double c2 = z0[1] - (b[0][0] * g[1] - b[1][0] * g[0]) / det;
      if (c1 >= lo[i] && c1 <= hi[i] && c2 >= lo[i + 1] && c2 <= hi[i + 1]) consider(c1, c2);
    }
    for (int l = 0; l < 2; ++l)
      for (const double bound : {lo[i + l], hi[i + l]}) {
        if (!std::isfinite(bound)) continue;
        const int o = 1 - l;
        const double other = along(o, bound);
        l == 0 ? consider(bound, other) : consider(other, bound);
      }
    x[i] = z1;
    x[i + 1] = z2;
  }
}

// The projected arc x(alpha) = project(x + alpha v), alpha = 1, 1/2, ..., 1/1024, of the
// --tnnmg variants: moves x to the arc's point of least merit if it is below merit(x) and
// returns its alpha (0: x kept). With stop_when_rising, the search ends at the first alpha
// whose merit no longer falls after a fall (the energies' searches); without, every alpha
// is tried (the law residual's, which is not monotone along the arc).
template <class Project, class Merit>
double least_on_arc(Vector& x, const Vector& v, Project project, Merit merit, bool stop_when_rising) {
  double best = merit(x), alpha = 0.0;
  Vector trial(x.size()), best_x;
  for (double step = 1.0; step >= 1.0 / 1024; step *= 0.5) {
    trial = x + step * v;
    project(trial);
    const double e = merit(trial);
    if (e < best) {
      best = e;
      alpha = step;
      best_x = trial;
    } else if (stop_when_rising && alpha > 0.0) {
      break;
    }
  }
  if (alpha > 0.0) x = best_x;
  return alpha;
}

// The truncated system of --tnnmg and --tnnmg-stick: m's values with the held rows and
// columns made the identity's and eps times m's diagonal added on the rest, into `out`,
// which has m's compressed pattern (so one analysis serves every iteration).
void truncated_matrix(const ColMatrix& m, const std::vector<char>& held, double eps, ColMatrix& out) {
  for (Eigen::Index c = 0; c < m.outerSize(); ++c)
    for (Eigen::Index q = m.outerIndexPtr()[c]; q < m.outerIndexPtr()[c + 1]; ++q) {
      const Eigen::Index row = m.innerIndexPtr()[q];
      double value = m.valuePtr()[q];
      if (held[row] || held[c]) value = row == c ? 1.0 : 0.0;
      else if (row == c) value += eps * value;
      out.valuePtr()[q] = value;
    }
}

// --tnnmg N: a truncated nonsmooth Newton in the manner of Graser and Kornhuber's TNNMG
// (Graser, Sack and Sander 2009; research note section 6), a direct solve in place of the
// multigrid (docs/performance.md, "A truncated nonsmooth Newton"). Each iteration:
//   1. K sweeps of the engine's exact Coulomb Gauss-Seidel (cd::solve_nsgs; the smoother);
//   2. De Saxce's shift s = mu |u_t| frozen at the impulses reached, which makes the step
//      the convex QP  min E(y) = y.M y / 2 + c_s.y  over y >= 0  (the LCP form above,
//      y = G R, c_s = G^-T (q + (s, 0)));
//   3. the truncation: the components at their bound (y_i = 0: an open contact's two, a
//      sliding contact's one) are held, and the linear correction M_FF v_F = -grad_F E
//      solved on the rest with one numeric factorisation (SimplicialLDLT, pattern analysed
//      once; eps times M's diagonal added, which keeps a rigid hyperstatic set regular);
//   4. of the projected arc max(0, y + alpha v), alpha = 1, 1/2, ..., 1/1024 (Bertsekas'
//      projected Newton), the point of least E.
// Step 4 never raises E, so with the shift frozen it is a descent method whose smoother
// alone converges; the shift moves between iterations (step 2 again), which no theorem
// covers. Stops on the law's residual.
// --tnnmg-frozen: the shift frozen at the start's instead, the smoother then block
// Gauss-Seidel on that QP (each contact's 2x2 bound-constrained QP solved exactly): the
// QP alone, stopped when its projected gradient has fallen by --tnnmg-qp-tolerance (1e-8)
// from the first iteration's; --tnnmg-refreeze X (0: never) moves the shift to the
// current velocity each time that residual has fallen by X since the last move (an
// outer fixed point on the shift, each QP solved to X). --tnnmg-shift previous freezes it
// at the previous step's |u_t| (step-K.ut0: the law lagged by a step), zero at 0 (the
// associated law, no shift), start at the start's (the default).
PolishReport tnnmg(const cd::DelassusProblem& p, Vector& r, int max_iterations, int sweeps, double eps,
                   double tolerance, double velocity_floor, int trace, int& sweeps_done, bool frozen,
                   double refreeze_ratio, double qp_tolerance, const Vector* frozen_speed) {
  PolishReport report;
  const Eigen::Index n = 2 * p.contacts();
  if (n == 0) return report;
  const LcpForm f = lcp_form(p);
  // G per contact: y1 = mu R_n - R_t, y2 = mu R_n + R_t.
  auto to_y = [&](const Vector& rr, Vector& y) {
    for (Eigen::Index a = 0; a < p.contacts(); ++a) {
      y[2 * a] = p.mu[a] * rr[2 * a] - rr[2 * a + 1];
      y[2 * a + 1] = p.mu[a] * rr[2 * a] + rr[2 * a + 1];
    }
  };
  ColMatrix a_matrix = f.m;  // M's pattern, values set each iteration
  a_matrix.makeCompressed();
  Eigen::SimplicialLDLT<ColMatrix, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt;
  ldlt.analyzePattern(a_matrix);
  const Vector diag = f.m.diagonal();
  Vector y(n), a(n), grad(n), v(n), mv(n);
  std::vector<char> held(n);
  cd::NsgsOptions no;
  no.tolerance = 1e-300;
  no.max_sweeps = sweeps;
  sweeps_done = 0;
  // --tnnmg-frozen: the shift held at the start's for the whole solve (the QP alone), the
  // smoother then block Gauss-Seidel on that QP (each contact's 2x2 bound-constrained QP exact).
  const Eigen::SparseMatrix<double, Eigen::RowMajor> m_rows = f.m;
  Vector frozen_shift(n);
  {
    to_y(r, y);
    a = f.m * y + f.c;
    for (Eigen::Index i = 0; i < n; i += 2) frozen_shift[i] = frozen_shift[i + 1] = 0.5 * std::abs(a[i + 1] - a[i]);
    // --tnnmg-shift previous or zero: the shift frozen at given speeds |u_t| instead
    if (frozen_speed)
      for (Eigen::Index c = 0; c < p.contacts(); ++c) frozen_shift[2 * c] = frozen_shift[2 * c + 1] = 0.5 * (*frozen_speed)[c];
  }
  const Vector zero = Vector::Zero(n), unbounded = Vector::Constant(n, std::numeric_limits<double>::infinity());
  auto qp_sweep = [&]() { block_box_sweep(m_rows, f.c + frozen_shift, zero, unbounded, y); };
  double qp_first = -1.0, qp_start = -1.0;
  int refreezes = 0;
  for (int k = 1; k <= max_iterations; ++k) {
    if (frozen) {
      to_y(r, y);
      for (Eigen::Index i = 0; i < n; ++i) y[i] = std::max(0.0, y[i]);
      for (int sw = 0; sw < sweeps; ++sw) qp_sweep();
      sweeps_done += sweeps;
      r = f.gi * y;
    } else if (sweeps > 0) {
      cd::solve_nsgs(p, r, no);
      sweeps_done += sweeps;
    }
    report.residual = cd::admm_law_residual(p, r, velocity_floor);
    if (report.residual <= tolerance) {
      report.converged = true;
      break;
    }
    to_y(r, y);
    a = f.m * y + f.c;
    int n_held = 0;
    double qp_residual = 0.0;  // with the shift frozen: the projected gradient's largest
    for (Eigen::Index i = 0; i < n; i += 2) {
      const double s = frozen ? frozen_shift[i] : 0.5 * std::abs(a[i + 1] - a[i]);  // (mu |u_t|, 0) in y's coordinates
      grad[i] = a[i] + s;
      grad[i + 1] = a[i + 1] + s;
      const double scale = std::abs(y[i]) + std::abs(y[i + 1]);
      for (Eigen::Index j = i; j < i + 2; ++j) {
        if (y[j] < 0.0) y[j] = 0.0;
        held[j] = y[j] <= 1e-12 * scale || scale == 0.0 ? 1 : 0;
        n_held += held[j];
        qp_residual = std::max(qp_residual, std::abs(y[j] - std::max(0.0, y[j] - grad[j] / diag[j])) * diag[j]);
      }
    }
    if (frozen) {
      // the shift moved to the current velocity once the QP's residual has fallen by
      // refreeze_ratio since the last move (an inexact outer fixed point on the shift)
      if (qp_start < 0.0) qp_start = qp_residual;
      if (refreeze_ratio == 0.0 && qp_residual <= qp_tolerance * qp_start) {
        report.iterations = k - 1;
        break;
      }
      if (qp_first < 0.0) {
        qp_first = qp_residual;
      } else if (qp_residual <= refreeze_ratio * qp_first) {
        for (Eigen::Index i = 0; i < n; i += 2) {
          const double sh = 0.5 * std::abs(a[i + 1] - a[i]);
          frozen_shift[i] = frozen_shift[i + 1] = sh;
          grad[i] = a[i] + sh;
          grad[i + 1] = a[i + 1] + sh;
        }
        qp_first = -1.0;
        ++refreezes;
      }
    }
    truncated_matrix(f.m, held, eps, a_matrix);
    ldlt.factorize(a_matrix);
    report.iterations = k;
    if (ldlt.info() != Eigen::Success) {
      std::printf("  tnnmg %d: the factorisation failed\n", k);
      break;
    }
    Vector rhs = -grad;
    for (Eigen::Index i = 0; i < n; ++i)
      if (held[i]) rhs[i] = 0.0;
    v = ldlt.solve(rhs);
    for (Eigen::Index i = 0; i < n; ++i)
      if (held[i]) v[i] = 0.0;
    // The projected arc y(alpha) = max(0, y + alpha v) (Bertsekas' projected Newton): the
    // alpha in 1, 1/2, ..., 1/1024 of least E, E(y) = y.M y / 2 + c_s.y with the shift frozen.
    Vector c_s = f.c;
    for (Eigen::Index i = 0; i < n; i += 2) {
      const double s = grad[i] - a[i];
      c_s[i] += s;
      c_s[i + 1] += s;
    }
    auto energy = [&](const Vector& z) { return 0.5 * z.dot(f.m * z) + c_s.dot(z); };
    int clipped = 0;
    const Vector y_before = y;
    const double alpha = least_on_arc(y, v, [](Vector& z) { z = z.cwiseMax(0.0); }, energy, true);
    for (Eigen::Index i = 0; i < n; ++i) clipped += y_before[i] + alpha * v[i] < 0.0 ? 1 : 0;
    r = f.gi * y;
    if (trace > 0 && k % trace == 0)
      std::printf("  tnnmg %4d: law before %.3e, qp %.3e, held %d of %ld, clipped %d, alpha %.3f, law after %.3e\n", k,
                  report.residual, qp_residual, n_held, static_cast<long>(n), clipped, alpha,
                  cd::admm_law_residual(p, r, velocity_floor));
  }
  report.residual = cd::admm_law_residual(p, r, velocity_floor);
  report.converged = report.residual <= tolerance;
  if (trace > 0) std::printf("  tnnmg: %d moves of the shift\n", refreezes);
  return report;
}

// --tnnmg-law N: the same scheme with the law's own linearisation instead of the frozen
// shift's QP: K sweeps of the exact Coulomb Gauss-Seidel, the statuses read from the
// impulses' geometry as TNNMG truncates (R_n = 0: open; |R_t| = mu R_n: sliding; else
// sticking), that set's linear system (cd::status_system, one sparse LU), and of the arc
// Proj_K(r + alpha (R_set - r)), alpha = 1, 1/2, ..., 1/1024, the point of least law
// residual if it is below the smoother's (else the smoother's impulses are kept).
void project_on_cone(double mu, double& rn, double& rt) {
  if (std::abs(rt) <= mu * rn) return;
  if (mu * std::abs(rt) <= -rn) {
    rn = rt = 0.0;
    return;
  }
  // onto the edge (1, +-mu)
  const double sign = rt > 0.0 ? 1.0 : -1.0;
  const double t = (rn + mu * std::abs(rt)) / (1.0 + mu * mu);
  rn = t;
  rt = sign * mu * t;
}

PolishReport tnnmg_law(const cd::DelassusProblem& p, Vector& r, int max_iterations, int sweeps, double tolerance,
                       double velocity_floor, int trace, int& sweeps_done) {
  PolishReport report;
  const Eigen::Index m = p.contacts(), n = 2 * m;
  if (n == 0) return report;
  cd::NsgsOptions no;
  no.tolerance = 1e-300;
  no.max_sweeps = sweeps;
  sweeps_done = 0;
  std::vector<cd::LawStatus> st(m);
  Eigen::SparseLU<ColMatrix, Eigen::COLAMDOrdering<int>> lu;
  for (int k = 1; k <= max_iterations; ++k) {
    cd::solve_nsgs(p, r, no);
    sweeps_done += sweeps;
    report.residual = cd::admm_law_residual(p, r, velocity_floor);
    if (report.residual <= tolerance) {
      report.converged = true;
      break;
    }
    int counts[4] = {0, 0, 0, 0};
    for (Eigen::Index a = 0; a < m; ++a) {
      const double rn = r[2 * a], rt = r[2 * a + 1], mu = p.mu[a];
      st[a] = rn <= 0.0                                 ? cd::LawStatus::open
              : std::abs(rt) < (1.0 - 1e-12) * mu * rn ? cd::LawStatus::stick
              : rt < 0.0                                ? cd::LawStatus::slip_plus
                                                        : cd::LawStatus::slip_minus;
      ++counts[static_cast<int>(st[a])];
    }
    ColMatrix a_matrix;
    Vector b;
    cd::status_system(p, st, a_matrix, b);
    lu.compute(a_matrix);
    report.iterations = k;
    if (lu.info() != Eigen::Success) {
      if (trace > 0) std::printf("  tnnmg-law %d: the LU failed\n", k);
      continue;
    }
    const Vector v = lu.solve(b) - r;
    const auto law = [&](const Vector& z) { return cd::admm_law_residual(p, z, velocity_floor); };
    const double alpha = least_on_arc(r, v, [&](Vector& z) { for (Eigen::Index a = 0; a < m; ++a) project_on_cone(p.mu[a], z[2 * a], z[2 * a + 1]); }, law, false);
    const double best = alpha > 0.0 ? law(r) : report.residual;
    if (trace > 0 && k % trace == 0)
      std::printf("  tnnmg-law %4d: law before %.3e, open %d stick %d slip %d, alpha %.4f, law after %.3e\n", k,
                  report.residual, counts[0], counts[1], counts[2] + counts[3], alpha, best);
  }
  report.residual = cd::admm_law_residual(p, r, velocity_floor);
  report.converged = report.residual <= tolerance;
  return report;
}

// --tnnmg-stick N: the truncation kept to the sticking contacts, where the law is linear
// and symmetric (u = 0, no shift): K sweeps of the exact Coulomb Gauss-Seidel, then the
// sticking set's system W_SS dR_S = -u_S (open and sliding contacts held; one numeric
// LDLT of W with the held rows and columns made the identity's, its pattern analysed once),
// and of the arc Proj_K(r + alpha dR), alpha = 1, 1/2, ..., 1/1024, the point of least
// E = R.W R / 2 + q.R (the sub-problem's energy: only sticking contacts move) if below
// the smoother's.
PolishReport tnnmg_stick(const cd::DelassusProblem& p, Vector& r, int max_iterations, int sweeps, double eps,
                         double tolerance, double velocity_floor, int trace, int& sweeps_done) {
  PolishReport report;
  const Eigen::Index m = p.contacts(), n = 2 * m;
  if (n == 0) return report;
  cd::NsgsOptions no;
  no.tolerance = 1e-300;
  no.max_sweeps = sweeps;
  sweeps_done = 0;
  const ColMatrix w = p.W;
  ColMatrix a_matrix = w;
  a_matrix.makeCompressed();
  Eigen::SimplicialLDLT<ColMatrix, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt;
  ldlt.analyzePattern(a_matrix);
  std::vector<char> held(n);
  Vector u(n), rhs(n);
  auto energy = [&](const Vector& z) { return 0.5 * z.dot(p.W * z) + p.q.dot(z); };
  for (int k = 1; k <= max_iterations; ++k) {
    if (sweeps > 0) {
      cd::solve_nsgs(p, r, no);
      sweeps_done += sweeps;
    }
    report.residual = cd::admm_law_residual(p, r, velocity_floor);
    if (report.residual <= tolerance) {
      report.converged = true;
      break;
    }
    int sticking = 0;
    for (Eigen::Index a = 0; a < m; ++a) {
      const double rn = r[2 * a], rt = r[2 * a + 1];
      const bool stick = rn > 0.0 && std::abs(rt) < (1.0 - 1e-9) * p.mu[a] * rn;
      held[2 * a] = held[2 * a + 1] = stick ? 0 : 1;
      sticking += stick ? 1 : 0;
    }
    truncated_matrix(w, held, eps, a_matrix);
    ldlt.factorize(a_matrix);
    report.iterations = k;
    if (ldlt.info() != Eigen::Success) {
      if (trace > 0) std::printf("  tnnmg-stick %d: the factorisation failed\n", k);
      continue;
    }
    u = p.W * r + p.q;
    for (Eigen::Index i = 0; i < n; ++i) rhs[i] = held[i] ? 0.0 : -u[i];
    Vector v = ldlt.solve(rhs);
    for (Eigen::Index i = 0; i < n; ++i)
      if (held[i]) v[i] = 0.0;
    const double alpha = least_on_arc(r, v, [&](Vector& z) { for (Eigen::Index a = 0; a < m; ++a) project_on_cone(p.mu[a], z[2 * a], z[2 * a + 1]); }, energy, true);
    if (trace > 0 && k % trace == 0)
      std::printf("  tnnmg-stick %4d: law before %.3e, sticking %d of %ld, alpha %.4f, law after %.3e\n", k,
                  report.residual, sticking, static_cast<long>(m), alpha,
                  cd::admm_law_residual(p, r, velocity_floor));
  }
  report.residual = cd::admm_law_residual(p, r, velocity_floor);
  report.converged = report.residual <= tolerance;
  return report;
}

// --tresca N: the same truncated Newton on Tresca's problem instead of the frozen shift's:
// with the friction bound g_a = mu R_n held, the step is the convex QP
//   min R.W R / 2 + q.R  over R_n >= 0, |R_t| <= g_a
// (no shift: its normal condition is Signorini's on u_n itself), smoothed by block
// Gauss-Seidel (each contact's 2x2 box QP solved exactly), its held components those at a
// bound, corrected on the rest by one numeric LDLT of W and the projected arc; g moves to
// mu R_n each time the QP's projected gradient has fallen by --tnnmg-refreeze X (an outer
// fixed point on the bound, Panagiotopoulos'), whose fixed points are Coulomb's law.
PolishReport tresca(const cd::DelassusProblem& p, Vector& r, int max_iterations, int sweeps, double eps,
                    double tolerance, double velocity_floor, int trace, int& sweeps_done, double refreeze_ratio) {
  PolishReport report;
  const Eigen::Index m = p.contacts(), n = 2 * m;
  if (n == 0) return report;
  const ColMatrix w = p.W;
  const Eigen::SparseMatrix<double, Eigen::RowMajor>& rows = p.W;
  ColMatrix a_matrix = w;
  a_matrix.makeCompressed();
  Eigen::SimplicialLDLT<ColMatrix, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt;
  ldlt.analyzePattern(a_matrix);
  Vector bound(m), lo(n), hi(n), u(n), v(n);
  auto set_bounds = [&]() {
    for (Eigen::Index a = 0; a < m; ++a) {
      bound[a] = p.mu[a] * std::max(0.0, r[2 * a]);
      lo[2 * a] = 0.0;
      hi[2 * a] = std::numeric_limits<double>::infinity();
      lo[2 * a + 1] = -bound[a];
      hi[2 * a + 1] = bound[a];
    }
  };
  set_bounds();
  r = r.cwiseMax(lo).cwiseMin(hi);
  auto box_sweep = [&]() { block_box_sweep(rows, p.q, lo, hi, r); };
  auto energy = [&](const Vector& z) { return 0.5 * z.dot(p.W * z) + p.q.dot(z); };
  std::vector<char> held(n);
  double qp_first = -1.0;
  int moves = 0;
  sweeps_done = 0;
  for (int k = 1; k <= max_iterations; ++k) {
    for (int s = 0; s < sweeps; ++s) box_sweep();
    sweeps_done += sweeps;
    report.residual = cd::admm_law_residual(p, r, velocity_floor);
    if (report.residual <= tolerance) {
      report.converged = true;
      break;
    }
    u = p.W * r + p.q;
    double qp_residual = 0.0;
    for (Eigen::Index i = 0; i < n; ++i) {
      const double d = p.W.coeff(i, i);
      qp_residual = std::max(qp_residual, std::abs(r[i] - std::clamp(r[i] - u[i] / d, lo[i], hi[i])) * d);
      held[i] = r[i] <= lo[i] || r[i] >= hi[i] ? 1 : 0;
    }
    if (qp_first < 0.0) {
      qp_first = qp_residual;
    } else if (qp_residual <= refreeze_ratio * qp_first) {
      set_bounds();  // g = mu R_n: the next QP
      r = r.cwiseMax(lo).cwiseMin(hi);
      qp_first = -1.0;
      ++moves;
      continue;
    }
    truncated_matrix(w, held, eps, a_matrix);
    ldlt.factorize(a_matrix);
    report.iterations = k;
    if (ldlt.info() != Eigen::Success) continue;
    Vector rhs(n);
    for (Eigen::Index i = 0; i < n; ++i) rhs[i] = held[i] ? 0.0 : -u[i];
    v = ldlt.solve(rhs);
    for (Eigen::Index i = 0; i < n; ++i)
      if (held[i]) v[i] = 0.0;
    const double alpha = least_on_arc(r, v, [&](Vector& z) { z = z.cwiseMax(lo).cwiseMin(hi); }, energy, true);
    if (trace > 0 && k % trace == 0)
      std::printf("  tresca %4d: law %.3e, qp %.3e, alpha %.4f, moves %d\n", k, report.residual, qp_residual, alpha,
                  moves);
  }
  report.residual = cd::admm_law_residual(p, r, velocity_floor);
  report.converged = report.residual <= tolerance;
  if (trace > 0) std::printf("  tresca: %d moves of the bound\n", moves);
  return report;
}

// --against-engine: a method's impulses r beside the engine's (the exact law's to its
// tolerance) on the same step: the critical contacts of each (analysis::is_critical with
// its default eps, the rule the tools count by), the contacts critical in one and not the
// other, the active ones (R_n > 0) likewise, |r - engine| / |engine|, and the largest |u_n|
// over each one's active contacts [m/s] (0 for the exact law at a rigid step; a law with a
// frozen shift lets a sliding contact open or press by mu times its change of |u_t|).
struct Comparison {
  int critical_engine = 0, critical = 0, critical_differ = 0, active_differ = 0;
  double impulse_difference = 0.0, largest_un_engine = 0.0, largest_un = 0.0;
};

Comparison compare(const cd::DelassusProblem& p, const Vector& r, const Vector& engine) {
  Comparison c;
  const Vector u = p.W * r + p.q, ue = p.W * engine + p.q;
  const double eps = cdpile::analysis::default_eps;
  for (Eigen::Index a = 0; a < p.contacts(); ++a) {
    const bool ce = cdpile::analysis::is_critical(engine[2 * a], engine[2 * a + 1], p.mu[a], eps);
    const bool cm = cdpile::analysis::is_critical(r[2 * a], r[2 * a + 1], p.mu[a], eps);
    c.critical_engine += ce;
    c.critical += cm;
    c.critical_differ += ce != cm;
    c.active_differ += (engine[2 * a] > 0.0) != (r[2 * a] > 0.0);
    if (engine[2 * a] > 0.0) c.largest_un_engine = std::max(c.largest_un_engine, std::abs(ue[2 * a]));
    if (r[2 * a] > 0.0) c.largest_un = std::max(c.largest_un, std::abs(u[2 * a]));
  }
  c.impulse_difference = (r - engine).norm() / std::max(engine.norm(), 1e-300);
  return c;
}

Eigen::VectorXd read_row(const std::string& path, Eigen::Index n) {
  std::ifstream in(path);
  std::vector<double> v;
  double x;
  while (in >> x) v.push_back(x);
  if (static_cast<Eigen::Index>(v.size()) != n) return Eigen::VectorXd::Zero(n);
  return Eigen::Map<Eigen::VectorXd>(v.data(), n);
}

}  // namespace

int main(int argc, char** argv) {
  cd::AdmmOptions o;
  o.tolerance = 1e-6;
  o.velocity_floor = 9.81 * 1e-4;  // g h of the paper's runs
  o.max_iterations = 5000;
  int trace = 0;
  bool ipm = false;
  bool fixed_shift = false;
  bool stewart_trinkle = false;
  double ipm_gamma = 0.01;
  std::string start_file;
  double ipm_tolerance = 0.0;
  std::string save_file;
  bool skip = false;
  bool from_engine = false;
  int polish_iterations = 0;
  double polish_proximal = 0.0;
  int polish_proximal_iterations = 1;
  bool polish_trace = false;
  int polish_max_changes = cd::ActiveSetOptions{}.max_status_changes;
  int nsgs_sweeps = 0;
  double prox_eps = 0.0;
  bool damped_newton = false;
  int prox_inner = 30;
  int prox_outer = 0;
  int fb_iterations = 0;
  double fb_smoothing = 0.0;
  double fb_levenberg = 0.0;
  bool prox_fb = false;
  int prox_anderson = 0;
  bool prox_uniform = false;
  int tnnmg_iterations = 0;
  int tnnmg_sweeps = 5;
  double tnnmg_eps = 1e-10;
  bool tnnmg_frozen = false;
  bool tnnmg_law_form = false;
  bool tnnmg_stick_form = false;
  bool tresca_form = false;
  double tnnmg_refreeze = 1e-2;
  double tnnmg_qp_tolerance = 1e-8;
  std::string tnnmg_shift = "start";
  bool against_engine = false;
  std::vector<std::string> files;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    const bool has = a + 1 < argc;
    if (arg == "--compliance" && has)
      o.compliance = std::stod(argv[++a]);
    else if (arg == "--rho" && has)
      o.rho = std::stod(argv[++a]);
    else if (arg == "--tolerance" && has)
      o.tolerance = std::stod(argv[++a]);
    else if (arg == "--max" && has)
      o.max_iterations = std::stoi(argv[++a]);
    else if (arg == "--trace" && has)
      trace = std::stoi(argv[++a]);
    else if (arg == "--relaxation" && has)
      o.relaxation = std::stod(argv[++a]);
    else if (arg == "--ipm")
      ipm = true;
    else if (arg == "--ipm-st")
      ipm = stewart_trinkle = true;
    else if (arg == "--ipm-gamma" && has)
      ipm_gamma = std::stod(argv[++a]);
    else if (arg == "--ipm-tolerance" && has)
      ipm_tolerance = std::stod(argv[++a]);
    else if (arg == "--start" && has)
      start_file = argv[++a];
    else if (arg == "--save" && has)
      save_file = argv[++a];
    else if (arg == "--fixed-shift")
      ipm = fixed_shift = true;
    else if (arg == "--warm")
      skip = true;
    else if (arg == "--from-engine")
      from_engine = skip = true;
    else if (arg == "--polish" && has)
      polish_iterations = std::stoi(argv[++a]);
    else if (arg == "--polish-proximal" && has)
      polish_proximal = std::stod(argv[++a]);
    else if (arg == "--polish-proximal-iterations" && has)
      polish_proximal_iterations = std::stoi(argv[++a]);
    else if (arg == "--polish-trace")
      polish_trace = true;
    else if (arg == "--polish-max-changes" && has)
      polish_max_changes = std::stoi(argv[++a]);
    else if (arg == "--newton" && has) {
      polish_iterations = std::stoi(argv[++a]);
      damped_newton = true;
    }
    else if (arg == "--prox" && a + 2 < argc) {
      prox_eps = std::stod(argv[++a]);
      prox_outer = std::stoi(argv[++a]);
    } else if (arg == "--prox-inner" && has) {
      prox_inner = std::stoi(argv[++a]);
    } else if (arg == "--fb" && has) {
      fb_iterations = std::stoi(argv[++a]);
      skip = true;
    } else if (arg == "--prox-anderson" && has) {
      prox_anderson = std::stoi(argv[++a]);
    } else if (arg == "--prox-uniform") {
      prox_uniform = true;
    } else if (arg == "--prox-fb") {
      prox_fb = true;
    } else if (arg == "--fb-lm" && has) {
      fb_levenberg = std::stod(argv[++a]);
    } else if (arg == "--fb-smooth" && has) {
      fb_smoothing = std::stod(argv[++a]);
    } else if (arg == "--tnnmg" && has) {
      tnnmg_iterations = std::stoi(argv[++a]);
      skip = true;
    } else if (arg == "--tnnmg-sweeps" && has) {
      tnnmg_sweeps = std::stoi(argv[++a]);
    } else if (arg == "--tnnmg-law" && has) {
      tnnmg_iterations = std::stoi(argv[++a]);
      tnnmg_law_form = skip = true;
    } else if (arg == "--tnnmg-stick" && has) {
      tnnmg_iterations = std::stoi(argv[++a]);
      tnnmg_stick_form = skip = true;
    } else if (arg == "--tresca" && has) {
      tnnmg_iterations = std::stoi(argv[++a]);
      tresca_form = skip = true;
    } else if (arg == "--tnnmg-frozen") {
      tnnmg_frozen = true;
    } else if (arg == "--tnnmg-qp-tolerance" && has) {
      tnnmg_qp_tolerance = std::stod(argv[++a]);
    } else if (arg == "--tnnmg-refreeze" && has) {
      tnnmg_refreeze = std::stod(argv[++a]);
    } else if (arg == "--tnnmg-shift" && has) {
      tnnmg_shift = argv[++a];
      if (tnnmg_shift != "start" && tnnmg_shift != "previous" && tnnmg_shift != "zero") {
        std::cerr << "admm_on_steps: --tnnmg-shift: '" << tnnmg_shift << "' is not start, previous or zero\n";
        return 2;
      }
    } else if (arg == "--against-engine") {
      against_engine = true;
    } else if (arg == "--tnnmg-eps" && has) {
      tnnmg_eps = std::stod(argv[++a]);
    } else if (arg == "--nsgs" && has)
      nsgs_sweeps = std::stoi(argv[++a]);
    else
      files.push_back(arg);
  }
  if (tnnmg_shift != "start" && !tnnmg_frozen) {
    std::cerr << "admm_on_steps: --tnnmg-shift needs --tnnmg-frozen (the shift it freezes)\n";
    return 2;
  }
  if (files.empty()) {
    std::cerr << "usage: admm_on_steps [--compliance C] [--rho R] [--tolerance T] [--max N] "
                 "[--trace K] STEP.dat...\n";
    return 2;
  }
  if (trace > 0)
    o.on_iteration = [&](int k, double law, double primal, double dual, double rho) {
      if (k % trace == 0)
        std::printf("  %5d law %.3e primal %.3e dual %.3e rho %.3e\n", k, law, primal, dual, rho);
    };
  std::printf(
      "file\tcontacts\titerations\tfactorisations\tlaw\tconverged\tcpu_ms\tnatural_map\t"
      "engine_natural_map\tengine_law%s\n",
      against_engine ? "\tcritical_engine\tcritical\tcritical_differ\tactive_differ\timpulse_difference\t"
                       "largest_un_engine\tlargest_un" : "");
  try {
    for (const std::string& file : files) {
      const cd::DelassusProblem p = cdpile::io::read_siconos_fc2d(file);
      const std::string stem = file.substr(0, file.size() - 4);
      Eigen::VectorXd r = read_row(stem + ".r0", 2 * p.contacts());
      const Eigen::VectorXd engine = read_row(stem + ".r", 2 * p.contacts());
      if (from_engine) r = engine;
      if (!start_file.empty()) r = read_row(start_file, 2 * p.contacts());
      const std::clock_t cpu = std::clock();
      cd::AdmmReport rep;
      if (ipm) {
        IpmOptions io;
        io.tolerance = ipm_tolerance > 0.0 ? ipm_tolerance : o.tolerance;
        io.velocity_floor = o.velocity_floor;
        io.max_iterations = o.max_iterations;
        io.fixed_shift = fixed_shift;
        io.neighbourhood = ipm_gamma;
        if (trace > 0)
          io.on_iteration = [&](int k, double law, double mu, double infeasible) {
            if (k % trace == 0)
              std::printf("  %5d law %.3e mu %.3e infeasibility %.3e\n", k, law, mu, infeasible);
          };
        const IpmReport i = stewart_trinkle ? solve_ipm_st(p, r, io) : solve_ipm(p, r, io);
        rep.iterations = rep.factorisations = i.iterations;
        rep.residual = i.residual;
        rep.converged = i.converged;
      } else if (!skip) {
        rep = cd::solve_admm(p, r, o);
      }
      if (tnnmg_iterations > 0) {
        int sweeps_done = 0;
        Vector speed;  // --tnnmg-shift previous / zero: the speeds |u_t| the shift is frozen at
        if (tnnmg_shift == "previous") {
          if (!std::ifstream(stem + ".ut0"))
            throw std::runtime_error(stem + ".ut0: missing (export_steps writes it from the second step on)");
          speed = read_row(stem + ".ut0", p.contacts());
        } else if (tnnmg_shift == "zero") {
          speed = Vector::Zero(p.contacts());
        }
        const PolishReport pr = tresca_form ? tresca(p, r, tnnmg_iterations, tnnmg_sweeps, tnnmg_eps, o.tolerance,
                                                     o.velocity_floor, trace, sweeps_done, tnnmg_refreeze) : tnnmg_stick_form ? tnnmg_stick(p, r, tnnmg_iterations, tnnmg_sweeps, tnnmg_eps, o.tolerance,
                                                               o.velocity_floor, trace, sweeps_done) : tnnmg_law_form ? tnnmg_law(p, r, tnnmg_iterations, tnnmg_sweeps, o.tolerance,
                                                           o.velocity_floor, trace, sweeps_done) : tnnmg(p, r, tnnmg_iterations, tnnmg_sweeps, tnnmg_eps, o.tolerance,
                                      o.velocity_floor, trace, sweeps_done, tnnmg_frozen, tnnmg_refreeze,
                                                  tnnmg_qp_tolerance, speed.size() ? &speed : nullptr);
        rep.iterations += pr.iterations + sweeps_done;
        rep.factorisations += pr.iterations;
        rep.residual = pr.residual;
        rep.converged = pr.converged;
      }
      if (nsgs_sweeps > 0) {
        // NSGS then, in chunks of 500 sweeps, to the law's residual (Siconos' measure stops
        // each chunk only at 1e-300): how far a start brings Gauss-Seidel.
        cd::NsgsOptions no;
        no.tolerance = 1e-300;
        no.max_sweeps = 500;
        int done = 0;
        while (done < nsgs_sweeps) {
          cd::solve_nsgs(p, r, no);
          done += no.max_sweeps;
          rep.residual = cd::admm_law_residual(p, r, o.velocity_floor);
          if (trace > 0) std::printf("  nsgs %6d: law %.3e\n", done, rep.residual);
          if (rep.residual <= o.tolerance) break;
        }
        rep.iterations += done;
        rep.converged = rep.residual <= o.tolerance;
      }
      if (fb_iterations > 0) {
        const IpmReport i = solve_fb(p, r, fb_iterations, o.tolerance, o.velocity_floor, trace, fb_smoothing, fb_levenberg);
        rep.iterations += i.iterations;
        rep.factorisations += i.iterations;
        rep.residual = i.residual;
        rep.converged = i.converged;
      }
      if (polish_iterations > 0 && !damped_newton && trace == 0) {
        // The library's active-set Newton (cd::solve_active_set, the engine's finish).
        cd::ActiveSetOptions ao;
        ao.tolerance = o.tolerance;
        ao.velocity_floor = o.velocity_floor;
        ao.max_factorisations = polish_iterations;
        ao.proximal = polish_proximal;
        ao.proximal_iterations = polish_proximal_iterations;
        ao.max_status_changes = polish_max_changes;
        if (polish_trace)
          ao.trace = [](int k, double law) { std::printf("  polish %3d: law %.3e\n", k, law); };
        const cd::ActiveSetReport ar = cd::solve_active_set(p, r, ao);
        if (ar.proximal_solves > 0)
          std::fprintf(stderr, "%s: %d of %d sets solved by the proximal point\n", file.c_str(),
                       ar.proximal_solves, ar.factorisations);
        rep.iterations += ar.factorisations;
        rep.factorisations += ar.factorisations;
        rep.residual = ar.residual;
        rep.converged = ar.converged;
      } else if (polish_iterations > 0) {
        const PolishReport pr = polish(p, r, polish_iterations, o.tolerance, o.velocity_floor, trace > 0 ? 1 : 0, damped_newton);
        rep.iterations += pr.iterations;
        rep.factorisations += pr.iterations;
        rep.residual = pr.residual;
        rep.converged = pr.converged;
      }
      if (prox_outer > 0) {
        const PolishReport pr =
            prox_anderson > 0
                ? anderson_proximal(p, r, prox_eps, prox_outer, prox_inner, prox_anderson, prox_uniform, o.tolerance,
                                    o.velocity_floor, trace)
                : proximal_newton(p, r, prox_eps, prox_outer, prox_inner, o.tolerance, o.velocity_floor, trace, prox_fb);
        rep.iterations += pr.iterations;
        rep.factorisations += pr.iterations;
        rep.residual = pr.residual;
        rep.converged = pr.converged;
      }
      const double ms = 1e3 * static_cast<double>(std::clock() - cpu) / CLOCKS_PER_SEC;
      if (!save_file.empty()) {
        std::ofstream out(save_file);
        out.precision(17);
        for (Eigen::Index i = 0; i < r.size(); ++i) out << (i ? " " : "") << r[i];
        out << "\n";
      }
      std::printf("%s\t%ld\t%d\t%d\t%.3e\t%d\t%.1f\t%.3e\t%.3e\t%.3e", file.c_str(),
                  static_cast<long>(p.contacts()), rep.iterations, rep.factorisations, rep.residual,
                  rep.converged ? 1 : 0, ms, cd::natural_map_residual(p, r),
                  cd::natural_map_residual(p, engine),
                  cd::admm_law_residual(p, engine, o.velocity_floor));
      if (against_engine) {
        const Comparison c = compare(p, r, engine);
        std::printf("\t%d\t%d\t%d\t%d\t%.3e\t%.3e\t%.3e", c.critical_engine, c.critical, c.critical_differ,
                    c.active_differ, c.impulse_difference, c.largest_un_engine, c.largest_un);
      }
      std::printf("\n");
      std::fflush(stdout);
    }
  } catch (const std::exception& e) {
    std::cerr << "admm_on_steps: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
