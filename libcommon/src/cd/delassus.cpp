// Delassus-form 2D frictional contact problems: the Siconos text reader, the natural-map
// residual and NSGS with the engine's exact local solver (delassus.hpp).
#include "cdpile/cd/delassus.hpp"

#include "cdpile/cd/local_solver.hpp"
#include "cdpile/check.hpp"
#include "cdpile/error.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace cdpile::cd {

namespace {

/// Line-by-line reader that names the file and line in every error.
class LineReader {
 public:
  explicit LineReader(const std::string& path) : path_(path), in_(path) {
    if (!in_) throw Error(path, "", "cannot open the file");
  }
  bool next(std::string& line) {
    while (std::getline(in_, line)) {
      ++number_;
      if (line.find_first_not_of(" \t\r") != std::string::npos) return true;
    }
    return false;
  }
  std::string get(const std::string& what) {
    std::string line;
    if (!next(line)) fail("unexpected end of file, expected " + what);
    return line;
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw Error(path_, "line " + std::to_string(number_), what);
  }
  long integer(const std::string& line, const std::string& what) const {
    std::istringstream s(line);
    long v = 0;
    std::string rest;
    if (!(s >> v) || (s >> rest)) fail("expected " + what + ", got '" + line + "'");
    return v;
  }

 private:
  std::string path_;
  std::ifstream in_;
  long number_ = 0;
};

double parse_real(const std::string& token, const LineReader& lines) {
  std::size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(token, &used);
  } catch (const std::exception&) {
    lines.fail("not a number: '" + token + "'");
  }
  if (used != token.size() || !std::isfinite(v)) lines.fail("not a finite number: '" + token + "'");
  return v;
}

}  // namespace

DelassusProblem read_siconos_fc2d(const std::string& path) {
  LineReader lines(path);
  if (lines.integer(lines.get("the dimension"), "the dimension") != 2)
    lines.fail("only 2D problems (dimension 2) are supported");
  const long m = lines.integer(lines.get("the number of contacts"), "the number of contacts");
  if (m < 1 || m > 100000000) lines.fail("bad number of contacts");
  if (lines.integer(lines.get("the storage code"), "the storage code") != 2)
    lines.fail("only sparse storage (code 2) is supported");
  const long rows = lines.integer(lines.get("the row count"), "the row count");
  const long cols = lines.integer(lines.get("the column count"), "the column count");
  if (rows != 2 * m || cols != 2 * m)
    lines.fail("the matrix is " + std::to_string(rows) + " x " + std::to_string(cols) +
               ", expected 2m x 2m = " + std::to_string(2 * m) + " x " + std::to_string(2 * m));
  lines.get("the sparse origin code");
  std::string line = lines.get("the CSparse banner");
  if (line.find("CSparse") == std::string::npos) lines.fail("expected a CSparse listing");
  // "R-by-C, nzmax: Z nnz: N, 1-norm: X": the entry count N is checked against the listing.
  line = lines.get("the CSparse size line");
  long size_r = 0, size_c = 0, nnz = -1;
  {
    const auto by = line.find("-by-");
    const auto at = line.find("nnz:");
    if (by == std::string::npos || at == std::string::npos)
      lines.fail("expected 'R-by-C, nzmax: Z nnz: N, ...', got '" + line + "'");
    std::istringstream r(line.substr(0, by)), c(line.substr(by + 4)), n(line.substr(at + 4));
    if (!(r >> size_r) || !(c >> size_c) || !(n >> nnz) || size_r != rows || size_c != cols ||
        nnz < 0)
      lines.fail("the CSparse size line '" + line + "' does not match the matrix");
  }

  // cs_print lists every column in order, "col j : locations a to b" (b = a - 1 when the
  // column is empty) followed by its b - a + 1 entries "row : value"; locations run on
  // from one column to the next.
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<std::size_t>(nnz));
  long location = 0;
  std::vector<long> seen_in(static_cast<std::size_t>(rows), -1);  // last column with the row
  for (long col = 0; col < cols; ++col) {
    line = lines.get("the header of column " + std::to_string(col));
    std::istringstream s(line);
    std::string word_col, word_loc, word_to;
    long j = -1, a = -1, b = -1;
    char colon = 0;
    if (!(s >> word_col >> j >> colon >> word_loc >> a >> word_to >> b) || word_col != "col" ||
        colon != ':' || word_loc != "locations" || word_to != "to")
      lines.fail("expected the header of column " + std::to_string(col) + ", got '" + line + "'");
    if (j != col || a != location || b < a - 1)
      lines.fail("column header '" + line + "' out of sequence (expected column " +
                 std::to_string(col) + " from location " + std::to_string(location) + ")");
    for (long k = a; k <= b; ++k) {
      line = lines.get("entry " + std::to_string(k - a + 1) + " of column " + std::to_string(col));
      std::istringstream e(line);
      long row = -1;
      char c = 0;
      std::string value, rest;
      if (!(e >> row >> c >> value) || c != ':' || (e >> rest))
        lines.fail("expected a matrix entry 'row : value' in column " + std::to_string(col) +
                   ", got '" + line + "'");
      if (row < 0 || row >= rows) lines.fail("row index out of range in '" + line + "'");
      if (seen_in[static_cast<std::size_t>(row)] == col)
        lines.fail("duplicate entry for row " + std::to_string(row) + " in column " +
                   std::to_string(col));
      seen_in[static_cast<std::size_t>(row)] = col;
      entries.emplace_back(static_cast<int>(row), static_cast<int>(col), parse_real(value, lines));
    }
    location = b + 1;
  }
  if (location != nnz)
    lines.fail("the listing holds " + std::to_string(location) + " entries, the size line says " +
               std::to_string(nnz));

  // q (2m values), then mu (m values); Siconos writes one line each, but only the order
  // of the values matters here.
  std::vector<double> numbers;
  numbers.reserve(static_cast<std::size_t>(3 * m));
  const auto expect = static_cast<std::size_t>(3 * m);
  while (numbers.size() < expect) {
    const bool in_q = numbers.size() < static_cast<std::size_t>(2 * m);
    line = lines.get(in_q ? "q (" + std::to_string(2 * m) + " values, " +
                                std::to_string(numbers.size()) + " read)"
                          : "mu (" + std::to_string(m) + " values, " +
                                std::to_string(numbers.size() - 2 * m) + " read)");
    std::istringstream s(line);
    std::string token;
    while (s >> token) {
      if (numbers.size() == expect)
        lines.fail("more values than the 3m = " + std::to_string(expect) + " of q and mu");
      numbers.push_back(parse_real(token, lines));
      if (numbers.size() > static_cast<std::size_t>(2 * m) && numbers.back() < 0.0)
        lines.fail("negative friction coefficient '" + token + "'");
    }
  }
  if (lines.next(line)) lines.fail("unexpected content after mu: '" + line + "'");

  DelassusProblem p;
  p.W.resize(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
  p.W.setFromTriplets(entries.begin(), entries.end());
  p.q = Eigen::Map<Eigen::VectorXd>(numbers.data(), 2 * m);
  p.mu = Eigen::Map<Eigen::VectorXd>(numbers.data() + 2 * m, m);
  return p;
}

void write_siconos_fc2d(std::ostream& out, const DelassusProblem& p) {
  const Eigen::Index m = p.contacts();
  if (p.W.rows() != 2 * m || p.W.cols() != 2 * m || p.q.size() != 2 * m)
    throw Error("write_siconos_fc2d: W and q do not match the " + std::to_string(m) + " contacts");
  const Eigen::SparseMatrix<double, Eigen::ColMajor> W = p.W;  // cs_print lists columns
  char buf[64];
  auto real = [&](double v) {
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
  };
  double norm1 = 0.0;  // the largest column sum of |W|, as cs_print states it
  for (Eigen::Index j = 0; j < W.outerSize(); ++j) {
    double sum = 0.0;
    for (Eigen::SparseMatrix<double, Eigen::ColMajor>::InnerIterator it(W, j); it; ++it)
      sum += std::abs(it.value());
    norm1 = std::max(norm1, sum);
  }
  out << 2 << '\n' << m << '\n' << 2 << '\n' << 2 * m << '\n' << 2 * m << '\n' << 2 << '\n';
  out << "CSparse Version 3.1.9, written by cdpile (cs_print layout)\n";
  out << 2 * m << "-by-" << 2 * m << ", nzmax: " << W.nonZeros() << " nnz: " << W.nonZeros()
      << ", 1-norm: " << real(norm1) << '\n';
  Eigen::Index location = 0;
  for (Eigen::Index j = 0; j < W.outerSize(); ++j) {
    const Eigen::Index count = W.outerIndexPtr()[j + 1] - W.outerIndexPtr()[j];
    out << "    col " << j << " : locations " << location << " to " << location + count - 1 << '\n';
    for (Eigen::SparseMatrix<double, Eigen::ColMajor>::InnerIterator it(W, j); it; ++it)
      out << "      " << it.row() << " : " << real(it.value()) << '\n';
    location += count;
  }
  for (Eigen::Index k = 0; k < 2 * m; ++k) out << real(p.q[k]) << (k + 1 < 2 * m ? " " : "\n");
  for (Eigen::Index k = 0; k < m; ++k) out << real(p.mu[k]) << (k + 1 < m ? " " : "\n");
  out.flush();
  if (!out) throw Error("write_siconos_fc2d: the stream failed");
}

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
