// The primal solver (primal.hpp; docs/method.md, "The primal solver") on scenes whose
// answers are known by hand, at k = 1e6 and 1e8 m g / D and rigid: Newton on the grains'
// velocities alone (solve_primal, on the wedge), and behind the seam in the engine.
#include "cd_scenes.hpp"
#include "cdpile/cd/engine.hpp"
#include "cdpile/cd/primal.hpp"
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

constexpr double kStiffnesses[] = {0.0, 1e6, 1e8};

double in_newtons(double stiffness, double m) { return stiffness * m * kG / (2 * kR); }

cd::Settings primal(double stiffness, double m) {
  cd::Settings s;
  s.solver = cd::SolverKind::primal;
  s.tolerance = 1e-9;
  s.max_sweeps = 100000;
  s.contact_stiffness = in_newtons(stiffness, m);
  return s;
}

cd::PrimalOptions tight() {
  cd::PrimalOptions o;
  o.tolerance = 1e-9;
  o.velocity_floor = kG * kH;
  o.max_factorisations = 200;
  return o;
}

}  // namespace

// A disk with its rotation locked on the floor of a tilted box (mu = 0.5): it sticks at 20
// degrees with f = m g (cos, sin) and slides at 30 with |f_t| = mu f_n, every step
// converged, rigid and compliant.
TEST(Primal, InclineSticksAndSlidesWithMu) {
  Grains g;
  g.add_disk(kR, kRho, Vec2(0.05, kR));
  const double m = g.mass[0], mg = m * kG;
  for (const double stiffness : kStiffnesses) {
    for (const double tilt : {20.0, 30.0}) {
      cd::Engine e(Box{0.5, 0.05}, g, primal(stiffness, m));
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
    }
  }
}

// A column of 10 disks on the floor: the contact under the n-th disk from the top carries
// n m g, rigid and at k = 1e6 and 1e8 m g / D.
TEST(Primal, ColumnCarriesTheWeightAbove) {
  const int k = 10;
  Grains g;
  for (int n = 0; n < k; ++n) g.add_disk(kR, kRho, Vec2(0.01, kR + 2 * kR * n));
  const double mg = g.mass[0] * kG;
  for (const double stiffness : kStiffnesses) {
    cd::Engine e(Box{0.02, 0.02}, g, primal(stiffness, g.mass[0]));
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

// The hyperstatic wedge: with the compliance anchored at R0_n = 2 m g h the answer is
// unique (R_n = 2 m g h, |R_t| = m g h / 2 on both walls, sticking) and Newton finds it from
// either start at k = 1e6 and 1e8. Rigid, the step is indeterminate: started at a solution
// it stays; started without friction it returns an admissible, symmetric answer.
TEST(Primal, HyperstaticWedge) {
  const double m = kRho * std::numbers::pi * kR * kR, mgh = m * kG * kH;
  for (const double stiffness : {1e6, 1e8}) {
    for (const double start : {1.0, 5.0}) {
      cd_scenes::Wedge w =
          cd_scenes::wedged_disk(start * mgh, 2.0 * mgh, 0.5 * mgh, in_newtons(stiffness, m), kH);
      const cd::PrimalReport rep = cd::solve_primal(w.system, tight());
      EXPECT_TRUE(rep.converged) << stiffness << " " << start << ": " << rep.residual;
      for (const cd::ContactRow& r : w.system.rows) {
        EXPECT_NEAR(r.rn, 2.0 * mgh, 1e-6 * mgh) << "k " << stiffness << ", start " << start;
        EXPECT_NEAR(std::abs(r.rt), 0.5 * mgh, 1e-6 * mgh);
        EXPECT_EQ(r.status, ContactStatus::stick);
      }
    }
  }
  {
    cd_scenes::Wedge w = cd_scenes::wedged_disk(5.0 * mgh, 0.0, 0.5 * mgh, 0.0, kH);
    const cd::PrimalReport rep = cd::solve_primal(w.system, tight());
    EXPECT_TRUE(rep.converged) << rep.residual;
    for (const cd::ContactRow& r : w.system.rows) {
      EXPECT_NEAR(r.rn, 5.0 * mgh, 1e-6 * mgh);
      EXPECT_NEAR(std::abs(r.rt), 0.5 * mgh, 1e-6 * mgh);
    }
  }
  {
    cd_scenes::Wedge w = cd_scenes::wedged_disk(2.0 * mgh, 0.0, 0.0, 0.0, kH);
    const cd::PrimalReport rep = cd::solve_primal(w.system, tight());
    EXPECT_TRUE(rep.converged) << rep.residual;
    EXPECT_LT(cd::law_residual(w.system, kG * kH).max, 1e-9);
    const auto& a = w.system.rows[0];
    const auto& b = w.system.rows[1];
    EXPECT_NEAR(a.rn, b.rn, 1e-9 * mgh);  // symmetric
    EXPECT_NEAR(a.rt, -b.rt, 1e-9 * mgh);
    EXPECT_LE(std::abs(a.rt), 0.5 * a.rn + 1e-12 * mgh);  // in the cone
    EXPECT_GE(a.rt * -1.0, 0.0);                           // friction holds the disk up
  }
}

TEST(Primal, SelectedByName) {
  EXPECT_EQ(cd::solver_from_name("primal"), cd::SolverKind::primal);
  EXPECT_STREQ(cd::solver_name(cd::SolverKind::primal), "primal");
  EXPECT_EQ(cd::make_solver(primal(1e6, 1.0))->kind(), cd::SolverKind::primal);
}
