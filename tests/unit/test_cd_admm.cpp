// The factorised solver (admm.hpp; docs/method.md, "The factorised solver") on scenes whose
// answers are known by hand, at k = 1e6 and 1e8 m g / D and rigid: ADMM alone on the
// step's Delassus problem (solve_admm), and the solver behind the seam in the engine.
#include "cd_scenes.hpp"
#include "cdpile/cd/admm.hpp"
#include "cdpile/cd/delassus.hpp"
#include "cdpile/cd/engine.hpp"
#include "cdpile/cd/solver.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace cd = cdpile::cd;
using cdpile::Box;
using cdpile::ContactStatus;
using cdpile::Grains;
using cdpile::Vec2;

namespace {

using cd_scenes::kDeg;
using cd_scenes::kG;
using cd_scenes::kR;
using cd_scenes::kRho;
constexpr double kH = 1e-4;

/// The stiffnesses of the tests, in m g / D (0: rigid contacts).
constexpr double kStiffnesses[] = {0.0, 1e6, 1e8};

/// k [N/m^2] of a stiffness in m g / D for disks of mass m and radius kR.
double in_newtons(double stiffness, double m) { return stiffness * m * kG / (2 * kR); }

cd::Settings admm(double stiffness, double m) {
  cd::Settings s;
  s.solver = cd::SolverKind::admm;
  s.tolerance = 1e-9;
  s.max_sweeps = 100000;
  s.contact_stiffness = in_newtons(stiffness, m);
  return s;
}

cd::AdmmOptions tight_options(double compliance) {
  cd::AdmmOptions o;
  o.tolerance = 1e-9;
  o.velocity_floor = kG * kH;
  o.compliance = compliance;
  o.max_iterations = 5000;
  return o;
}

}  // namespace

// The law's residual counts a negative normal impulse as a violation (R_n >= 0), also at a
// contact that separates, where the law asks R = 0: a disk leaving the floor at 1e-3 m/s
// with R_n = -1e-6 is off by W_nn 1e-6 (the finish's check, docs/method.md, "Finishing a
// step by its active set", must not accept it).
TEST(Admm, TheLawResidualCountsANegativeNormalImpulse) {
  cd::DelassusProblem p;
  p.W.resize(2, 2);
  p.W.insert(0, 0) = 2.0;
  p.W.insert(1, 1) = 6.0;
  p.q = Eigen::Vector2d(1e-3, 0.0);
  p.mu = Eigen::VectorXd::Constant(1, 0.5);
  EXPECT_EQ(cd::admm_law_residual(p, Eigen::Vector2d(0.0, 0.0), 1.0), 0.0);
  EXPECT_DOUBLE_EQ(cd::admm_law_residual(p, Eigen::Vector2d(-1e-6, 0.0), 1.0), 2e-6);
}

// A disk with its rotation locked on the floor of a tilted box (mu = 0.5): at 20 degrees
// (tan 20 < mu) it sticks with f = m g (cos, sin); at 30 degrees it slides with f_n =
// m g cos 30, |f_t| = mu f_n and the acceleration g (sin 30 - mu cos 30). Every step
// converges with the law's residual below the tolerance, rigid and compliant.
TEST(Admm, InclineSticksAndSlidesWithMu) {
  Grains g;
  g.add_disk(kR, kRho, Vec2(0.05, kR));
  const double m = g.mass[0], mg = m * kG;
  for (const double stiffness : kStiffnesses) {
    for (const double tilt : {20.0, 30.0}) {
      cd::Engine e(Box{0.5, 0.05}, g, admm(stiffness, m));
      e.lock_rotation(0);
      cd::StepReport rep;
      for (int n = 0; n < 200; ++n) {
        rep = e.step(tilt * kDeg);
        ASSERT_TRUE(rep.converged) << stiffness << " " << tilt << " step " << n;
        EXPECT_LT(rep.law_residual, 1e-9) << stiffness << " " << tilt << " step " << n;
      }
      const auto c = e.contacts();
      ASSERT_EQ(c.size(), 1u);
      EXPECT_NEAR(c.fn[0], mg * std::cos(tilt * kDeg), 1e-8 * mg) << stiffness << " " << tilt;
      const double ft = tilt < 25.0 ? mg * std::sin(tilt * kDeg) : 0.5 * c.fn[0];
      EXPECT_NEAR(std::abs(c.ft[0]), ft, 1e-8 * mg) << stiffness << " " << tilt;
      EXPECT_EQ(c.status[0], tilt < 25.0 ? ContactStatus::stick : ContactStatus::slide);
      if (tilt > 25.0) {
        // From rest a compliant contact takes a few steps to load: the velocity lags the
        // rigid one by at most that.
        const double a = kG * (std::sin(tilt * kDeg) - 0.5 * std::cos(tilt * kDeg));
        const double lag = stiffness > 0.0 ? 3 * kG * kH : 0.0;
        EXPECT_NEAR(e.grains().velocity[0].x(), a * 200 * kH, 1e-10 + lag) << stiffness;
      }
    }
  }
}

// A column of 10 disks on the floor: the contact under the n-th disk from the top carries
// n m g, rigid and at k = 1e6 and 1e8 m g / D.
TEST(Admm, ColumnCarriesTheWeightAbove) {
  const int k = 10;
  Grains g;
  for (int n = 0; n < k; ++n) g.add_disk(kR, kRho, Vec2(0.01, kR + 2 * kR * n));
  const double mg = g.mass[0] * kG;
  for (const double stiffness : kStiffnesses) {
    cd::Engine e(Box{0.02, 0.02}, g, admm(stiffness, g.mass[0]));
    cd::StepReport rep;
    for (int step = 0; step < 400; ++step) {
      rep = e.step(0.0);
      ASSERT_TRUE(rep.converged) << stiffness << " step " << step;
    }
    EXPECT_LT(rep.law_residual, 1e-9) << stiffness;
    const auto c = e.contacts();
    ASSERT_EQ(c.size(), static_cast<std::size_t>(k));
    for (std::size_t q = 0; q < c.size(); ++q) {
      const int carried = c.j[q] < 0 ? k : k - 1 - c.i[q];
      EXPECT_NEAR(c.fn[q], carried * mg, 1e-6 * k * mg) << "contact " << q << " k " << stiffness;
    }
  }
}

// ADMM alone on a step's problem (the engine's column, exported after its first step):
// from zero impulses, with De Saxce's shift inside the iteration, it reaches the tolerance
// and the impulses the engine's pcg found, at each stiffness.
TEST(Admm, AloneSolvesTheStepProblemFromZero) {
  const int k = 10;
  Grains g;
  for (int n = 0; n < k; ++n) g.add_disk(kR, kRho, Vec2(0.01, kR + 2 * kR * n));
  for (const double stiffness : kStiffnesses) {
    cd::Settings s = admm(stiffness, g.mass[0]);
    s.solver = cd::SolverKind::pcg;
    s.tolerance = 1e-12;
    cd::Engine e(Box{0.02, 0.02}, g, s);
    for (int step = 0; step < 5; ++step) e.step(0.0);
    const cd::DelassusProblem p = e.delassus_problem();
    const Eigen::VectorXd engine = e.local_impulses();
    Eigen::VectorXd r = Eigen::VectorXd::Zero(engine.size());
    const double c = stiffness > 0.0 ? 1.0 / (s.contact_stiffness * kH * kH) : 0.0;
    const cd::AdmmReport rep = cd::solve_admm(p, r, tight_options(c));
    EXPECT_TRUE(rep.converged) << stiffness << ": " << rep.residual;
    EXPECT_LE(rep.iterations, 1000) << stiffness;
    EXPECT_LT(cd::admm_law_residual(p, r, kG * kH), 1e-9) << stiffness;
    const double mgh = g.mass[0] * kG * kH;
    for (Eigen::Index q = 0; q < r.size(); ++q)
      EXPECT_NEAR(r[q], engine[q], 1e-6 * mgh) << "component " << q << " k " << stiffness;
  }
}

// The hyperstatic wedge (test_cd_solver.cpp, ForceSelection): a disk held between two
// walls by friction alone. With the compliance anchored at R0_n = 2 m g h the solution is
// unique, R_n = 2 m g h and R_t = m g h / 2 on both walls, and ADMM finds it from either
// start at k = 1e6 and 1e8. Rigid, the step is indeterminate (the disk sticks with any
// R_n >= m g h, or slides with R_t = mu R_n and any smaller R_n): started at a solution
// ADMM keeps it; started elsewhere it returns one of them (the proximal selection,
// docs/method.md "The factorised solver").
TEST(Admm, HyperstaticWedge) {
  const double m = kRho * std::numbers::pi * kR * kR, mgh = m * kG * kH;
  for (const double stiffness : {1e6, 1e8}) {
    const double k = in_newtons(stiffness, m);
    for (const double start : {1.0, 5.0}) {
      cd_scenes::Wedge w = cd_scenes::wedged_disk(start * mgh, 2.0 * mgh, 0.5 * mgh, k, kH);
      const cd::SolveReport rep = cd::make_solver(admm(stiffness, m))->solve(w.system, kG * kH);
      EXPECT_TRUE(rep.converged);
      for (const cd::ContactRow& r : w.system.rows) {
        EXPECT_NEAR(r.rn, 2.0 * mgh, 1e-6 * mgh) << "k " << stiffness << ", start " << start;
        EXPECT_NEAR(std::abs(r.rt), 0.5 * mgh, 1e-6 * mgh);
        EXPECT_EQ(r.status, ContactStatus::stick);
      }
      EXPECT_LT(cd::law_residual(w.system, kG * kH).max, 1e-8);
    }
  }
  // Rigid: a solution is kept.
  {
    cd_scenes::Wedge w = cd_scenes::wedged_disk(5.0 * mgh, 0.0, 0.5 * mgh, 0.0, kH);
    const cd::DelassusProblem p = cd::delassus_problem(w.system);
    Eigen::VectorXd r(4);
    r << 5.0 * mgh, -0.5 * mgh, 5.0 * mgh, 0.5 * mgh;
    const Eigen::VectorXd start = r;
    const cd::AdmmReport rep = cd::solve_admm(p, r, tight_options(0.0));
    EXPECT_TRUE(rep.converged);
    EXPECT_EQ(rep.iterations, 0);
    EXPECT_EQ(r, start);
  }
  // Rigid, started without friction (R_n = 2 m g h, R_t = 0: not a solution, the disk
  // would fall with its friction inside the cone). ADMM returns one of the indeterminate
  // step's solutions, symmetric: here the disk slides down with R_t = mu R_n on both
  // walls and R_n = 0.70 m g h (the proximal path's choice, neither the start's R_n nor
  // the sticking solutions).
  {
    cd_scenes::Wedge w = cd_scenes::wedged_disk(2.0 * mgh, 0.0, 0.0, 0.0, kH);
    const cd::DelassusProblem p = cd::delassus_problem(w.system);
    Eigen::VectorXd r(4);
    r << 2.0 * mgh, 0.0, 2.0 * mgh, 0.0;
    const cd::AdmmReport rep = cd::solve_admm(p, r, tight_options(0.0));
    EXPECT_TRUE(rep.converged) << rep.residual;
    EXPECT_LT(cd::admm_law_residual(p, r, kG * kH), 1e-9);
    EXPECT_NEAR(r[0], r[2], 1e-9 * mgh) << r.transpose() / mgh;  // symmetric
    EXPECT_NEAR(r[1], -0.5 * r[0], 1e-9 * mgh);                  // sliding: R_t = mu R_n
    EXPECT_NEAR(r[3], 0.5 * r[2], 1e-9 * mgh);
    EXPECT_NEAR(r[0], 0.70 * mgh, 0.01 * mgh);
  }
}

// The seam knows the solver by its name.
TEST(Admm, SelectedByName) {
  EXPECT_EQ(cd::solver_from_name("admm"), cd::SolverKind::admm);
  EXPECT_STREQ(cd::solver_name(cd::SolverKind::admm), "admm");
  EXPECT_EQ(cd::make_solver(admm(1e6, 1.0))->kind(), cd::SolverKind::admm);
}
