// Delassus-form 2D frictional contact problems: the natural-map residual and NSGS, the
// engine's Gauss-Seidel pass (nsgs.hpp) over W's blocks (delassus.hpp). The files that
// carry them are io's (io/siconos.hpp).
#include "cdpile/cd/delassus.hpp"

#include "cdpile/cd/local_solver.hpp"
#include "cdpile/cd/nsgs.hpp"
#include "cdpile/check.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
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

// The rows of H are those of the sweep: u_n = (v_i - v_j).n and
// u_t = (v_i - v_j).t - w_i r_i - w_j r_j, with t = (-n_y, n_x); a body that does not move
// (a glued grain, or the walls' static body) has a zero inverse mass and drops out of W.
DelassusProblem delassus_problem(const ContactSystem& s) {
  const auto m = static_cast<Eigen::Index>(s.rows.size());
  const auto n = static_cast<Eigen::Index>(s.bodies.size());
  std::vector<Eigen::Triplet<double>> h, hm;  // H and H M^-1
  h.reserve(12 * s.rows.size());
  hm.reserve(12 * s.rows.size());
  auto add = [&](Eigen::Index row, std::int32_t body, double x, double y, double w, double sign) {
    const Body& b = s.bodies[static_cast<std::size_t>(body)];
    if (!moves(b)) return;  // the walls, a glued grain
    const Eigen::Index c = 3 * static_cast<Eigen::Index>(body);
    const double v[3] = {sign * x, sign * y, w};
    const double inv[3] = {b.inv_m, b.inv_m, b.inv_i};
    for (int k = 0; k < 3; ++k) {
      if (v[k] == 0.0 || inv[k] == 0.0) continue;
      h.emplace_back(row, c + k, v[k]);
      hm.emplace_back(row, c + k, v[k] * inv[k]);
    }
  };
  std::vector<double> mu(s.rows.size());
  Eigen::VectorXd r(2 * m);
  for (Eigen::Index a = 0; a < m; ++a) {
    const ContactRow& row = s.rows[static_cast<std::size_t>(a)];
    add(2 * a, row.bi, row.nx, row.ny, 0.0, 1.0);
    add(2 * a, row.bj, row.nx, row.ny, 0.0, -1.0);
    add(2 * a + 1, row.bi, -row.ny, row.nx, -row.ri, 1.0);
    add(2 * a + 1, row.bj, -row.ny, row.nx, -row.rj, -1.0);
    mu[static_cast<std::size_t>(a)] = row.mu;
    r[2 * a] = row.rn;
    r[2 * a + 1] = row.rt;
  }
  DelassusProblem p;
  p.mu = Eigen::Map<const Eigen::VectorXd>(mu.data(), m);
  Eigen::SparseMatrix<double, Eigen::RowMajor> H(2 * m, 3 * n), HM(2 * m, 3 * n);
  H.setFromTriplets(h.begin(), h.end());
  HM.setFromTriplets(hm.begin(), hm.end());
  p.W = HM * Eigen::SparseMatrix<double, Eigen::RowMajor>(H.transpose());
  // q = u - W r: the bodies hold v = v_free + M^-1 H^T R, so the local velocities less
  // W r are the free ones (to rounding).
  p.q = -(p.W * r);
  for (Eigen::Index a = 0; a < m; ++a) {
    const ContactRow& row = s.rows[static_cast<std::size_t>(a)];
    const Body& bi = s.bodies[static_cast<std::size_t>(row.bi)];
    const Body& bj = s.bodies[static_cast<std::size_t>(row.bj)];
    const double dvx = bi.vx - bj.vx, dvy = bi.vy - bj.vy;
    p.q[2 * a] += dvx * row.nx + dvy * row.ny + row.gap_velocity;
    p.q[2 * a + 1] += -dvx * row.ny + dvy * row.nx - bi.w * row.ri - bj.w * row.rj;
  }
  // The compliance of the force-selection rule: C on the diagonal, -C R0 in q.
  if (s.compliant()) {
    for (Eigen::Index a = 0; a < m; ++a) {
      const ContactRow& row = s.rows[static_cast<std::size_t>(a)];
      p.q[2 * a] -= s.compliance_n * row.rn0;
      p.q[2 * a + 1] -= s.compliance_t * row.rt0;
      p.W.coeffRef(2 * a, 2 * a) += s.compliance_n;
      p.W.coeffRef(2 * a + 1, 2 * a + 1) += s.compliance_t;
    }
  }
  return p;
}

double natural_map_residual(const DelassusProblem& p, const Eigen::VectorXd& r) {
  const Eigen::VectorXd u = p.W * r + p.q;
  return natural_map_residual(p, r, u);
}

namespace {

/// A contact of a Delassus problem as the NSGS pass sees it (nsgs.hpp, sweep_rows).
struct DelassusRow {
  Eigen::Index a;                 ///< the contact: components 2a (normal), 2a + 1 (tangent)
  double w_nn, w_nt, w_tn, w_tt;  ///< its diagonal block W_aa
  double mu;
  double rn, rt;
  ContactStatus status;
};

/// A general W's block is full: the 2x2 local solve (local_solver.hpp).
LocalImpulse local_solve(const DelassusRow& r, double b_n, double b_t) {
  return cd::local_solve(r.w_nn, r.w_nt, r.w_tn, r.w_tt, r.mu, b_n, b_t);
}

/// The rows of a problem from the impulses r, the diagonal blocks taken from W's column
/// blocks (zero where W has none).
std::vector<DelassusRow> delassus_rows(const DelassusProblem& p, const BlockColumns& columns,
                                       const Eigen::VectorXd& r) {
  std::vector<DelassusRow> rows(static_cast<std::size_t>(p.contacts()));
  for (Eigen::Index a = 0; a < p.contacts(); ++a) {
    DelassusRow& c = rows[static_cast<std::size_t>(a)];
    c = {a, 0.0, 0.0, 0.0, 0.0, p.mu[a], r[2 * a], r[2 * a + 1], ContactStatus::open};
    for (Eigen::Index k = columns.start[static_cast<std::size_t>(a)];
         k < columns.start[static_cast<std::size_t>(a + 1)]; ++k)
      if (columns.row[static_cast<std::size_t>(k)] == a) {
        const double* w = &columns.block[static_cast<std::size_t>(4 * k)];
        c.w_nn = w[0];
        c.w_nt = w[1];
        c.w_tn = w[2];
        c.w_tt = w[3];
      }
  }
  return rows;
}

/// The velocities side of the pass: u = W r + q, kept current as the engine keeps its
/// grains' velocities (each change of r_a scattered through its column block), so a sweep
/// and its residual cost one pass over W.
struct DelassusVelocities {
  const BlockColumns& columns;
  Eigen::VectorXd& u;

  /// b_a = u_a - W_aa r_a: the velocity with the contact's own impulse removed.
  void free_local_velocity(const DelassusRow& r, double& b_n, double& b_t) const {
    b_n = u[2 * r.a] - r.w_nn * r.rn - r.w_nt * r.rt;
    b_t = u[2 * r.a + 1] - r.w_tn * r.rn - r.w_tt * r.rt;
  }
  void apply_impulse(const DelassusRow& r, double dn, double dt) {
    for (Eigen::Index k = columns.start[static_cast<std::size_t>(r.a)];
         k < columns.start[static_cast<std::size_t>(r.a + 1)]; ++k) {
      const double* blk = &columns.block[static_cast<std::size_t>(4 * k)];
      const Eigen::Index b = columns.row[static_cast<std::size_t>(k)];
      u[2 * b] += blk[0] * dn + blk[1] * dt;
      u[2 * b + 1] += blk[2] * dn + blk[3] * dt;
    }
  }
};

}  // namespace

NsgsReport solve_nsgs(const DelassusProblem& p, Eigen::VectorXd& r, const NsgsOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const Eigen::Index m = p.contacts();
  CDPILE_DEBUG_CHECK(p.W.rows() == 2 * m && p.W.cols() == 2 * m && p.q.size() == 2 * m,
                     "W is 2m x 2m and q has 2m values for m = " + std::to_string(m) + " contacts");
  if (r.size() != 2 * m) r = Eigen::VectorXd::Zero(2 * m);
  const BlockColumns columns = block_columns(p);
  std::vector<DelassusRow> rows = delassus_rows(p, columns, r);
  Eigen::VectorXd u = p.W * r + p.q;
  DelassusVelocities velocities{columns, u};
  NsgsReport report;
  for (int sweep = 1; sweep <= options.max_sweeps; ++sweep) {
    // Contacts in file order, every sweep forward, as Siconos' fc2d NSGS sweeps them.
    sweep_rows(
        velocities, [&](std::size_t k) -> DelassusRow& { return rows[k]; }, 0, rows.size(), false);
    for (const DelassusRow& c : rows) {
      r[2 * c.a] = c.rn;
      r[2 * c.a + 1] = c.rt;
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
