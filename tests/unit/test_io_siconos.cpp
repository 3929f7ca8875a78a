// Siconos' fc2d text format (io/siconos.hpp) and the Delassus-form solver it feeds
// (cd/delassus.hpp): the reader, its errors on malformed files, and NSGS with the engine's
// local solver on a problem solved by hand and on Siconos' three granular test problems
// (docs/method.md, "Validation"), which must reach the natural-map residual 1e-5 that
// Siconos' own tests ask for. Here in io's tests because every case reads a file.
#include "cdpile/io/siconos.hpp"

#include "cdpile/cd/delassus.hpp"

#include "cdpile/error.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace cd = cdpile::cd;
namespace io = cdpile::io;
namespace fs = std::filesystem;

namespace {

struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() /
           ("cdpile-delassus-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  std::string write(const std::string& name, const std::string& text) const {
    const fs::path file = path / name;
    std::ofstream(file) << text;
    return file.string();
  }
};

// Two contacts, written as Siconos writes them. Normal block [[1, -1/2], [-1/2, 1]],
// tangent blocks 3 (no coupling). By hand: the normal impulses solve
// [[1, -1/2], [-1/2, 1]] r_n = (1, 1), r_n = (2, 2); contact 0 cannot stick
// (-q_t / W_tt = -2 lies outside |r_t| <= 0.5 * 2), so it slides with r_t = -1 and
// u_t = 3 * (-1) + 6 = 3 > 0, opposing r_t; contact 1 sticks with r_t = 0.
// Line numbers are given because the error tests point at them.
const std::string kSmall =
    "2\n"  // 1  dimension
    "2\n"  // 2  contacts
    "2\n"  // 3  storage: sparse
    "4\n"  // 4  rows
    "4\n"  // 5  columns
    "2\n"  // 6  sparse origin
    "CSparse Version 3.1.9, May 4, 2016.  Copyright (c) Timothy A. Davis, 2006-2016\n"  // 7
    "4-by-4, nzmax: 6 nnz: 6, 1-norm: 3\n"                                              // 8
    "    col 0 : locations 0 to 1\n"                                                    // 9
    "      0 : 1\n"                                                                     // 10
    "      2 : -0.5\n"                                                                  // 11
    "    col 1 : locations 2 to 2\n"                                                    // 12
    "      1 : 3\n"                                                                     // 13
    "    col 2 : locations 3 to 4\n"                                                    // 14
    "      0 : -0.5\n"                                                                  // 15
    "      2 : 1\n"                                                                     // 16
    "    col 3 : locations 5 to 5\n"                                                    // 17
    "      3 : 3\n"                                                                     // 18
    "  -1.0e+00   6.0e+00  -1.0e+00   0.0e+00\n"                                        // 19 q
    "  5.0e-01   3.0e-01\n";                                                            // 20 mu

/// kSmall with line `number` (1-based) replaced by `text` (or removed when text is null).
std::string edit_line(int number, const char* text) {
  std::string out, line;
  std::istringstream in(kSmall);
  for (int n = 1; std::getline(in, line); ++n) {
    if (n != number)
      out += line + "\n";
    else if (text)
      out += std::string(text) + "\n";
  }
  return out;
}

/// The message of the cdpile::Error thrown when reading `path`, or "" if none is.
std::string read_error(const std::string& path) {
  try {
    io::read_siconos_fc2d(path);
  } catch (const cdpile::Error& e) {
    return e.what();
  }
  return "";
}

/// The solution checked independently of the residual, contact by contact, with
/// u = W r + q: Signorini (r_n >= 0, u_n >= 0, r_n u_n = 0) and Coulomb (|r_t| <= mu r_n;
/// strictly inside the cone the contact sticks, u_t = 0; on the cone r_t opposes u_t).
/// Every violation is a velocity: an impulse is turned into one by the contact's W_nn.
/// Returns the largest violation over all contacts, to compare with a velocity bound.
struct LawCheck {
  double worst = 0.0;  ///< largest violation [velocity units of the problem]
  int active = 0;      ///< contacts with W_nn r_n above `floor`
  int sliding = 0;     ///< active contacts on the cone (within `floor`)
};
LawCheck check_law(const cd::DelassusProblem& p, const Eigen::VectorXd& r, double floor) {
  const Eigen::VectorXd u = p.W * r + p.q;
  LawCheck c;
  auto at_most = [&](double v) { c.worst = std::max(c.worst, v); };
  for (Eigen::Index a = 0; a < p.contacts(); ++a) {
    const double w = p.W.coeff(2 * a, 2 * a);
    const double rn = w * r[2 * a], rt = w * r[2 * a + 1];  // as velocities
    const double un = u[2 * a], ut = u[2 * a + 1], mu = p.mu[a];
    at_most(-rn);                         // r_n >= 0
    at_most(-un);                         // u_n >= 0
    at_most(std::min(rn, std::abs(un)));  // r_n u_n = 0
    at_most(std::abs(rt) - mu * rn);      // |r_t| <= mu r_n
    if (rn > floor) {
      ++c.active;
      if (mu * rn - std::abs(rt) > floor) {
        at_most(std::abs(ut));  // inside the cone: sticks
      } else {
        ++c.sliding;
        if (std::abs(rt) > floor) at_most(rt > 0.0 ? ut : -ut);  // r_t opposes u_t
      }
    }
  }
  return c;
}

// The 667- and 2020-contact problems are in tests/data/siconos-fc2d (README.md there says
// where they come from). The 7002-contact one (4 MB) is not: its cases run when the
// variable CDPILE_SICONOS_DATA names a folder that holds it (the Siconos repository's
// numerics/src/FrictionContact/test/data), and are left out with a note otherwise.
// Returns the path of the problem, or "" when it is in neither folder.
std::string siconos_file(const std::string& name) {
  std::vector<std::string> dirs;
  if (const char* env = std::getenv("CDPILE_SICONOS_DATA"); env && *env) dirs.emplace_back(env);
  dirs.emplace_back(std::string(CDPILE_TEST_DATA) + "/siconos-fc2d");
  for (const auto& dir : dirs)
    if (fs::is_regular_file(dir + "/" + name)) return dir + "/" + name;
  std::printf("  %s: absent (set CDPILE_SICONOS_DATA to a folder holding it to test it)\n",
              name.c_str());
  return "";
}

}  // namespace

// --- the reader on a small problem written by hand --------------------------------

TEST(SiconosReader, ReadsTheSmallProblem) {
  TempDir dir;
  const auto p = io::read_siconos_fc2d(dir.write("small.dat", kSmall));
  ASSERT_EQ(p.contacts(), 2);
  ASSERT_EQ(p.W.rows(), 4);
  ASSERT_EQ(p.W.cols(), 4);
  EXPECT_EQ(p.W.nonZeros(), 6);
  EXPECT_EQ(p.W.coeff(0, 0), 1.0);
  EXPECT_EQ(p.W.coeff(2, 0), -0.5);
  EXPECT_EQ(p.W.coeff(0, 2), -0.5);
  EXPECT_EQ(p.W.coeff(1, 1), 3.0);
  EXPECT_EQ(p.W.coeff(3, 3), 3.0);
  EXPECT_EQ(p.W.coeff(1, 0), 0.0);
  EXPECT_EQ(p.q[0], -1.0);
  EXPECT_EQ(p.q[1], 6.0);
  EXPECT_EQ(p.q[3], 0.0);
  EXPECT_EQ(p.mu[0], 0.5);
  EXPECT_EQ(p.mu[1], 0.3);
}

// The writer lays the small problem out as Siconos does, line for line from the matrix
// on (its own banner aside), and what it writes reads back bit for bit, values that
// need all 17 digits included.
TEST(SiconosWriter, WritesTheSmallProblemAsSiconosDoesAndReadsBack) {
  TempDir dir;
  const auto p = io::read_siconos_fc2d(dir.write("small.dat", kSmall));
  std::ostringstream out;
  io::write_siconos_fc2d(out, p);
  std::istringstream written(out.str()), expected(kSmall);
  std::string a, b;
  for (int line = 1; std::getline(expected, b); ++line) {
    ASSERT_TRUE(std::getline(written, a)) << "line " << line;
    if (line == 7) {  // the CSparse banner: ours names the writer
      EXPECT_EQ(a.rfind("CSparse Version", 0), 0u);
      continue;
    }
    if (line >= 19) break;  // q and mu: compared as numbers below
    EXPECT_EQ(a, b) << "line " << line;
  }
  auto q = p;
  q.q[0] = 0.1;  // not a short decimal: needs 17 digits
  q.q[1] = -1.0 / 3.0;
  q.mu[1] = std::nextafter(0.3, 1.0);
  std::ostringstream out2;
  io::write_siconos_fc2d(out2, q);
  const auto back = io::read_siconos_fc2d(dir.write("back.dat", out2.str()));
  EXPECT_EQ((Eigen::MatrixXd(back.W) - Eigen::MatrixXd(q.W)).norm(), 0.0);
  EXPECT_EQ(back.q, q.q);
  EXPECT_EQ(back.mu, q.mu);
}

TEST(SiconosReader, ErrorsNameTheFileAndTheLine) {
  TempDir dir;
  struct Case {
    const char* name;
    std::string text;
    const char* where;  // "line N" expected in the message
    const char* what;   // a fragment of the reason
  };
  const Case cases[] = {
      {"truncated-in-column", kSmall.substr(0, kSmall.find("    col 1")), "line 11",
       "expected the header of column 1"},
      {"truncated-before-mu", kSmall.substr(0, kSmall.find("  5.0e-01")), "line 19",
       "expected mu (2 values, 0 read)"},
      {"truncated-in-header", "2\n2\n2\n4\n", "line 4", "expected the column count"},
      {"column-too-short", edit_line(9, "    col 0 : locations 0 to 2"), "line 12",
       "expected a matrix entry"},
      {"column-too-long", edit_line(9, "    col 0 : locations 0 to 0"), "line 11",
       "expected the header of column 1"},
      {"wrong-contact-count", edit_line(2, "3"), "line 5", "expected 2m x 2m = 6 x 6"},
      {"wrong-nnz", edit_line(8, "4-by-4, nzmax: 7 nnz: 7, 1-norm: 3"), "line 18",
       "the size line says 7"},
      {"too-few-q", edit_line(19, "  -1.0e+00   6.0e+00  -1.0e+00"), "line 20",
       "expected mu (2 values, 1 read)"},  // mu's first value is taken as q's last
      {"too-many-values", edit_line(20, "  5.0e-01   3.0e-01  1.0"), "line 20",
       "more values than the 3m = 6"},
      {"non-numeric-entry", edit_line(13, "      1 : abc"), "line 13", "not a number: 'abc'"},
      {"non-numeric-count", edit_line(2, "two"), "line 2", "expected the number of contacts"},
      {"nan-in-q", edit_line(19, "  -1.0e+00   nan  -1.0e+00   0.0e+00"), "line 19",
       "not a finite number: 'nan'"},
      {"inf-in-w", edit_line(16, "      2 : inf"), "line 16", "not a finite number: 'inf'"},
      {"trailing-garbage", edit_line(18, "      3 : 3x"), "line 18", "not a finite number: '3x'"},
      {"row-out-of-range", edit_line(13, "      4 : 3"), "line 13", "row index out of range"},
      {"duplicate-entry", edit_line(11, "      0 : -0.5"), "line 11", "duplicate entry"},
      {"negative-mu", edit_line(20, "  5.0e-01  -3.0e-01"), "line 20",
       "negative friction coefficient"},
      {"three-dimensional", edit_line(1, "3"), "line 1", "only 2D problems"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = dir.write(std::string(c.name) + ".dat", c.text);
    const std::string message = read_error(path);
    EXPECT_NE(message.find(path + ": " + c.where + ": "), std::string::npos) << message;
    EXPECT_NE(message.find(c.what), std::string::npos) << message;
  }
  EXPECT_NE(read_error((dir.path / "absent.dat").string()).find("cannot open"), std::string::npos);
}

// --- NSGS on the small problem ----------------------------------------------------

TEST(SiconosNsgs, SolvesTheSmallProblemAsByHand) {
  TempDir dir;
  const auto p = io::read_siconos_fc2d(dir.write("small.dat", kSmall));
  Eigen::VectorXd r;
  const auto report = cd::solve_nsgs(p, r, {.tolerance = 1e-12, .max_sweeps = 1000});
  ASSERT_TRUE(report.converged) << report.residual;
  EXPECT_LE(report.residual, 1e-12);
  EXPECT_NEAR(r[0], 2.0, 1e-11);
  EXPECT_NEAR(r[1], -1.0, 1e-11);  // slides: on the cone, against u_t = 3
  EXPECT_NEAR(r[2], 2.0, 1e-11);
  EXPECT_NEAR(r[3], 0.0, 1e-11);
  // The exact solution has residual zero; a wrong one does not.
  Eigen::VectorXd exact(4), wrong(4);
  exact << 2.0, -1.0, 2.0, 0.0;
  wrong << 2.0, -0.9, 2.0, 0.0;  // inside the cone while sliding
  EXPECT_LE(cd::natural_map_residual(p, exact), 1e-15);
  EXPECT_GT(cd::natural_map_residual(p, wrong), 1e-3);
  EXPECT_LE(check_law(p, exact, 1e-12).worst, 1e-15);
  EXPECT_EQ(check_law(p, exact, 1e-12).sliding, 1);
  EXPECT_NEAR(check_law(p, wrong, 1e-12).worst, 3.3, 1e-12);  // inside, yet u_t = 3.3
}

// --- Siconos' three granular problems ---------------------------------------------

struct Known {
  const char* file;
  long contacts, nnz;
  // (row, column, value) entries and (index, value) of q, as printed in the file
  struct Entry {
    int row, col;
    double value;
  };
  Entry w[3];
  struct Value {
    int index;
    double value;
  };
  Value q[2];
  // Sweeps Siconos' own fc2d NSGS takes to 1e-5 from r = 0 (python3-siconos 4.4.0,
  // benchmarks/siconos_reference.py): the same iterates take the same number.
  int siconos_sweeps;
};

const Known kProblems[] = {
    {"fc2d_granularflowonwall_00667_00000.dat",
     667,
     3822,
     {{0, 0, 856.713}, {649, 0, -454.43}, {1333, 1333, 2521.06}},
     {{1, 1.084202172485504434007453e-19}, {2, -1.084202172485504434007453e-19}},
     1},
    {"fc2d_granularflowonwall_02020_00213.dat",
     2020,
     20616,
     {{0, 0, 814.288}, {1144, 0, -416.766}, {4038, 4039, -9.72628e-06}},
     {{3, 1.387778780781445675529540e-17}, {4038, -1.461573504837301584746712e-01}},
     806},
    {"fc2d_granularflowonwall_07002_00801.dat",
     7002,
     125806,
     {{1, 0, 64.3983}, {2140, 0, -101.0}, {14003, 14003, 1227.17}},
     {{0, 3.946463423731838560115648e-05}, {14003, -1.764494538685856817039621e-01}},
     1021},
};

TEST(SiconosFc2d, ReadsTheThreeProblems) {
  int tested = 0;
  for (const auto& k : kProblems) {
    SCOPED_TRACE(k.file);
    const std::string file = siconos_file(k.file);
    if (file.empty()) continue;
    ++tested;
    const auto p = io::read_siconos_fc2d(file);
    ASSERT_EQ(p.contacts(), k.contacts);
    EXPECT_EQ(p.W.rows(), 2 * k.contacts);
    EXPECT_EQ(p.W.cols(), 2 * k.contacts);
    EXPECT_EQ(p.W.nonZeros(), k.nnz);
    EXPECT_EQ(p.q.size(), 2 * k.contacts);
    for (const auto& e : k.w) EXPECT_EQ(p.W.coeff(e.row, e.col), e.value) << e.row << "," << e.col;
    for (const auto& v : k.q) EXPECT_EQ(p.q[v.index], v.value) << v.index;
    // Every contact of these files has mu = 0.5.
    EXPECT_EQ(p.mu.minCoeff(), 0.5);
    EXPECT_EQ(p.mu.maxCoeff(), 0.5);
    // W is a Delassus operator: symmetric (to the 6 digits of the file) with positive
    // diagonal.
    const Eigen::SparseMatrix<double, Eigen::RowMajor> asym =
        Eigen::SparseMatrix<double, Eigen::RowMajor>(p.W.transpose()) - p.W;
    double worst = 0.0;
    for (int row = 0; row < asym.outerSize(); ++row)
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(asym, row); it; ++it)
        worst = std::max(worst, std::abs(it.value()) / p.W.coeff(row, row));
    EXPECT_LT(worst, 1e-5);
    EXPECT_GT(p.W.diagonal().minCoeff(), 0.0);
  }
  EXPECT_GE(tested, 2) << "tests/data/siconos-fc2d holds two of the problems";
}

TEST(SiconosFc2d, NsgsReachesTheNaturalMapResidual) {
  const double tolerance = 1e-5;
  int tested = 0;
  for (const auto& k : kProblems) {
    SCOPED_TRACE(k.file);
    const std::string file = siconos_file(k.file);
    if (file.empty()) continue;
    ++tested;
    const auto p = io::read_siconos_fc2d(file);
    Eigen::VectorXd r;
    const auto report = cd::solve_nsgs(p, r, {.tolerance = tolerance, .max_sweeps = 10000});
    const double norm_q = p.q.norm();
    const LawCheck law = check_law(p, r, tolerance * norm_q);
    std::printf(
        "  %s: %ld contacts, |q| %.3e, %d sweeps, residual %.3e, %.3f s, "
        "%d active, %d sliding, worst violation %.3e\n",
        k.file, k.contacts, norm_q, report.sweeps, report.residual, report.seconds, law.active,
        law.sliding, law.worst);
    ASSERT_TRUE(report.converged) << report.sweeps << " sweeps, residual " << report.residual;
    EXPECT_LE(report.residual, tolerance);
    EXPECT_EQ(cd::natural_map_residual(p, r), report.residual);
    EXPECT_EQ(report.sweeps, k.siconos_sweeps);
    if (norm_q > 1e-15) {
      // The residual, in velocity units, is tolerance * |q|: no contact may break the law
      // by more than that.
      EXPECT_LE(law.worst, tolerance * norm_q);
      EXPECT_GT(law.active, k.contacts / 10);  // a loaded pile, not a trivial answer
      EXPECT_GT(law.sliding, 0);
    } else {
      // The 667-contact file's q is round-off of zero (|q| ~ 4e-18, below DBL_EPSILON,
      // where Siconos' residual is absolute); its solution is r = 0 to round-off, and no
      // contact may break the law by more than the size of q itself.
      EXPECT_LE(law.worst, norm_q);
      EXPECT_LE((p.W * r).norm(), norm_q);
    }
  }
  EXPECT_GE(tested, 2) << "tests/data/siconos-fc2d holds two of the problems";
}

TEST(SiconosFc2d, HittingTheSweepCapIsReported) {
  const std::string file = siconos_file(kProblems[1].file);
  ASSERT_FALSE(file.empty()) << "tests/data/siconos-fc2d holds this problem";
  const auto p = io::read_siconos_fc2d(file);
  Eigen::VectorXd r;
  const auto report = cd::solve_nsgs(p, r, {.tolerance = 1e-5, .max_sweeps = 20});
  EXPECT_FALSE(report.converged);
  EXPECT_EQ(report.sweeps, 20);
  EXPECT_GT(report.residual, 1e-5);
  EXPECT_EQ(cd::natural_map_residual(p, r), report.residual);
}
