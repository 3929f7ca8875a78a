// The active-set Newton on a step's problem (active_set.hpp; docs/method.md, "Finishing a
// step by its active set").
#include "cdpile/cd/active_set.hpp"

#include "cdpile/cd/admm.hpp"

#include <Eigen/SparseCore>
#include <Eigen/SparseLU>

#include <algorithm>
#include <cmath>
#include <vector>

namespace cdpile::cd {

namespace {
using Vector = Eigen::VectorXd;
using ColMatrix = Eigen::SparseMatrix<double>;
using SparseLu = Eigen::SparseLU<ColMatrix, Eigen::COLAMDOrdering<int>>;

/// The contacts whose statuses differ between two sets.
int status_changes(const std::vector<LawStatus>& a, const std::vector<LawStatus>& b) {
  int changed = 0;
  for (std::size_t c = 0; c < a.size(); ++c) changed += a[c] != b[c] ? 1 : 0;
  return changed;
}

/// The proximal point on a singular set's system A x = b (docs/performance.md, "A
/// proximal term on the rigid sets"): x <- x + (A + eps D)^-1 (b - A x) from x, D the
/// diagonal of W on the rows that carry u, with `lu` holding A + eps D.
/// Each iterate is the solution of the system nearest the last in the metric eps D, so the
/// part of x that A leaves free (the hyperstatic network's self-stresses) keeps its start
/// while the rest converges, at the rate eps / (lambda + eps) on a mode of stiffness lambda.
/// Returns whether the iterates settled (a step below 1e-13 of x); they do not when the
/// set's system has no solution (then they drift), nor when A has an eigenvalue near
/// -eps D (then they grow): both seen on the rigid steps.
bool proximal_solve(const SparseLu& lu, const ColMatrix& a, const Vector& b, Vector& x,
                    int max_iterations) {
  for (int j = 0; j < max_iterations; ++j) {
    const Vector dx = lu.solve(b - a * x);
    if (!dx.allFinite()) return false;
    x += dx;
    if (dx.lpNorm<Eigen::Infinity>() <= 1e-13 * x.lpNorm<Eigen::Infinity>()) return true;
  }
  return false;
}
}  // namespace

std::vector<LawStatus> law_statuses(const DelassusProblem& p, const Vector& r) {
  const Vector u = p.W * r + p.q;
  std::vector<LawStatus> st(static_cast<std::size_t>(p.contacts()));
  for (Eigen::Index a = 0; a < p.contacts(); ++a) {
    const double rho = 1.0 / p.W.coeff(2 * a, 2 * a);
    const double tn = r[2 * a] - rho * u[2 * a];
    const double tt = r[2 * a + 1] - rho * u[2 * a + 1];
    LawStatus s = LawStatus::open;
    if (tn > 0.0)
      s = std::abs(tt) <= p.mu[a] * tn ? LawStatus::stick
          : tt > 0.0                   ? LawStatus::slip_plus
                                       : LawStatus::slip_minus;
    st[static_cast<std::size_t>(a)] = s;
  }
  return st;
}

void status_system(const DelassusProblem& p, const std::vector<LawStatus>& st, ColMatrix& a,
                   Vector& b) {
  const Eigen::Index n = 2 * p.contacts();
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<std::size_t>(p.W.nonZeros()));
  b = Vector::Zero(n);
  auto copy_row = [&](Eigen::Index row) {
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(p.W, row); it; ++it)
      t.emplace_back(row, it.col(), it.value());
    b[row] = -p.q[row];
  };
  for (Eigen::Index c = 0; c < p.contacts(); ++c) {
    const LawStatus s = st[static_cast<std::size_t>(c)];
    if (s == LawStatus::open) {
      t.emplace_back(2 * c, 2 * c, 1.0);
      t.emplace_back(2 * c + 1, 2 * c + 1, 1.0);
    } else if (s == LawStatus::stick) {
      copy_row(2 * c);
      copy_row(2 * c + 1);
    } else {
      copy_row(2 * c);
      t.emplace_back(2 * c + 1, 2 * c + 1, 1.0);
      t.emplace_back(2 * c + 1, 2 * c, s == LawStatus::slip_plus ? -p.mu[c] : p.mu[c]);
    }
  }
  a.resize(n, n);
  a.setFromTriplets(t.begin(), t.end());
}

ActiveSetReport solve_active_set(const DelassusProblem& p, Vector& r, const ActiveSetOptions& o) {
  ActiveSetReport report;
  const Eigen::Index n = 2 * p.contacts();
  if (r.size() != n) r = Vector::Zero(n);
  if (n == 0) {
    report.converged = true;
    return report;
  }
  std::vector<LawStatus> previous;
  std::vector<std::vector<LawStatus>> solved;  // every set solved so far
  SparseLu lu;
  ColMatrix a;
  Vector b;
  while (true) {
    const std::vector<LawStatus> st = law_statuses(p, r);
    if (st == previous) {  // the last solve's statuses hold at its solution
      report.residual = admm_law_residual(p, r, o.velocity_floor);
      report.converged = report.residual <= o.tolerance;
      return report;
    }
    if (report.factorisations >= o.max_factorisations) break;
    // A set solved before and not the last one: the Newton cycles, and would forever.
    if (std::find(solved.begin(), solved.end(), st) != solved.end()) break;
    // A set far from the last: the Newton wanders (docs/performance.md, "Finishing the hard
    // steps by their active set": its successes change at most 14 contacts a set).
    if (!previous.empty() && status_changes(previous, st) > o.max_status_changes) break;
    if (o.cancel && o.cancel()) throw StepCancelled();
    status_system(p, st, a, b);
    lu.compute(a);
    Vector next;
    if (lu.info() == Eigen::Success) {
      ++report.factorisations;
      next = lu.solve(b);
    }
    if (lu.info() != Eigen::Success || !next.allFinite()) {
      // singular: rigid contacts sticking in a hyperstatic network
      if (!(o.proximal > 0.0)) break;
      // The term on the rows that carry u (the law's velocity), none on the rows R = 0 and
      // R_t = -+mu R_n, which a proximal term on the impulses leaves exact.
      Vector d = Vector::Zero(a.rows());
      for (Eigen::Index c = 0; c < p.contacts(); ++c) {
        const LawStatus s = st[static_cast<std::size_t>(c)];
        if (s == LawStatus::open) continue;
        d[2 * c] = p.W.coeff(2 * c, 2 * c);
        if (s == LawStatus::stick) d[2 * c + 1] = p.W.coeff(2 * c + 1, 2 * c + 1);
      }
      ColMatrix regular = a;
      regular.diagonal() += o.proximal * d;
      lu.compute(regular);
      if (lu.info() != Eigen::Success) break;
      ++report.factorisations;
      ++report.proximal_solves;
      next = r;
      // One proximal step is taken as the set's solution; more must settle.
      if (!proximal_solve(lu, a, b, next, o.proximal_iterations) && o.proximal_iterations > 1) break;
    }
    if (!next.allFinite()) break;
    r = next;
    previous = st;
    solved.push_back(st);
    // A set's solution that meets the law's residual is kept even before its statuses
    // repeat (rounding can flip a contact at its bound from one solve to the next).
    report.residual = admm_law_residual(p, r, o.velocity_floor);
    if (o.trace) o.trace(report.factorisations, report.residual);
    if (report.residual <= o.tolerance) {
      report.converged = true;
      return report;
    }
  }
  report.residual = admm_law_residual(p, r, o.velocity_floor);
  return report;
}

Vector row_impulses(const ContactSystem& s) {
  Vector r(2 * static_cast<Eigen::Index>(s.rows.size()));
  for (std::size_t a = 0; a < s.rows.size(); ++a) {
    r[2 * static_cast<Eigen::Index>(a)] = s.rows[a].rn;
    r[2 * static_cast<Eigen::Index>(a) + 1] = s.rows[a].rt;
  }
  return r;
}

void set_row_impulses(ContactSystem& s, const Vector& r) {
  for (std::size_t a = 0; a < s.rows.size(); ++a) {
    ContactRow& row = s.rows[a];
    const double rn = r[2 * static_cast<Eigen::Index>(a)],
                 rt = r[2 * static_cast<Eigen::Index>(a) + 1];
    s.apply_impulse(row, rn - row.rn, rt - row.rt);
    row.rn = rn;
    row.rt = rt;
    row.status = !(rn > 0.0)                  ? ContactStatus::open
                 : std::abs(rt) < row.mu * rn ? ContactStatus::stick
                                              : ContactStatus::slide;
  }
}

}  // namespace cdpile::cd
