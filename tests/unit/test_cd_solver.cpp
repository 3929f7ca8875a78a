// The solver seam, the solver-independent residual of the contact law, and the
// force-selection rule (docs/method.md, "Force selection", "The residual"): scenes whose
// answers are computed by hand, run through every solver behind the seam.
#include "cd_scenes.hpp"
#include "cdpile/cd/contact_system.hpp"
#include "cdpile/cd/delassus.hpp"
#include "cdpile/cd/engine.hpp"
#include "cdpile/cd/face_newton.hpp"
#include "cdpile/cd/nsgs.hpp"
#include "cdpile/cd/solver.hpp"
#include "cdpile/error.hpp"

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
using cd_scenes::triangular_stack;
using cd_scenes::Wedge;
constexpr double kH = 1e-4;

const cd::SolverKind kAllSolvers[] = {cd::SolverKind::nsgs, cd::SolverKind::nncg,
                                      cd::SolverKind::pcg, cd::SolverKind::newton,
                                      cd::SolverKind::admm};

// pcg's gradient rounds and newton's Newton steps start after the first sweep and follow
// every sweep, so that the small scenes here, which NSGS converges in a few sweeps, go
// through them too.
cd::Settings tight(cd::SolverKind solver) {
  cd::Settings s;
  s.solver = solver;
  s.tolerance = 1e-10;
  s.krylov_after = 1;
  s.sweeps_between_rounds = 1;
  s.newton_after = 0;
  return s;
}

Wedge wedged_disk(double start_n, double anchor_n, double anchor_t, double stiffness) {
  return cd_scenes::wedged_disk(start_n, anchor_n, anchor_t, stiffness, kH);
}

}  // namespace

// The seam: a solver named in the settings is the one the engine runs, and its names
// round-trip; an unknown name is a usage error.
TEST(Seam, SolverNamesRoundTripAndTheEngineRunsTheNamedSolver) {
  for (const cd::SolverKind k : kAllSolvers) {
    EXPECT_EQ(cd::solver_from_name(cd::solver_name(k)), k);
    EXPECT_EQ(cd::make_solver(tight(k))->kind(), k);
  }
  EXPECT_THROW(cd::solver_from_name("pgs"), cdpile::UsageError);
  for (const cd::Criterion c :
       {cd::Criterion::maxm, cd::Criterion::quad, cd::Criterion::qm16, cd::Criterion::law,
        cd::Criterion::err})
    EXPECT_EQ(cd::criterion_from_name(cd::criterion_name(c)), c);
  cd::SolverSettings bad;
  bad.check_every = 0;
  EXPECT_THROW(cd::make_solver(bad), cdpile::UsageError);
  for (const bool after : {true, false}) {
    cd::SolverSettings rounds;
    (after ? rounds.krylov_after : rounds.sweeps_between_rounds) = 0;
    EXPECT_THROW(cd::make_solver(rounds), cdpile::UsageError);
  }
}

// Every solver, rigid and with the compliance: a locked disk on a 20-degree incline sticks
// with f = m g (cos, sin); a free disk at 30 degrees rolls without slip at (2/3) g sin theta.
TEST(Seam, InclineThroughEverySolver) {
  for (const cd::SolverKind k : kAllSolvers)
    for (const double stiffness : {0.0, 1e6}) {
      Grains g;
      g.add_disk(kR, kRho, Vec2(0.05, kR));
      const double m = g.mass[0];
      cd::Settings s = tight(k);
      s.contact_stiffness = stiffness * m * kG / (2 * kR);  // in m g / D
      {
        cd::Engine e(Box{0.1, 0.05}, g, s);
        e.lock_rotation(0);
        for (int n = 0; n < 300; ++n) e.step(20 * kDeg);
        const auto c = e.contacts();
        ASSERT_EQ(c.size(), 1u);
        EXPECT_NEAR(c.fn[0], m * kG * std::cos(20 * kDeg), 1e-8 * m * kG) << stiffness;
        EXPECT_NEAR(std::abs(c.ft[0]), m * kG * std::sin(20 * kDeg), 1e-8 * m * kG) << stiffness;
        EXPECT_EQ(c.status[0], ContactStatus::stick);
      }
      cd::Engine e(Box{0.5, 0.05}, g, s);
      for (int n = 0; n < 100; ++n) e.step(30 * kDeg);
      // From rest the compliant contact takes a few steps to load (its spring starts at
      // zero); the acceleration is then the rigid one, so the velocity lags by at most that.
      const double v = e.grains().velocity[0].x(), t = 100 * kH;
      const double lag = stiffness > 0.0 ? 3 * kG * kH : 0.0;
      EXPECT_NEAR(v, 2.0 / 3.0 * kG * std::sin(30 * kDeg) * t, 1e-12 + lag) << stiffness;
      EXPECT_NEAR(v + e.grains().angular_velocity[0] * kR, 0.0, 1e-10) << stiffness;
    }
}

// Every solver: a column of 10 disks, the contact under the n-th disk from the top carries
// n m g, rigid and compliant (the compliance changes how the load builds up, not the
// static answer).
TEST(Seam, ColumnThroughEverySolver) {
  const int k = 10;
  Grains g;
  for (int n = 0; n < k; ++n) g.add_disk(kR, kRho, Vec2(0.01, kR + 2 * kR * n));
  for (const cd::SolverKind kind : kAllSolvers)
    for (const double stiffness : {0.0, 1e5}) {
      cd::Settings s = tight(kind);
      s.contact_stiffness = stiffness * g.mass[0] * kG / (2 * kR);
      s.max_sweeps = 100000;
      cd::Engine e(Box{0.02, 0.02}, g, s);
      cd::StepReport rep;
      for (int step = 0; step < 400; ++step) rep = e.step(0.0);
      EXPECT_TRUE(rep.converged);
      const double mg = g.mass[0] * kG;
      const auto c = e.contacts();
      ASSERT_EQ(c.size(), static_cast<std::size_t>(k));
      for (std::size_t q = 0; q < c.size(); ++q) {
        const int carried = c.j[q] < 0 ? k : k - 1 - c.i[q];
        EXPECT_NEAR(c.fn[q], carried * mg, 1e-6 * k * mg) << "contact " << q << " k " << stiffness;
      }
      // The law's residual of a converged step is at the solver's tolerance.
      EXPECT_LT(rep.law_residual, 1e-6);
    }
}

// The residual of the law: zero at a solution, and a hand-computed value away from it.
// One disk resting on the floor: the solution is R_n = m g h, R_t = 0. With R_n off by
// delta the exact local solve corrects the velocity by W_nn delta = delta / m: the
// residual is delta / (m g h) in units of g h.
TEST(LawResidual, ZeroAtTheSolutionAndTheLocalCorrectionAway) {
  const double m = kRho * std::numbers::pi * kR * kR;
  for (const double delta_in_mgh : {0.0, 0.25, -0.5}) {
    cd::ContactSystem s;
    s.bodies = {{0.0, -kG * kH, 0.0, 1.0 / m, 2.0 / (m * kR * kR)}, {0.0, 0.0, 0.0, 0.0, 0.0}};
    cd::ContactRow r{};
    r.i = 0;
    r.j = cdpile::wall_floor;
    r.bj = 1;
    r.ny = 1.0;
    r.ri = kR;
    r.mu = 0.5;
    r.w_nn = 1.0 / m;
    r.w_tt = 3.0 / m;
    r.rn = m * kG * kH * (1.0 + delta_in_mgh);
    s.rows.push_back(r);
    s.apply_impulse(r, r.rn, r.rt);
    const cd::LawResidual law = cd::law_residual(s, kG * kH);
    EXPECT_NEAR(law.max, std::abs(delta_in_mgh), 1e-12) << delta_in_mgh;
    EXPECT_NEAR(law.rms, std::abs(delta_in_mgh), 1e-12);
  }
}

// The force-selection rule on a hyperstatic scene (docs/method.md, "Force selection"). A
// disk wedged between two walls, held up by friction alone: for rigid grains the normal
// impulses are indeterminate, any R_n = s on both walls with s >= m g h / (2 mu) and
// R_t = m g h / 2 holding the disk is a solution, and NSGS returns whichever s it
// starts from. With the compliance c = 1/(k h^2) anchored at the previous impulses R0 the
// step's problem is (W + c I) R = c R0 - q on the stick set, W + c I positive definite,
// so its solution is unique: by hand, R_n = R0_n on both walls (the normal rows of W
// cancel for equal impulses, leaving c R_n = c R0_n) and R_t = m g h / 2 (the tangent
// rows give (2/m + c) R_t = (2/m + c) m g h / 2 with R0_t = m g h / 2). Every solver, from
// any start, must return it.
TEST(ForceSelection, HyperstaticWedgeIsIndeterminateRigidAndUniqueWithTheCompliance) {
  const double m = kRho * std::numbers::pi * kR * kR, mgh = m * kG * kH;
  for (const cd::SolverKind kind : kAllSolvers) {
    const auto solver = cd::make_solver(tight(kind));
    // Rigid: two starts, two different solutions, both with a zero residual.
    for (const double start : {1.0, 5.0}) {
      Wedge w = wedged_disk(start * mgh, start * mgh, 0.5 * mgh, 0.0);
      const cd::SolveReport rep = solver->solve(w.system, kG * kH);
      EXPECT_TRUE(rep.converged);
      for (const cd::ContactRow& r : w.system.rows) {
        EXPECT_NEAR(r.rn, start * mgh, 1e-9 * mgh) << "rigid keeps its start " << start;
        EXPECT_NEAR(std::abs(r.rt), 0.5 * mgh, 1e-9 * mgh);
      }
      EXPECT_LT(cd::law_residual(w.system, kG * kH).max, 1e-9);
      EXPECT_NEAR(w.system.bodies[0].vy, 0.0, 1e-12 * kG * kH);
    }
    // Compliant (k = 1e5 m g / D), anchored at R0_n = 2 m g h: from starts 1 and 5 m g h
    // alike, the unique solution R_n = 2 m g h.
    const double k = 1e5 * m * kG / (2 * kR);
    for (const double start : {1.0, 5.0}) {
      Wedge w = wedged_disk(start * mgh, 2.0 * mgh, 0.5 * mgh, k);
      const cd::SolveReport rep = solver->solve(w.system, kG * kH);
      EXPECT_TRUE(rep.converged);
      for (const cd::ContactRow& r : w.system.rows) {
        EXPECT_NEAR(r.rn, 2.0 * mgh, 1e-8 * mgh) << "compliant, start " << start;
        EXPECT_NEAR(std::abs(r.rt), 0.5 * mgh, 1e-8 * mgh);
        EXPECT_EQ(r.status, ContactStatus::stick);
      }
      EXPECT_LT(cd::law_residual(w.system, kG * kH).max, 1e-8);
    }
  }
}

// The engine's compliance is 1/(k h^2) on both diagonal entries of each contact's block,
// with -c R0 in q: the exported Delassus problem of a compliant step differs from the
// rigid one by exactly that, and the step's impulses solve it.
TEST(ForceSelection, ExportedProblemCarriesTheCompliance) {
  Grains g;
  g.add_disk(kR, kRho, Vec2(0.05, kR));
  cd::Settings rigid = tight(cd::SolverKind::nsgs), soft = rigid;
  soft.contact_stiffness = 1e5 * g.mass[0] * kG / (2 * kR);
  cd::Engine a(Box{0.1, 0.05}, g, rigid), b(Box{0.1, 0.05}, g, soft);
  for (int n = 0; n < 50; ++n) {
    a.step(0.0);
    b.step(0.0);
  }
  const cd::DelassusProblem pa = a.delassus_problem(), pb = b.delassus_problem();
  const double c = 1.0 / (soft.contact_stiffness * kH * kH);
  EXPECT_NEAR(pb.W.coeff(0, 0) - pa.W.coeff(0, 0), c, 1e-12 * c);
  EXPECT_NEAR(pb.W.coeff(1, 1) - pa.W.coeff(1, 1), c, 1e-12 * c);
  Eigen::VectorXd r = b.local_impulses();
  EXPECT_LT(cd::natural_map_residual(pb, r), 1e-8);
  // At rest the spring holds the weight: R_n = m g h in both.
  EXPECT_NEAR(r[0], g.mass[0] * kG * kH, 1e-8 * g.mass[0] * kG * kH);
}

// check_every: the criterion is tested only every K sweeps, so a converging step stops at
// a multiple of K, never earlier than with K = 1.
TEST(Seam, CheckEveryStopsOnAMultiple) {
  const int k = 10;
  Grains g;
  for (int n = 0; n < k; ++n) g.add_disk(kR, kRho, Vec2(0.01, kR + 2 * kR * n));
  cd::Settings s = tight(cd::SolverKind::nsgs);
  s.tolerance = 1e-6;
  const int every1 = cd::Engine(Box{0.02, 0.02}, g, s).step(0.0).sweeps;
  s.check_every = 7;
  const cd::StepReport rep = cd::Engine(Box{0.02, 0.02}, g, s).step(0.0);
  EXPECT_TRUE(rep.converged);
  EXPECT_EQ(rep.sweeps % 7, 0);
  EXPECT_GE(rep.sweeps, every1);
  EXPECT_LT(rep.sweeps, every1 + 7);
}

// A scrambled sweep order is a permutation, the same for the same (seed, step) and another
// for another step or seed; seed 0 is pair order.
TEST(Scramble, SweepOrderIsASeededPermutationPerStep) {
  cd::ContactSystem s;
  s.rows.resize(50);
  s.step = 7;
  EXPECT_TRUE(cd::sweep_order(s, 0).empty());
  const auto a = cd::sweep_order(s, 3);
  ASSERT_EQ(a.size(), 50u);
  auto sorted = a;
  std::sort(sorted.begin(), sorted.end());
  for (std::uint32_t k = 0; k < 50; ++k) EXPECT_EQ(sorted[k], k);
  EXPECT_EQ(cd::sweep_order(s, 3), a);
  EXPECT_NE(cd::sweep_order(s, 4), a);
  s.step = 8;
  EXPECT_NE(cd::sweep_order(s, 3), a);
}

// Six disks stacked in a triangle on the floor (3, 2, 1), tilted by 10 degrees, touch at 12
// contacts: 24 impulse components against 18 equations of equilibrium, so the rigid forces
// are not unique and
// the sweep order picks among them; with the force-selection compliance they are unique
// and every order finds the same forces (docs/method.md, "Force selection").
TEST(Scramble, RigidForcesDependOnTheSweepOrderCompliantOnesDoNot) {
  Grains g;
  const double r3 = std::sqrt(3.0) * kR;
  for (double x : {1.0, 3.0, 5.0}) g.add_disk(kR, kRho, Vec2(0.01 + x * kR, kR));
  for (double x : {2.0, 4.0}) g.add_disk(kR, kRho, Vec2(0.01 + x * kR, kR + r3));
  g.add_disk(kR, kRho, Vec2(0.01 + 3.0 * kR, kR + 2 * r3));
  const double mg = g.mass[0] * kG;
  auto forces = [&](double stiffness, std::uint64_t seed) {
    cd::Settings s = tight(cd::SolverKind::nsgs);
    s.tolerance = 1e-10;
    s.max_sweeps = 1000000;
    s.scramble = seed;
    s.contact_stiffness = stiffness * g.mass[0] * kG / (2 * kR);
    cd::Engine e(Box{0.03, 0.03}, g, s);
    cd::StepReport rep;
    // tilted by 10 degrees, the stack needs friction to stand
    for (int n = 0; n < 5; ++n) rep = e.step(10.0 * std::numbers::pi / 180.0);
    EXPECT_TRUE(rep.converged);
    EXPECT_LT(rep.law_residual, 1e-6);
    return e.contacts();
  };
  auto largest_difference = [](const cdpile::Contacts& a, const cdpile::Contacts& b) {
    EXPECT_EQ(a.size(), b.size());
    double d = 0.0;
    for (std::size_t k = 0; k < a.size() && k < b.size(); ++k)
      d = std::max({d, std::abs(a.fn[k] - b.fn[k]), std::abs(a.ft[k] - b.ft[k])});
    return d;
  };
  const cdpile::Contacts rigid1 = forces(0.0, 1), rigid2 = forces(0.0, 2);
  ASSERT_EQ(rigid1.size(), 12u);
  EXPECT_GT(largest_difference(rigid1, rigid2), 1e-3 * mg);
  const cdpile::Contacts soft1 = forces(1e4, 1), soft2 = forces(1e4, 2), soft0 = forces(1e4, 0);
  EXPECT_LT(largest_difference(soft1, soft2), 1e-6 * mg);
  EXPECT_LT(largest_difference(soft1, soft0), 1e-6 * mg);
}

namespace {

// The stiff stack through `kind` and through NSGS (the two tests below): every step
// converged, the same forces, balancing the weight, in a third of NSGS's sweeps or fewer.
void stiff_stack_against_nsgs(cd::SolverKind kind) {
  const int base = 8;
  const Grains g = triangular_stack(base);
  const double mg = g.mass[0] * kG, tilt = 10.0 * kDeg;
  auto run = [&](cd::SolverKind solver, long& work) {
    cd::Settings s;
    s.solver = solver;
    s.tolerance = 1e-8;
    s.max_sweeps = 1000000;
    s.newton_after = 0;  // newton: Newton steps from the first round
    s.contact_stiffness = 1e7 * mg / (2 * kR);
    cd::Engine e(Box{2 * base * kR, 0.03}, g, s);
    work = 0;
    for (int n = 0; n < 40; ++n) {
      const cd::StepReport rep = e.step(tilt);
      EXPECT_TRUE(rep.converged) << cd::solver_name(solver) << " step " << n;
      EXPECT_LT(rep.law_residual, 1e-4) << cd::solver_name(solver) << " step " << n;
      work += rep.sweeps;
    }
    return e.contacts();
  };
  long nsgs_work = 0, kind_work = 0;
  const cdpile::Contacts a = run(cd::SolverKind::nsgs, nsgs_work);
  const cdpile::Contacts b = run(kind, kind_work);
  ASSERT_EQ(a.size(), b.size());
  Vec2 walls(0.0, 0.0);  // the force of the floor and walls on the stack
  for (std::size_t q = 0; q < b.size(); ++q) {
    EXPECT_NEAR(b.fn[q], a.fn[q], 1e-4 * mg) << "contact " << q;
    EXPECT_NEAR(b.ft[q], a.ft[q], 1e-4 * mg) << "contact " << q;
    const Vec2 n = b.normal[q], t(-n.y(), n.x());
    if (b.j[q] < 0) walls += b.fn[q] * n + b.ft[q] * t;
  }
  // At rest they balance the weight m g (sin theta, -cos theta) in the box frame.
  const double weight = static_cast<double>(g.size()) * mg;
  EXPECT_NEAR(walls.x(), -weight * std::sin(tilt), 1e-6 * weight);
  EXPECT_NEAR(walls.y(), weight * std::cos(tilt), 1e-6 * weight);
  EXPECT_LT(kind_work, nsgs_work / 3)
      << cd::solver_name(kind) << " " << kind_work << " NSGS " << nsgs_work;
}

}  // namespace

// pcg solves the same step problem as NSGS: on a stiff hyperstatic stack (k = 1e7 m g / D,
// where Gauss-Seidel's error decays by about 1 - 1e-3 per sweep) tilted by 10 degrees,
// both converge every step to the forces of the unique compliant solution, which carry
// the stack's weight to the floor and walls, and pcg needs a fraction of NSGS's sweeps.
TEST(Pcg, StiffStackSameForcesAsNsgsInAFractionOfTheSweeps) {
  stiff_stack_against_nsgs(cd::SolverKind::pcg);
}

// The following rounds (SolverSettings::following_until) change the path, not the
// solution: the stiff stack at mu = 0.1, tilted by 10 degrees from zero forces, so that
// contacts slide while its forces build up, solved by pcg with gradient rounds only, with
// following rounds first (the default) and with following rounds throughout: every step
// converges, and the forces after 40 steps are NSGS's within 1e-4 m g.
TEST(Pcg, FollowingRoundsSameForcesWhereContactsSlide) {
  const int base = 8;
  const Grains g = triangular_stack(base);
  const double mg = g.mass[0] * kG, tilt = 10.0 * kDeg;
  auto run = [&](cd::SolverKind solver, int following_until, long& sliding) {
    cd::Settings s;
    s.solver = solver;
    s.mu_grain = s.mu_wall = 0.1;
    s.tolerance = 1e-8;
    s.max_sweeps = 1000000;
    s.following_until = following_until;
    s.contact_stiffness = 1e7 * mg / (2 * kR);
    cd::Engine e(Box{2 * base * kR, 0.03}, g, s);
    sliding = 0;
    for (int n = 0; n < 40; ++n) {
      const cd::StepReport rep = e.step(tilt);
      EXPECT_TRUE(rep.converged) << following_until << " step " << n;
      EXPECT_LT(rep.law_residual, 1e-4) << following_until << " step " << n;
      sliding += rep.sliding;
    }
    return e.contacts();
  };
  long sliding = 0;
  const cdpile::Contacts nsgs = run(cd::SolverKind::nsgs, 0, sliding);
  for (const int following_until : {0, 30, 1000000}) {
    const cdpile::Contacts b = run(cd::SolverKind::pcg, following_until, sliding);
    EXPECT_GT(sliding, 0) << following_until;  // the following rounds had rows to follow
    ASSERT_EQ(b.size(), nsgs.size());
    for (std::size_t q = 0; q < b.size(); ++q) {
      EXPECT_NEAR(b.fn[q], nsgs.fn[q], 1e-4 * mg) << following_until << " contact " << q;
      EXPECT_NEAR(b.ft[q], nsgs.ft[q], 1e-4 * mg) << following_until << " contact " << q;
    }
  }
}

// The 'err' criterion bounds the error, not the last correction (docs/method.md,
// "Convergence"): on the stiff stack's first step (forces built from zero, Gauss-Seidel
// contracting by about 1 - 1e-3 per sweep) maxm at a tolerance stops while the forces are
// still far from the converged ones, about the condition number times the tolerance;
// err at the same tolerance stops within a few tolerances of them (forces in m g, the
// velocity scale of the measures being about g h here), with NSGS and with pcg, whose
// contraction is measured over two cycles of sweeps and rounds (cd::err_window).
TEST(Criterion, ErrBoundsTheErrorWhereTheLastCorrectionUnderestimatesIt) {
  const int base = 8;
  const Grains g = triangular_stack(base);
  const double mg = g.mass[0] * kG, tilt = 10.0 * kDeg, tol = 1e-5;
  auto first_step = [&](cd::SolverKind kind, cd::Criterion c, double tolerance, int& sweeps) {
    cd::Settings s;
    s.solver = kind;
    s.criterion = c;
    s.tolerance = tolerance;
    s.max_sweeps = 1000000;
    s.contact_stiffness = 1e7 * mg / (2 * kR);
    cd::Engine e(Box{2 * base * kR, 0.03}, g, s);
    const cd::StepReport rep = e.step(tilt);
    EXPECT_TRUE(rep.converged);
    sweeps = rep.sweeps;
    return e.contacts();
  };
  int n = 0;
  const cdpile::Contacts exact = first_step(cd::SolverKind::nsgs, cd::Criterion::maxm, 1e-13, n);
  auto error = [&](const cdpile::Contacts& c) {  // the largest force error [m g]
    double e = 0.0;
    for (std::size_t q = 0; q < c.size(); ++q)
      e = std::max({e, std::abs(c.fn[q] - exact.fn[q]), std::abs(c.ft[q] - exact.ft[q])});
    return e / mg;
  };
  for (const cd::SolverKind kind : {cd::SolverKind::nsgs, cd::SolverKind::pcg}) {
    int maxm_sweeps = 0, err_sweeps = 0;
    const double maxm = error(first_step(kind, cd::Criterion::maxm, tol, maxm_sweeps));
    const double err = error(first_step(kind, cd::Criterion::err, tol, err_sweeps));
    // measured: NSGS 11 668 sweeps, 0.017 m g against 43 580, 4.8e-6 m g; pcg 4094,
    // 0.015 m g against 28 281, 6.4e-6 m g
    EXPECT_GT(maxm, 100 * tol) << cd::solver_name(kind);
    EXPECT_LT(err, 3 * tol) << cd::solver_name(kind);
    EXPECT_GT(err_sweeps, maxm_sweeps) << cd::solver_name(kind);
  }
}

// The face's Newton step (face_newton.hpp) solves the linear problem of the statuses it is
// given exactly, a sliding contact's friction following its normal impulse. The wedged
// disk at k = 1e5 m g / D from R_n = 1 m g h: with both contacts sticking, one step leaves
// u'_n = u'_t = 0 at both (the compliant solution R_n = 2 m g h); with the right wall's
// contact sliding, one step leaves its u'_n = 0 and R_t = s mu R_n, and the left one's
// u' = 0.
TEST(Newton, FaceStepSolvesTheFaceExactlyWithSlidingFrictionFollowingTheNormal) {
  const double m = kRho * std::numbers::pi * kR * kR, mgh = m * kG * kH;
  const double k = 1e5 * m * kG / (2 * kR);
  for (const bool right_slides : {false, true}) {
    Wedge w = wedged_disk(1.0 * mgh, 2.0 * mgh, 0.5 * mgh, k);
    cd::ContactSystem& s = w.system;
    if (right_slides) {  // put it on the cone, friction holding the disk up
      cd::ContactRow& r = s.rows[0];
      const double rt = -r.mu * r.rn;
      s.apply_impulse(r, 0.0, rt - r.rt);
      r.rt = rt;
    }
    const std::vector<cd::FaceRow> face{{0, !right_slides}, {1, true}};
    auto law_velocity = [&](std::size_t a) {  // u' = W_aa R_a + b_a
      double b_n, b_t;
      const cd::ContactRow& r = s.rows[a];
      s.free_local_velocity(r, b_n, b_t);
      return cd::FaceValue{b_n + r.w_nn * r.rn, b_t + r.w_tt * r.rt};
    };
    std::vector<cd::FaceValue> res(2);
    for (std::size_t a = 0; a < 2; ++a) {
      const cd::FaceValue u = law_velocity(a);
      res[a] = {-u.n, face[a].t ? -u.t : 0.0};
    }
    ASSERT_GT(std::abs(res[1].n), 0.1 * kG * kH) << "a face already solved: no test";
    cd::FaceFactor factor;
    ASSERT_TRUE(cd::newton_face_step(s, face, res, factor, 0.0));
    for (std::size_t a = 0; a < 2; ++a) {
      const cd::FaceValue u = law_velocity(a);
      EXPECT_NEAR(u.n, 0.0, 1e-12 * kG * kH) << "contact " << a << " sliding " << right_slides;
      if (face[a].t) {
        EXPECT_NEAR(u.t, 0.0, 1e-12 * kG * kH) << "contact " << a;
      }
    }
    if (right_slides) {
      EXPECT_NEAR(s.rows[0].rt, -s.rows[0].mu * s.rows[0].rn, 1e-12 * mgh);
    } else {
      for (const cd::ContactRow& r : s.rows) EXPECT_NEAR(r.rn, 2.0 * mgh, 1e-9 * mgh);
    }
  }
}

namespace {

// A zig-zag column of n disks on the floor, each resting on the one below, every other
// one shifted sideways by 0.6 radius (normals (+-0.3, 0.95), so that normal and
// tangential components couple), every contact's impulse at `start_n`: the contact
// system of one compliant step, by hand.
cd::ContactSystem column_of_disks(int n, double start_n, double stiffness) {
  const double m = kRho * std::numbers::pi * kR * kR;
  const double inv_m = 1.0 / m, inv_i = 2.0 / (m * kR * kR);
  cd::ContactSystem s;
  for (int b = 0; b < n; ++b) s.bodies.push_back({0.0, -kG * kH, 0.0, inv_m, inv_i});
  s.bodies.push_back({0.0, 0.0, 0.0, 0.0, 0.0});  // the floor
  s.compliance_n = s.compliance_t = 1.0 / (stiffness * kH * kH);
  for (int b = 0; b < n; ++b) {
    cd::ContactRow r{};
    r.i = b;
    r.j = b == 0 ? cdpile::wall_floor : b - 1;
    r.bi = b;
    r.bj = b == 0 ? n : b - 1;
    r.nx = b == 0 ? 0.0 : (b % 2 == 1 ? 0.3 : -0.3);
    r.ny = std::sqrt(1.0 - r.nx * r.nx);
    r.ri = kR;
    r.rj = b == 0 ? 0.0 : kR;
    r.mu = 0.5;
    const double j_moves = b == 0 ? 0.0 : 1.0;
    r.w_nn = (1.0 + j_moves) * inv_m + s.compliance_n;
    r.w_tt = (1.0 + j_moves) * inv_m + (1.0 + j_moves) * kR * kR * inv_i + s.compliance_t;
    r.rn0 = r.rn = start_n;
    s.rows.push_back(r);
  }
  for (const cd::ContactRow& r : s.rows) s.apply_impulse(r, r.rn, r.rt);
  return s;
}

}  // namespace

// The later faces of a time step are solved with the step's factor of J (FaceFactor):
// on a zig-zag column of 12 disks, the first face (every contact sticking) makes the factor and
// is solved exactly in one GMRES iteration; a later face with one contact sliding differs
// from it by two components' rank-one terms in J, and GMRES preconditioned by the kept
// factor solves it exactly in at most three iterations, with no new factor; the next
// time step makes a factor of its own.
TEST(Newton, TheStepsFactorSolvesItsLaterFacesInRankPlusOneIterations) {
  const int n = 12;
  const double m = kRho * std::numbers::pi * kR * kR, mgh = m * kG * kH;
  cd::ContactSystem s = column_of_disks(n, 1.0 * mgh, 1e5 * m * kG / (2 * kR));
  auto law_velocity = [&](std::size_t a) {  // u' = W_aa R_a + b_a
    double b_n, b_t;
    const cd::ContactRow& r = s.rows[a];
    s.free_local_velocity(r, b_n, b_t);
    return cd::FaceValue{b_n + r.w_nn * r.rn, b_t + r.w_tt * r.rt};
  };
  auto residual = [&](const std::vector<cd::FaceRow>& face) {
    std::vector<cd::FaceValue> res(face.size());
    for (std::size_t k = 0; k < face.size(); ++k) {
      const cd::FaceValue u = law_velocity(face[k].row);
      res[k] = {-u.n, face[k].t ? -u.t : 0.0};
    }
    return res;
  };
  auto expect_solved = [&](const std::vector<cd::FaceRow>& face, const char* what) {
    for (const cd::FaceRow& f : face) {
      const cd::FaceValue u = law_velocity(f.row);
      EXPECT_NEAR(u.n, 0.0, 1e-10 * kG * kH) << what << ", contact " << f.row;
      if (f.t) {
        EXPECT_NEAR(u.t, 0.0, 1e-10 * kG * kH) << what << ", contact " << f.row;
      }
    }
  };
  const double target = 1e-12 * kG * kH;
  cd::FaceFactor factor;
  std::vector<cd::FaceRow> face;
  for (std::uint32_t a = 0; a < n; ++a) face.push_back({a, true});
  ASSERT_TRUE(cd::newton_face_step(s, face, residual(face), factor, target));
  expect_solved(face, "all sticking");
  EXPECT_EQ(factor.counts().factorisations, 1);
  EXPECT_EQ(factor.counts().iterations, 1);

  for (cd::ContactRow& row : s.rows) {  // away from that solution: R_n 20 % lower
    s.apply_impulse(row, -0.2 * row.rn, 0.0);
    row.rn *= 0.8;
  }
  cd::ContactRow& r = s.rows[5];  // and contact 5 on the cone, sliding
  s.apply_impulse(r, 0.0, r.mu * r.rn - r.rt);
  r.rt = r.mu * r.rn;
  face[5].t = false;
  const std::vector<cd::FaceValue> res = residual(face);
  ASSERT_GT(std::abs(res[0].n), 1e-3 * kG * kH) << "a face already solved: no test";
  ASSERT_TRUE(cd::newton_face_step(s, face, res, factor, target));
  expect_solved(face, "contact 5 sliding");
  EXPECT_NEAR(s.rows[5].rt, s.rows[5].mu * s.rows[5].rn, 1e-12 * mgh);
  EXPECT_EQ(factor.counts().factorisations, 1) << "a new factor within the step";
  EXPECT_GE(factor.counts().iterations - 1, 2) << "the changed face solved as if unchanged";
  EXPECT_LE(factor.counts().iterations - 1, 3);

  ++s.step;
  for (cd::ContactRow& row : s.rows) {  // a new step's problem: other anchors
    row.rn0 *= 1.5;
  }
  ASSERT_TRUE(cd::newton_face_step(s, face, residual(face), factor, target));
  EXPECT_EQ(factor.counts().factorisations, 2) << "the next step kept the last step's factor";
}

// newton solves the same step problem as NSGS and pcg: on the stiff stack of the pcg test
// above (k = 1e7 m g / D, tilted by 10 degrees, from zero forces), with Newton steps from
// the first round, every step converges to NSGS's forces, which balance the weight, in a
// fraction of NSGS's sweeps.
TEST(Newton, StiffStackSameForcesAsNsgsInAFractionOfTheSweeps) {
  stiff_stack_against_nsgs(cd::SolverKind::newton);
}
