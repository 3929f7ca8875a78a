// Siconos' fc2d text format, read and written (siconos.hpp): how Delassus problems reach
// other codes and come back from them (docs/method.md, "Delassus problems from other
// codes").
#include "cdpile/io/siconos.hpp"

#include "cdpile/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace cdpile::io {

using cd::DelassusProblem;

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

}  // namespace cdpile::io
