// Delassus-form 2D frictional contact problems: the Siconos text reader, the natural-map
// residual and NSGS with the engine's exact local solver (delassus.hpp).
#include "cdpile/cd/delassus.hpp"

#include "cdpile/cd/local_solver.hpp"
#include "cdpile/error.hpp"

#include <chrono>
#include <cmath>
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
  if (rows != 2 * m || cols != 2 * m) lines.fail("the matrix is not 2m x 2m");
  lines.get("the sparse origin code");
  std::string line = lines.get("the CSparse banner");
  if (line.find("CSparse") == std::string::npos) lines.fail("expected a CSparse listing");
  line = lines.get("the CSparse size line");
  if (line.find("-by-") == std::string::npos) lines.fail("expected 'N-by-N, nzmax: ...'");

  std::vector<Eigen::Triplet<double>> entries;
  long col = -1, expected = 0;
  while (lines.next(line)) {
    std::istringstream s(line);
    std::string first;
    s >> first;
    if (first == "col") {
      if (expected != 0) lines.fail("column " + std::to_string(col) + " has too few entries");
      long a = 0, b = 0;
      char colon = 0;
      std::string word, to;
      if (!(s >> col >> colon >> word >> a >> to >> b) || colon != ':' || col < 0 ||
          col >= cols || b < a - 1)
        lines.fail("bad column header '" + line + "'");
      expected = b - a + 1;
      continue;
    }
    if (expected == 0) break;  // the first line of q
    long row = 0;
    char colon = 0;
    std::string value;
    std::istringstream e(line);
    if (!(e >> row >> colon >> value) || colon != ':' || row < 0 || row >= rows)
      lines.fail("bad matrix entry '" + line + "'");
    entries.emplace_back(static_cast<int>(row), static_cast<int>(col), parse_real(value, lines));
    --expected;
  }
  if (expected != 0) lines.fail("the matrix listing is truncated");

  std::vector<double> numbers;
  do {
    std::istringstream s(line);
    std::string token;
    while (s >> token) numbers.push_back(parse_real(token, lines));
  } while (lines.next(line));
  if (numbers.size() != static_cast<std::size_t>(3 * m))
    lines.fail("expected " + std::to_string(3 * m) + " values for q and mu, found " +
               std::to_string(numbers.size()));

  DelassusProblem p;
  p.W.resize(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
  p.W.setFromTriplets(entries.begin(), entries.end());
  p.q = Eigen::Map<Eigen::VectorXd>(numbers.data(), 2 * m);
  p.mu = Eigen::Map<Eigen::VectorXd>(numbers.data() + 2 * m, m);
  for (Eigen::Index a = 0; a < m; ++a)
    if (!(p.mu[a] >= 0.0)) throw Error(path, "mu", "negative friction coefficient");
  return p;
}

double natural_map_residual(const DelassusProblem& p, const Eigen::VectorXd& r) {
  const Eigen::VectorXd u = p.W * r + p.q;
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

NsgsReport solve_nsgs(const DelassusProblem& p, Eigen::VectorXd& r, const NsgsOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const Eigen::Index m = p.contacts();
  if (r.size() != 2 * m) r = Eigen::VectorXd::Zero(2 * m);
  // The diagonal 2x2 blocks, kept apart: the sweep needs W_aa to remove a contact's own
  // impulse from its velocity (b_a = (W r)_a + q_a - W_aa r_a).
  std::vector<double> block(static_cast<std::size_t>(4 * m), 0.0);
  for (Eigen::Index row = 0; row < 2 * m; ++row)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(p.W, row); it; ++it)
      if (it.col() / 2 == row / 2)
        block[static_cast<std::size_t>(4 * (row / 2) + 2 * (row % 2) + it.col() % 2)] = it.value();
  NsgsReport report;
  for (int sweep = 1; sweep <= options.max_sweeps; ++sweep) {
    for (Eigen::Index a = 0; a < m; ++a) {
      const double* w = &block[static_cast<std::size_t>(4 * a)];  // nn, nt, tn, tt
      const double un = p.W.row(2 * a).dot(r) + p.q[2 * a];
      const double ut = p.W.row(2 * a + 1).dot(r) + p.q[2 * a + 1];
      const double rn = r[2 * a], rt = r[2 * a + 1];
      const double bn = un - w[0] * rn - w[1] * rt;
      const double bt = ut - w[2] * rn - w[3] * rt;
      const LocalImpulse s = local_solve(w[0], w[1], w[2], w[3], p.mu[a], bn, bt);
      r[2 * a] = s.rn;
      r[2 * a + 1] = s.rt;
    }
    report.sweeps = sweep;
    report.residual = natural_map_residual(p, r);
    if (!std::isfinite(report.residual)) break;
    if (report.residual <= options.tolerance) {
      report.converged = true;
      break;
    }
  }
  report.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace cdpile::cd
