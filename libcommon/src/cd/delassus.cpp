// Delassus-form 2D frictional contact problems: the natural-map residual and NSGS with the
// engine's exact local solver (delassus.hpp). The files that carry them are io's
// (io/siconos.hpp).
#include "cdpile/cd/delassus.hpp"

#include "cdpile/cd/local_solver.hpp"
#include "cdpile/check.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

namespace cdpile::cd {

namespace {

/// The natural-map residual of `r` given its local velocities u = W r + q.
double natural_map_residual(const DelassusProblem& p, const Eigen::VectorXd& r,
                            const Eigen::VectorXd& u) {
  double sum = 0.0;
  for (Eigen::Index a = 0; a < p.contacts(); ++a) {
    const double mu = p.mu[a];
    const double rn = r[2 * a], rt = r[2 * a + 1];
    // x = r - u_hat (rho = 1), then its projection on the cone |x_t| <= mu x_n.
    double xn = rn - (u[2 * a] + mu * std::abs(u[2 * a + 1]));
    double xt = rt - u[2 * a + 1];
    const double norm_t = std::abs(xt);
    if (mu * norm_t <= -xn) {  // in the polar cone: projects to the apex
      xn = 0.0;
      xt = 0.0;
    } else if (norm_t > mu * xn) {  // outside: onto the nearest edge of the cone
      xn = (mu * norm_t + xn) / (mu * mu + 1.0);
      xt = mu * xn * (xt > 0.0 ? 1.0 : (xt < 0.0 ? -1.0 : 0.0));
    }
    const double en = rn - xn, et = rt - xt;
    sum += en * en + et * et;
  }
  const double norm_q = p.q.norm();
  const double error = std::sqrt(sum);
  return norm_q > 2.220446049250313e-16 ? error / norm_q : error;
}

/// W by 2x2 blocks, column block by column block: for contact a, the contacts b whose
/// velocities its impulse moves and the blocks W_ba (nn, nt, tn, tt). A sweep scatters
/// each change of r_a through its column block, so u = W r + q stays current and the
/// residual after a sweep needs no product with W (the ELG layout of the engine, for a
/// general W).
struct BlockColumns {
  std::vector<Eigen::Index> start;  ///< m + 1 offsets into row and block
  std::vector<Eigen::Index> row;    ///< the contact b of each block
  std::vector<double> block;  ///< 4 per block: W(2b, 2a), W(2b, 2a+1), W(2b+1, 2a), W(2b+1, 2a+1)
};

BlockColumns block_columns(const DelassusProblem& p) {
  const Eigen::Index m = p.contacts();
  // Bucket the entries by column block (a counting sort). W is read row by row, so within
  // a bucket the row blocks b arrive in increasing order and the entries of one block are
  // consecutive once the two rows 2b and 2b + 1 are merged below.
  struct Entry {
    Eigen::Index b;
    int k;
    double value;
  };
  std::vector<Eigen::Index> offset(static_cast<std::size_t>(m + 1), 0);
  for (Eigen::Index i = 0; i < p.W.outerSize(); ++i)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(p.W, i); it; ++it)
      ++offset[static_cast<std::size_t>(it.col() / 2 + 1)];
  for (std::size_t a = 1; a < offset.size(); ++a) offset[a] += offset[a - 1];
  std::vector<Entry> entries(static_cast<std::size_t>(p.W.nonZeros()));
  {
    std::vector<Eigen::Index> fill(offset.begin(), offset.end() - 1);
    for (Eigen::Index i = 0; i < p.W.outerSize(); ++i)
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(p.W, i); it; ++it)
        entries[static_cast<std::size_t>(fill[static_cast<std::size_t>(it.col() / 2)]++)] = {
            i / 2, static_cast<int>(2 * (i % 2) + it.col() % 2), it.value()};
  }
  BlockColumns c;
  c.start.assign(static_cast<std::size_t>(m + 1), 0);
  for (Eigen::Index a = 0; a < m; ++a) {
    const std::size_t first = c.row.size();
    for (Eigen::Index e = offset[static_cast<std::size_t>(a)];
         e < offset[static_cast<std::size_t>(a + 1)]; ++e) {
      const Entry& x = entries[static_cast<std::size_t>(e)];
      if (c.row.size() == first || c.row.back() != x.b) {
        c.row.push_back(x.b);
        c.block.insert(c.block.end(), 4, 0.0);
      }
      c.block[c.block.size() - 4 + static_cast<std::size_t>(x.k)] = x.value;
    }
    c.start[static_cast<std::size_t>(a + 1)] = static_cast<Eigen::Index>(c.row.size());
  }
  return c;
}

}  // namespace

double natural_map_residual(const DelassusProblem& p, const Eigen::VectorXd& r) {
  const Eigen::VectorXd u = p.W * r + p.q;
  return natural_map_residual(p, r, u);
}

NsgsReport solve_nsgs(const DelassusProblem& p, Eigen::VectorXd& r, const NsgsOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const Eigen::Index m = p.contacts();
  CDPILE_DEBUG_CHECK(p.W.rows() == 2 * m && p.W.cols() == 2 * m && p.q.size() == 2 * m,
                     "W is 2m x 2m and q has 2m values for m = " + std::to_string(m) + " contacts");
  if (r.size() != 2 * m) r = Eigen::VectorXd::Zero(2 * m);
  const BlockColumns columns = block_columns(p);
  // The diagonal 2x2 blocks, kept apart: the sweep needs W_aa to remove a contact's own
  // impulse from its velocity (b_a = u_a - W_aa r_a).
  std::vector<double> diagonal(static_cast<std::size_t>(4 * m), 0.0);
  for (Eigen::Index a = 0; a < m; ++a)
    for (Eigen::Index k = columns.start[static_cast<std::size_t>(a)];
         k < columns.start[static_cast<std::size_t>(a + 1)]; ++k)
      if (columns.row[static_cast<std::size_t>(k)] == a)
        std::copy_n(&columns.block[static_cast<std::size_t>(4 * k)], 4,
                    &diagonal[static_cast<std::size_t>(4 * a)]);
  Eigen::VectorXd u = p.W * r + p.q;
  NsgsReport report;
  for (int sweep = 1; sweep <= options.max_sweeps; ++sweep) {
    for (Eigen::Index a = 0; a < m; ++a) {
      const double* w = &diagonal[static_cast<std::size_t>(4 * a)];  // nn, nt, tn, tt
      const double rn = r[2 * a], rt = r[2 * a + 1];
      const double bn = u[2 * a] - w[0] * rn - w[1] * rt;
      const double bt = u[2 * a + 1] - w[2] * rn - w[3] * rt;
      const LocalImpulse s = local_solve(w[0], w[1], w[2], w[3], p.mu[a], bn, bt);
      const double dn = s.rn - rn, dt = s.rt - rt;
      r[2 * a] = s.rn;
      r[2 * a + 1] = s.rt;
      if (dn == 0.0 && dt == 0.0) continue;
      for (Eigen::Index k = columns.start[static_cast<std::size_t>(a)];
           k < columns.start[static_cast<std::size_t>(a + 1)]; ++k) {
        const double* blk = &columns.block[static_cast<std::size_t>(4 * k)];
        const Eigen::Index b = columns.row[static_cast<std::size_t>(k)];
        u[2 * b] += blk[0] * dn + blk[1] * dt;
        u[2 * b + 1] += blk[2] * dn + blk[3] * dt;
      }
    }
    report.sweeps = sweep;
    report.residual = natural_map_residual(p, r, u);
    if (!std::isfinite(report.residual)) break;
    // The updated u carries the rounding of many small updates: a solve is accepted, and
    // the reported residual taken, on u recomputed as W r + q.
    const bool last = sweep == options.max_sweeps;
    if (report.residual <= options.tolerance || last) {
      u = p.W * r + p.q;
      report.residual = natural_map_residual(p, r, u);
      if (report.residual <= options.tolerance) {
        report.converged = true;
        break;
      }
    }
  }
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace cdpile::cd
