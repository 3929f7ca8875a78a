// The factorised solver: ADMM on the step's contact problem with the De Saxce shift
// inside the iteration (admm.hpp; docs/method.md, "The factorised solver").
#include "cdpile/cd/admm.hpp"

#include "cdpile/cd/active_set.hpp"
#include "cdpile/cd/local_solver.hpp"
#include "cdpile/cd/pcg.hpp"
#include "cdpile/check.hpp"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace cdpile::cd {

namespace {

using Vector = Eigen::VectorXd;
using ColMatrix = Eigen::SparseMatrix<double>;

/// Contact a's 2x2 diagonal block of G (W_nt = 0 for disks; kept for other problems).
struct Block {
  double nn = 0.0, nt = 0.0, tn = 0.0, tt = 0.0;
};

std::vector<Block> diagonal_blocks(const DelassusProblem& p) {
  std::vector<Block> blocks(static_cast<std::size_t>(p.contacts()));
  for (Eigen::Index i = 0; i < p.W.outerSize(); ++i)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(p.W, i); it; ++it) {
      if (it.col() / 2 != i / 2) continue;
      Block& b = blocks[static_cast<std::size_t>(i / 2)];
      (i % 2 == 0 ? (it.col() % 2 == 0 ? b.nn : b.nt) : (it.col() % 2 == 0 ? b.tn : b.tt)) =
          it.value();
    }
  return blocks;
}

/// The metric D: per contact one scalar, the mean of its block's diagonal, on both of its
/// components (a scalar per contact keeps the Euclidean projection on its cone exact).
Vector contact_metric(const std::vector<Block>& blocks) {
  Vector d(2 * static_cast<Eigen::Index>(blocks.size()));
  for (std::size_t a = 0; a < blocks.size(); ++a) {
    const double mean = 0.5 * (blocks[a].nn + blocks[a].tt);
    CDPILE_DEBUG_CHECK(mean > 0.0, "contact " + std::to_string(a) + ": a positive diagonal block");
    d[2 * static_cast<Eigen::Index>(a)] = d[2 * static_cast<Eigen::Index>(a) + 1] = mean;
  }
  return d;
}

/// The Euclidean projection of (n, t) on the 2D Coulomb cone |t| <= mu n: itself inside,
/// the apex from the polar cone, else the nearer edge.
void project_on_cone(double mu, double& n, double& t) {
  const double at = std::abs(t);
  if (at <= mu * n) return;
  if (mu * at <= -n) {
    n = t = 0.0;
    return;
  }
  n = (n + mu * at) / (1.0 + mu * mu);
  t = std::copysign(mu * n, t);
}

void project_on_cones(const Vector& mu, Vector& r) {
  for (Eigen::Index a = 0; a < mu.size(); ++a) project_on_cone(mu[a], r[2 * a], r[2 * a + 1]);
}

/// De Saxce's shift of the local velocities u: (mu |u_t|, 0) per contact. With it the
/// cone complementarity of (R, u + s) is Coulomb's law, not the associated flow rule.
void de_saxce_shift(const Vector& mu, const Vector& u, Vector& s) {
  for (Eigen::Index a = 0; a < mu.size(); ++a) {
    s[2 * a] = mu[a] * std::abs(u[2 * a + 1]);
    s[2 * a + 1] = 0.0;
  }
}

/// admm_law_residual given u = G r + q.
double law_residual(const DelassusProblem& p, const std::vector<Block>& blocks, const Vector& r,
                    const Vector& u, double velocity_floor) {
  double largest = 0.0, scale_sum = 0.0;
  int active = 0;
  for (Eigen::Index a = 0; a < p.contacts(); ++a) {
    const Block& w = blocks[static_cast<std::size_t>(a)];
    const double rn = r[2 * a], rt = r[2 * a + 1];
    const double b_n = u[2 * a] - w.nn * rn - w.nt * rt;
    const double b_t = u[2 * a + 1] - w.tn * rn - w.tt * rt;
    const LocalImpulse l = local_solve(w.nn, w.nt, w.tn, w.tt, p.mu[a], b_n, b_t);
    if (rn > 0.0) {
      scale_sum += w.nn * rn;
      ++active;
    }
    // Open and staying open; a negative normal impulse is a violation (R_n >= 0), which
    // the local solve's projection measures.
    if (rn == 0.0 && !(l.rn > 0.0)) continue;
    largest = std::max({largest, std::abs(w.nn * (l.rn - rn)), std::abs(w.tt * (l.rt - rt))});
  }
  const double scale = std::max(velocity_floor, active > 0 ? scale_sum / active : 0.0);
  return largest / (scale > 0.0 ? scale : 1.0);
}

/// The largest eigenvalue of D^-1/2 G D^-1/2 (power iteration; G is symmetric positive
/// semi-definite, so a few products bound it well enough to place rho).
double largest_scaled_eigenvalue(const ColMatrix& g, const Vector& d) {
  const Vector inv_sqrt = d.cwiseSqrt().cwiseInverse();
  Vector x = Vector::Ones(d.size()).normalized(), y(d.size());
  double lambda = 1.0;
  for (int k = 0; k < 20; ++k) {
    y = inv_sqrt.cwiseProduct(g * inv_sqrt.cwiseProduct(x));
    lambda = y.norm();
    if (!(lambda > 0.0)) return 1.0;
    x = y / lambda;
  }
  return lambda;
}

/// The factor of G + rho D that the iterations share, refactorised when rho changes (the
/// pattern, and so its ordering and symbolic analysis, stays).
class ProximalFactor {
 public:
  ProximalFactor(const ColMatrix& g, const Vector& d, double rho) : k_(g), d_(d) {
    for (Eigen::Index i = 0; i < k_.cols(); ++i) diagonal_.push_back(&k_.coeffRef(i, i));
    base_.resize(k_.cols());
    for (Eigen::Index i = 0; i < k_.cols(); ++i) base_[i] = *diagonal_[static_cast<std::size_t>(i)];
    ldlt_.analyzePattern(k_);
    set_rho(rho);
  }
  /// G + rho D factorised; false if the factorisation failed.
  bool set_rho(double rho) {
    rho_ = rho;
    for (Eigen::Index i = 0; i < k_.cols(); ++i)
      *diagonal_[static_cast<std::size_t>(i)] = base_[i] + rho * d_[i];
    ldlt_.factorize(k_);
    ++factorisations_;
    return ldlt_.info() == Eigen::Success;
  }
  double rho() const { return rho_; }
  int factorisations() const { return factorisations_; }
  void solve(const Vector& rhs, Vector& x) const { x = ldlt_.solve(rhs); }

 private:
  ColMatrix k_;
  const Vector& d_;
  std::vector<double*> diagonal_;
  Vector base_;
  Eigen::SimplicialLDLT<ColMatrix, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt_;
  double rho_ = 0.0;
  int factorisations_ = 0;
};

/// The first rho: sqrt(lambda_min lambda_max) of D^-1/2 G D^-1/2 (Carpentier et al.),
/// lambda_min the compliance relative to D, floored for rigid contacts where G is
/// singular.
double first_rho(const ColMatrix& g, const Vector& d, double compliance) {
  const double lambda_max = largest_scaled_eigenvalue(g, d);
  const double lambda_min = std::max(compliance / d.maxCoeff(), 1e-4 * lambda_max);
  return std::sqrt(lambda_min * lambda_max);
}

/// OSQP's and Chrono's rule: rho follows the square root of the ratio of the primal
/// residual D |x - z| to the dual one rho D |z - z_before| (both velocities), at most a
/// factor 50 at a time; 1 when the balance is within the ratio that pays a factorisation.
double rho_factor(const Vector& d, const Vector& x, const Vector& z, const Vector& z_before,
                  double rho, double refactor_ratio) {
  const double primal = d.cwiseProduct(x - z).lpNorm<Eigen::Infinity>();
  const double dual = rho * d.cwiseProduct(z - z_before).lpNorm<Eigen::Infinity>();
  if (!(primal > 0.0) || !(dual > 0.0)) return 1.0;
  const double factor = std::clamp(std::sqrt(primal / dual), 1.0 / 50.0, 50.0);
  return factor > refactor_ratio || factor < 1.0 / refactor_ratio ? factor : 1.0;
}

}  // namespace

double admm_law_residual(const DelassusProblem& p, const Vector& r, double velocity_floor) {
  const Vector u = p.W * r + p.q;
  return law_residual(p, diagonal_blocks(p), r, u, velocity_floor);
}

AdmmReport solve_admm(const DelassusProblem& p, Vector& r, const AdmmOptions& o) {
  const Eigen::Index m = p.contacts(), n = 2 * m;
  CDPILE_DEBUG_CHECK(p.W.rows() == n && p.W.cols() == n && p.q.size() == n,
                     "W is 2m x 2m and q has 2m values for m = " + std::to_string(m) + " contacts");
  AdmmReport report;
  if (r.size() != n) r = Vector::Zero(n);
  if (m == 0) {
    report.converged = true;
    return report;
  }
  const std::vector<Block> blocks = diagonal_blocks(p);
  const Vector d = contact_metric(blocks);
  const ColMatrix g = p.W;
  // The start: the warm start projected on K, and the dual at its De Saxce velocity.
  Vector z = r;
  project_on_cones(p.mu, z);
  Vector u = g * z + p.q, s(n), x = z, rhs(n);
  de_saxce_shift(p.mu, u, s);
  Vector v = u + s;
  report.residual = law_residual(p, blocks, z, u, o.velocity_floor);
  if (report.residual <= o.tolerance) {
    r = z;
    report.converged = true;
    return report;
  }
  ProximalFactor factor(g, d, o.rho > 0.0 ? o.rho : first_rho(g, d, o.compliance));
  Vector z_next(n);
  for (int k = 1; k <= o.max_iterations; ++k) {
    if (o.cancel && o.cancel()) throw StepCancelled();
    const double rho = factor.rho();
    // s: De Saxce's shift at the dual velocity; x: the unconstrained step, one back-solve
    // with the kept factor, over-relaxed towards z.
    de_saxce_shift(p.mu, v, s);
    rhs = rho * d.cwiseProduct(z) - p.q - s + v;
    factor.solve(rhs, x);
    x = o.relaxation * x + (1.0 - o.relaxation) * z;
    // z: the cones; v: the dual velocity.
    z_next = x - v.cwiseQuotient(rho * d);
    project_on_cones(p.mu, z_next);
    v += rho * d.cwiseProduct(z_next - x);
    u = g * z_next + p.q;
    report.iterations = k;
    report.residual = law_residual(p, blocks, z_next, u, o.velocity_floor);
    if (o.on_iteration)
      o.on_iteration(k, report.residual, d.cwiseProduct(x - z_next).lpNorm<Eigen::Infinity>(),
                     rho * d.cwiseProduct(z_next - z).lpNorm<Eigen::Infinity>(), rho);
    if (report.residual <= o.tolerance) {
      z = z_next;
      report.converged = true;
      break;
    }
    if (k % o.rebalance_every == 0) {
      const double f = rho_factor(d, x, z_next, z, rho, o.refactor_ratio);
      if (f != 1.0 && !factor.set_rho(rho * f)) break;
    }
    z = z_next;
  }
  report.factorisations = factor.factorisations();
  report.rho = factor.rho();
  r = z;
  return report;
}

SolveReport AdmmSolver::solve(ContactSystem& system, double gravity_velocity) const {
  if (system.rows.empty()) return SolveReport{};
  // ADMM on the step's problem from the impulses the rows hold (the previous step's).
  AdmmOptions o;
  o.tolerance = 0.5 * settings_.tolerance;
  o.velocity_floor = gravity_velocity;
  o.compliance = std::min(system.compliance_n, system.compliance_t);
  o.max_iterations = std::min(admm_budget, settings_.max_sweeps - 1);
  o.cancel = system.cancel;
  const DelassusProblem p = delassus_problem(system);
  Vector r = row_impulses(system);
  const AdmmReport a = solve_admm(p, r, o);
  set_row_impulses(system, r);
  // pcg from ADMM's impulses: its sweeps test the criterion on the impulses of a sweep,
  // as every solver returns, and finish what ADMM left.
  SolverSettings rest = settings_;
  rest.solver = SolverKind::pcg;
  rest.max_sweeps = settings_.max_sweeps - a.iterations;
  SolveReport report = PcgSolver(rest).solve(system, gravity_velocity);
  report.sweeps += a.iterations;
  return report;
}

}  // namespace cdpile::cd
