// Physics validation of the CD engine on scenes with known answers (docs/method.md,
// "Validation"):
// a block and a rolling disk on an incline, a column of disks, collisions with e = 0.
#include "cdpile/cd/active_set.hpp"
#include "cdpile/cd/delassus.hpp"
#include "cdpile/cd/engine.hpp"
#include "cdpile/cd/local_solver.hpp"
#include "cdpile/error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

namespace cd = cdpile::cd;
using cdpile::Box;
using cdpile::ContactStatus;
using cdpile::Grains;
using cdpile::Vec2;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kR = 0.5e-3;    // disk radius [m] (D = 1 mm)
constexpr double kRho = 2500.0;  // glass [kg/m^3]

cd::Settings settings(double mu_wall = 0.5) {
  cd::Settings s;
  s.mu_wall = mu_wall;
  s.tolerance = 1e-10;  // the analytic answers are exact per step: converge fully
  return s;
}

/// One disk resting on the floor (gap 0), far from the side walls.
Grains one_disk() {
  Grains g;
  g.add_disk(kR, kRho, Vec2(0.05, kR));
  return g;
}

}  // namespace

// --- the local solver ------------------------------------------------------------

TEST(LocalSolver, CasesOfTheDiagonalBlock) {
  // open: approaching velocity is not needed, no impulse
  auto open = cd::local_solve_diagonal(2.0, 6.0, 0.5, 0.1, -3.0);
  EXPECT_EQ(open.status, ContactStatus::open);
  EXPECT_EQ(open.rn, 0.0);
  EXPECT_EQ(open.rt, 0.0);
  // stick: R = -W^-1 b, inside the cone: u = W R + b = 0
  auto stick = cd::local_solve_diagonal(2.0, 6.0, 0.5, -1.0, 1.2);
  EXPECT_EQ(stick.status, ContactStatus::stick);
  EXPECT_DOUBLE_EQ(stick.rn, 0.5);
  EXPECT_DOUBLE_EQ(stick.rt, -0.2);
  // slide: |b_t| / W_tt > mu b_n / W_nn; R_t on the cone, exactly, opposing b_t
  auto slide = cd::local_solve_diagonal(2.0, 6.0, 0.5, -1.0, 3.0);
  EXPECT_EQ(slide.status, ContactStatus::slide);
  EXPECT_DOUBLE_EQ(slide.rn, 0.5);
  EXPECT_EQ(std::abs(slide.rt), 0.5 * slide.rn);
  EXPECT_LT(slide.rt, 0.0);
}

TEST(LocalSolver, FullBlockSatisfiesTheLaw) {
  // With a coupled block the solution must still satisfy Signorini-Coulomb exactly.
  const double w_nn = 2.0, w_nt = 0.4, w_tn = 0.4, w_tt = 5.0, mu = 0.3;
  for (double bn : {-1.0, -0.3}) {
    for (double bt : {-4.0, -1.0, -0.05, 0.0, 0.2, 1.0, 4.0}) {
      auto r = cd::local_solve(w_nn, w_nt, w_tn, w_tt, mu, bn, bt);
      const double un = w_nn * r.rn + w_nt * r.rt + bn;
      const double ut = w_tn * r.rn + w_tt * r.rt + bt;
      EXPECT_GT(r.rn, 0.0);
      EXPECT_NEAR(un, 0.0, 1e-12);
      EXPECT_LE(std::abs(r.rt), mu * r.rn * (1 + 1e-12));
      if (r.status == ContactStatus::stick) {
        EXPECT_NEAR(ut, 0.0, 1e-12);
      } else {
        EXPECT_LE(ut * r.rt, 1e-15);  // sliding: R_t opposes u_t
      }
    }
  }
}

// --- a disk with locked rotation on a tilted floor (a block) ----------------------

TEST(Incline, LockedDiskSticksWhileTanThetaAtMostMu) {
  // tan(theta) <= mu = 0.5, i.e. theta <= 26.565 deg: the block stays at rest.
  for (double deg : {5.0, 20.0, 26.0}) {
    cd::Engine e(Box{0.1, 0.05}, one_disk(), settings());
    e.lock_rotation(0);
    cd::StepReport rep;
    for (int k = 0; k < 200; ++k) rep = e.step(deg * kDeg);
    EXPECT_LT(e.grains().velocity[0].norm(), 1e-12) << deg;
    EXPECT_NEAR(e.grains().position[0].x(), 0.05, 1e-15) << deg;
    // The floor carries the weight's normal component: f_n = m g cos(theta).
    const auto c = e.contacts();
    ASSERT_EQ(c.size(), 1u);
    const double m = e.grains().mass[0];
    EXPECT_NEAR(c.fn[0], m * 9.81 * std::cos(deg * kDeg), 1e-9 * m * 9.81);
    EXPECT_NEAR(std::abs(c.ft[0]), m * 9.81 * std::sin(deg * kDeg), 1e-9 * m * 9.81);
    EXPECT_EQ(c.status[0], ContactStatus::stick);
  }
}

TEST(Incline, LockedDiskSlidesAboveWithCoulombAcceleration) {
  // a = g (sin theta - mu cos theta): 0.0670 g at 30 deg (docs/method.md, "Validation").
  for (double deg : {30.0, 45.0}) {
    cd::Engine e(Box{0.5, 0.05}, one_disk(), settings());
    e.lock_rotation(0);
    const int steps = 100;
    for (int k = 0; k < steps; ++k) e.step(deg * kDeg);
    const double t = steps * e.settings().time_step;
    const double a = 9.81 * (std::sin(deg * kDeg) - 0.5 * std::cos(deg * kDeg));
    EXPECT_NEAR(e.grains().velocity[0].x(), a * t, 1e-12) << deg;
    EXPECT_NEAR(e.grains().velocity[0].y(), 0.0, 1e-15);
    const auto c = e.contacts();
    ASSERT_EQ(c.size(), 1u);
    EXPECT_EQ(c.status[0], ContactStatus::slide);
    EXPECT_EQ(std::abs(c.ft[0]), 0.5 * c.fn[0]);  // exactly on the cone
  }
  EXPECT_NEAR(9.81 * (std::sin(30 * kDeg) - 0.5 * std::cos(30 * kDeg)) / 9.81, 0.0670, 1e-4);
}

// --- a free disk rolls on a frictional incline ------------------------------------

TEST(Incline, FreeDiskRollsWithoutSlipAtTwoThirdsGSinTheta) {
  // Rolling holds while tan(theta) <= 3 mu (theta <= 56.31 deg): a = (2/3) g sin theta,
  // and the contact point does not slip: v_x = -omega r.
  for (double deg : {10.0, 30.0, 55.0}) {
    cd::Engine e(Box{0.5, 0.05}, one_disk(), settings());
    const int steps = 100;
    for (int k = 0; k < steps; ++k) e.step(deg * kDeg);
    const double t = steps * e.settings().time_step;
    const double v = e.grains().velocity[0].x();
    EXPECT_NEAR(v, 2.0 / 3.0 * 9.81 * std::sin(deg * kDeg) * t, 1e-12) << deg;
    EXPECT_NEAR(v + e.grains().angular_velocity[0] * kR, 0.0, 1e-12) << deg;
    EXPECT_EQ(e.contacts().status[0], ContactStatus::stick);
  }
}

TEST(Incline, FreeDiskSlipsAboveThreeMu) {
  // Above 56.31 deg: a = g (sin theta - mu cos theta), alpha = 2 mu g cos theta / r;
  // a = 0.616 g at 60 deg (docs/method.md, "Validation").
  const double deg = 60.0;
  cd::Engine e(Box{0.5, 0.05}, one_disk(), settings());
  const int steps = 100;
  for (int k = 0; k < steps; ++k) e.step(deg * kDeg);
  const double t = steps * e.settings().time_step;
  const double a = 9.81 * (std::sin(deg * kDeg) - 0.5 * std::cos(deg * kDeg));
  EXPECT_NEAR(a / 9.81, 0.616, 1e-3);
  EXPECT_NEAR(e.grains().velocity[0].x(), a * t, 1e-12);
  EXPECT_NEAR(e.grains().angular_velocity[0], -2.0 * 0.5 * 9.81 * std::cos(deg * kDeg) / kR * t,
              1e-9);
  EXPECT_EQ(e.contacts().status[0], ContactStatus::slide);
}

// --- a column of k equal disks ---------------------------------------------------

TEST(Column, ContactUnderTheNthDiskCarriesNmg) {
  const int k = 10;
  Grains g;
  for (int n = 0; n < k; ++n) g.add_disk(kR, kRho, Vec2(0.01, kR + 2 * kR * n));
  for (bool symmetric : {true, false}) {
    cd::Settings s = settings();
    s.symmetric_sweeps = symmetric;
    cd::Engine e(Box{0.02, 0.02}, g, s);
    cd::StepReport rep;
    for (int step = 0; step < 20; ++step) rep = e.step(0.0);
    EXPECT_TRUE(rep.converged);
    const double mg = e.grains().mass[0] * 9.81;
    const auto c = e.contacts();
    ASSERT_EQ(c.size(), static_cast<std::size_t>(k));
    for (std::size_t q = 0; q < c.size(); ++q) {
      // Grain i = 0 is at the bottom: the floor carries k m g, the contact (i, i+1)
      // carries the k - 1 - i disks above it.
      const int carried = c.j[q] < 0 ? k : k - 1 - c.i[q];
      EXPECT_NEAR(c.fn[q], carried * mg, 1e-9 * k * mg) << "contact " << q;
      EXPECT_EQ(c.ft[q], 0.0);
    }
    EXPECT_LT(e.grains().velocity[k - 1].norm(), 1e-8 * 9.81 * e.settings().time_step);
  }
}

// A step is static only when no grain is in flight (docs/analysis.md, "Static and
// moving states"): a disk released 2 D above a resting one has no contact while it
// falls (free fall for sqrt(2 * 2D / g) = 20 ms, 200 steps of 0.1 ms) and its largest speed is
// g t; once it has landed, both rest on contacts and the count is 0.
TEST(Column, AFallingDiskIsCountedWithoutContactUntilItLands) {
  Grains g;
  g.add_disk(kR, kRho, Vec2(0.01, kR));
  g.add_disk(kR, kRho, Vec2(0.01, kR + 2 * kR + 2e-3));
  cd::Engine e(Box{0.02, 0.02}, g, settings());
  const double h = e.settings().time_step;
  cd::StepReport rep = e.step(0.0);
  EXPECT_EQ(rep.grains_without_contact, 1);
  EXPECT_NEAR(rep.max_speed, 9.81 * h, 1e-9);
  for (int step = 0; step < 150; ++step) rep = e.step(0.0);
  EXPECT_EQ(rep.grains_without_contact, 1);  // still in flight at 15 ms
  for (int step = 0; step < 400; ++step) rep = e.step(0.0);
  EXPECT_EQ(rep.grains_without_contact, 0);
  EXPECT_EQ(rep.contacts, 2);
  EXPECT_LT(rep.max_speed, 1e-8);
}

// Hitting the sweep cap is reported, never silent: a column of 10 disks starting from
// rest without a warm start needs its weight carried down 10 contacts, which 3 sweeps
// cannot do; the report says so (converged false, the cap's sweeps, the residual above
// the tolerance), and with the cap lifted the same step converges.
TEST(Column, HittingTheSweepCapIsReported) {
  Grains g;
  for (int n = 0; n < 10; ++n) g.add_disk(kR, kRho, Vec2(0.01, kR + 2 * kR * n));
  cd::Settings s = settings();
  s.max_sweeps = 3;
  cd::Engine capped(Box{0.02, 0.02}, g, s);
  const cd::StepReport rep = capped.step(0.0);
  EXPECT_FALSE(rep.converged);
  EXPECT_EQ(rep.sweeps, 3);
  EXPECT_GT(rep.residual, s.tolerance);
  s.max_sweeps = 2000;
  cd::Engine free(Box{0.02, 0.02}, g, s);
  const cd::StepReport ok = free.step(0.0);
  EXPECT_TRUE(ok.converged);
  EXPECT_GT(ok.sweeps, 3);
  EXPECT_LE(ok.residual, s.tolerance);
}

// The three convergence criteria stop at the first sweep that meets their rule, and not
// before: the same 10-disk column from rest (no warm start), run once to convergence
// and once with the cap one sweep short, which must then report no convergence. The
// root mean square of the corrections never exceeds their largest, so 'quad' stops no
// later than 'qm16', which stops no later than 'maxm'.
TEST(Column, EachCriterionStopsAtTheFirstSweepThatMeetsIt) {
  Grains g;
  for (int n = 0; n < 10; ++n) g.add_disk(kR, kRho, Vec2(0.01, kR + 2 * kR * n));
  const double tol = 1e-6;
  auto first_step = [&](cd::Criterion c, int cap) {
    cd::Settings s = settings();
    s.tolerance = tol;
    s.criterion = c;
    s.max_sweeps = cap;
    cd::Engine e(Box{0.02, 0.02}, g, s);
    return e.step(0.0);
  };
  int sweeps[3] = {0, 0, 0};
  const cd::Criterion all[3] = {cd::Criterion::maxm, cd::Criterion::qm16, cd::Criterion::quad};
  for (int k = 0; k < 3; ++k) {
    const cd::StepReport ok = first_step(all[k], 2000);
    ASSERT_TRUE(ok.converged) << cd::criterion_name(all[k]);
    EXPECT_LE(ok.residual_rms, ok.residual);
    switch (all[k]) {
      case cd::Criterion::maxm: EXPECT_LE(ok.residual, tol); break;
      case cd::Criterion::qm16:
        EXPECT_LE(ok.residual_rms, tol);
        EXPECT_LE(ok.residual, cd::qm16_max_factor * tol);
        break;
      case cd::Criterion::quad: EXPECT_LE(ok.residual_rms, tol); break;
      case cd::Criterion::law:
      case cd::Criterion::err: break;  // not among the three compared here
    }
    ASSERT_GT(ok.sweeps, 1);
    const cd::StepReport short_cap = first_step(all[k], ok.sweeps - 1);
    EXPECT_FALSE(short_cap.converged) << cd::criterion_name(all[k]);
    sweeps[k] = ok.sweeps;
  }
  EXPECT_GE(sweeps[0], sweeps[1]);
  EXPECT_GE(sweeps[1], sweeps[2]);
  EXPECT_GT(sweeps[0], sweeps[2]);  // ten contacts: the mean is well below the max
}

TEST(Criterion, NamesRoundTripAndAnUnknownOneIsAUsageError) {
  for (const cd::Criterion c : {cd::Criterion::maxm, cd::Criterion::quad, cd::Criterion::qm16})
    EXPECT_EQ(cd::criterion_from_name(cd::criterion_name(c)), c);
  EXPECT_THROW(cd::criterion_from_name("Quad "), cdpile::UsageError);
}

// --- collisions with restitution 0 -----------------------------------------------

TEST(Collision, HeadOnGivesACommonVelocity) {
  cd::Settings s = settings();
  s.gravity = 0.0;
  Grains g;
  g.add_disk(kR, kRho, Vec2(0.01, 0.01));
  // Initial gap 0.1 D, several steps of approach: the contact must close without overlap.
  g.add_disk(1.5 * kR, kRho, Vec2(0.01 + 2.5 * kR + 1e-4, 0.01));
  g.velocity[0] = Vec2(0.2, 0.0);
  g.velocity[1] = Vec2(-0.05, 0.0);
  const double m0 = g.mass[0], m1 = g.mass[1];
  const double p = m0 * 0.2 - m1 * 0.05;
  const double e0 = 0.5 * m0 * 0.04 + 0.5 * m1 * 0.0025;
  cd::Engine e(Box{0.05, 0.05}, g, s);
  for (int k = 0; k < 40; ++k) e.step(0.0);
  const Vec2 v0 = e.grains().velocity[0], v1 = e.grains().velocity[1];
  EXPECT_NEAR(v0.x(), p / (m0 + m1), 1e-12);
  EXPECT_NEAR(v1.x(), p / (m0 + m1), 1e-12);
  EXPECT_NEAR(m0 * v0.x() + m1 * v1.x(), p, 1e-12 * std::abs(p));
  // The kinetic energy lost is that of the relative motion: mu_red (v0 - v1)^2 / 2.
  const double lost = 0.5 * m0 * m1 / (m0 + m1) * 0.25 * 0.25;
  const double e1 = 0.5 * m0 * v0.squaredNorm() + 0.5 * m1 * v1.squaredNorm();
  EXPECT_NEAR(e0 - e1, lost, 1e-9 * e0);
  // No overlap was created: contact became active before the surfaces met.
  const double gap = (e.grains().position[1] - e.grains().position[0]).norm() - 2.5 * kR;
  EXPECT_GT(gap, -1e-12);
}

TEST(Collision, EqualMassesLoseHalfTheEnergy) {
  cd::Settings s = settings();
  s.gravity = 0.0;
  Grains g;
  g.add_disk(kR, kRho, Vec2(0.01, 0.01));
  g.add_disk(kR, kRho, Vec2(0.01 + 2 * kR + 1e-5, 0.01));
  g.velocity[0] = Vec2(0.3, 0.0);
  cd::Engine e(Box{0.05, 0.05}, g, s);
  for (int k = 0; k < 10; ++k) e.step(0.0);
  const auto r = e.step(0.0);
  const double e0 = 0.5 * g.mass[0] * 0.09;
  EXPECT_NEAR(r.kinetic_energy, 0.5 * e0, 1e-9 * e0);
  EXPECT_NEAR(e.grains().velocity[1].x(), 0.15, 1e-12);
}

namespace {
/// Two equal touching disks (gap 0), disk 0 at the left, moving with (vn, vt) where vn
/// is its velocity towards disk 1 and vt along +y; no gravity, no spin. theta = 1, so the
/// predicted configuration is the initial one and the normal is exactly +x.
cd::Engine oblique(double vn, double vt) {
  cd::Settings s = settings();
  s.gravity = 0.0;
  s.theta = 1.0;
  Grains g;
  g.add_disk(kR, kRho, Vec2(0.01, 0.01));
  g.add_disk(kR, kRho, Vec2(0.01 + 2 * kR, 0.01));
  g.velocity[0] = Vec2(vn, vt);
  return cd::Engine(Box{0.05, 0.05}, g, s);
}
/// Relative velocity at the contact point, tangential component along +y.
double slip_velocity(const cd::Engine& e) {
  const auto& g = e.grains();
  // point of disk 0: +r x, of disk 1: -r x; omega x (r e_x) = omega r e_y
  return (g.velocity[0].y() + g.angular_velocity[0] * kR) -
         (g.velocity[1].y() - g.angular_velocity[1] * kR);
}
}  // namespace

TEST(Collision, ObliqueSticksWhenTangentialAtMostThreeMuNormal) {
  // Equal uniform disks: W_tt = 3 W_nn, so the contact sticks iff |u_t| <= 3 mu |u_n|.
  auto e = oblique(0.2, 0.25);  // 0.25 <= 1.5 * 0.2
  auto r = e.step(0.0);
  EXPECT_EQ(r.contacts, 1);
  EXPECT_EQ(e.contacts().status[0], ContactStatus::stick);
  EXPECT_NEAR(slip_velocity(e), 0.0, 1e-12);
  EXPECT_NEAR(e.grains().velocity[0].x() - e.grains().velocity[1].x(), 0.0, 1e-12);
}

TEST(Collision, ObliqueSlidesAboveAsTheLocalSolutionSays) {
  const double un = 0.2, ut = 0.5;  // 0.5 > 1.5 * 0.2: slide
  auto e = oblique(un, ut);
  e.step(0.0);
  const auto c = e.contacts();
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c.status[0], ContactStatus::slide);
  EXPECT_EQ(std::abs(c.ft[0]), 0.5 * c.fn[0]);
  // Normal velocity cancelled; slip reduced by W_tt mu R_n = 3 mu u_n.
  EXPECT_NEAR(e.grains().velocity[0].x() - e.grains().velocity[1].x(), 0.0, 1e-12);
  EXPECT_NEAR(slip_velocity(e), ut - 3 * 0.5 * un, 1e-12);
}

// --- warm start and state ---------------------------------------------------------

TEST(Engine, StateRoundTripContinuesBitForBit) {
  Grains g;
  for (int n = 0; n < 6; ++n)
    g.add_disk(kR * (1 + 0.1 * n), kRho,
               Vec2(0.003 + 0.0011 * n, kR * (1 + 0.1 * n) + 0.0005 * (n % 2)));
  cd::Settings s;
  cd::Engine a(Box{0.02, 0.02}, g, s);
  for (int k = 0; k < 150; ++k) a.step(0.01 * k * kDeg);
  cd::Engine b(Box{0.02, 0.02}, a.grains(), s);
  b.set_state(a.state());
  for (int k = 150; k < 300; ++k) {
    a.step(0.01 * k * kDeg);
    b.step(0.01 * k * kDeg);
  }
  for (std::size_t i = 0; i < g.size(); ++i) {
    EXPECT_EQ(a.grains().position[i], b.grains().position[i]);
    EXPECT_EQ(a.grains().velocity[i], b.grains().velocity[i]);
    EXPECT_EQ(a.grains().angular_velocity[i], b.grains().angular_velocity[i]);
  }
}

// A cancelled step changes nothing that a checkpoint holds: the 10-disk column from rest
// needs many sweeps; cancelled after 3 of them (both solvers), the engine's grains and
// state are those before the step, and the same engine then steps exactly as one never
// cancelled.
TEST(Engine, ACancelledStepLeavesTheStateOfTheLastCompletedStep) {
  for (const cd::SolverKind kind : {cd::SolverKind::nsgs, cd::SolverKind::nncg}) {
    Grains g;
    for (int n = 0; n < 10; ++n) g.add_disk(kR, kRho, Vec2(0.01, kR + 2 * kR * n));
    cd::Settings s = settings();
    s.solver = kind;
    cd::Engine ref(Box{0.02, 0.02}, g, s), cut(Box{0.02, 0.02}, g, s);
    ref.step(0.0);
    cut.step(0.0);
    const Grains before = cut.grains();
    const cd::EngineState state = cut.state();
    int polls = 0;
    cut.set_cancel([&] { return ++polls > 3; });
    EXPECT_THROW(cut.step(30 * kDeg), cd::StepCancelled);  // a new load: many sweeps
    EXPECT_EQ(polls, 4);
    EXPECT_EQ(cut.grains().position, before.position);
    EXPECT_EQ(cut.grains().velocity, before.velocity);
    EXPECT_EQ(cut.grains().angular_velocity, before.angular_velocity);
    EXPECT_EQ(cut.state().step, state.step);
    ASSERT_EQ(cut.state().impulses.size(), state.impulses.size());
    for (std::size_t k = 0; k < state.impulses.size(); ++k) {
      EXPECT_EQ(cut.state().impulses[k].rn, state.impulses[k].rn);
      EXPECT_EQ(cut.state().impulses[k].rt, state.impulses[k].rt);
    }
    cut.set_cancel({});
    for (int k = 1; k < 4; ++k) {
      const cd::StepReport a = ref.step(30 * k * kDeg), b = cut.step(30 * k * kDeg);
      EXPECT_EQ(a.sweeps, b.sweeps);
    }
    EXPECT_EQ(cut.grains().position, ref.grains().position);
    EXPECT_EQ(cut.grains().velocity, ref.grains().velocity);
  }
}

// --- the last step's problem in Delassus form --------------------------------------

// A disk at rest on the floor tilted by theta: H maps (v, w) to u_n = v_y and
// u_t = -v_x - w r (t = (-n_y, n_x) = (-1, 0) for the floor's normal (0, 1)), so
// W = diag(1/m, 1/m + r^2/I) and the free local velocity is h g(theta) in that frame:
// q = (-g h cos theta, -g h sin theta). The step's impulses solve it.
TEST(DelassusExport, OneDiskOnTheFloorIsTheAnalyticProblem) {
  const double deg = 20.0;
  cd::Engine e(Box{0.1, 0.05}, one_disk(), settings());
  e.step(deg * kDeg);  // settles nothing: the disk starts at rest with a zero gap
  const cd::DelassusProblem p = e.delassus_problem();
  ASSERT_EQ(p.contacts(), 1);
  const double m = e.grains().mass[0], inertia = e.grains().inertia[0];
  const double gh = 9.81 * e.settings().time_step;
  EXPECT_DOUBLE_EQ(p.W.coeff(0, 0), 1.0 / m);
  EXPECT_DOUBLE_EQ(p.W.coeff(1, 1), 1.0 / m + kR * kR / inertia);
  EXPECT_EQ(p.W.coeff(0, 1), 0.0);
  EXPECT_EQ(p.W.coeff(1, 0), 0.0);
  EXPECT_NEAR(p.q[0], -gh * std::cos(deg * kDeg), 1e-15);
  EXPECT_NEAR(p.q[1], -gh * std::sin(deg * kDeg), 1e-15);
  EXPECT_EQ(p.mu[0], e.settings().mu_wall);
  const Eigen::VectorXd r = e.local_impulses();
  const auto c = e.contacts();
  EXPECT_DOUBLE_EQ(r[0], c.fn[0] * e.settings().time_step);
  EXPECT_DOUBLE_EQ(r[1], c.ft[0] * e.settings().time_step);
  EXPECT_LT(cd::natural_map_residual(p, r), 1e-12);
}

// The problem of a column of disks (a chain of contacts: W couples each contact with its
// neighbours through the disk they share) is the one the engine solved: its impulses
// give a natural-map residual at the engine's tolerance, and solve_nsgs from zero finds
// the same impulses, each contact carrying the disks above it (r_n = k m g h).
TEST(DelassusExport, AColumnIsSolvedAgainToTheSameImpulses) {
  const int k = 6;
  Grains g;
  for (int n = 0; n < k; ++n) g.add_disk(kR, kRho, Vec2(0.01, kR + 2 * kR * n));
  cd::Engine e(Box{0.02, 0.02}, g, settings());
  for (int step = 0; step < 5; ++step) e.step(0.0);
  const cd::DelassusProblem p = e.delassus_problem();
  ASSERT_EQ(p.contacts(), k);
  EXPECT_EQ((Eigen::MatrixXd(p.W) - Eigen::MatrixXd(p.W).transpose()).norm(), 0.0);
  const Eigen::VectorXd engine_r = e.local_impulses();
  EXPECT_LT(cd::natural_map_residual(p, engine_r), 1e-9);
  Eigen::VectorXd r;
  const cd::NsgsReport rep = cd::solve_nsgs(p, r, {1e-12, 100000});
  EXPECT_TRUE(rep.converged);
  const double mgh = e.grains().mass[0] * 9.81 * e.settings().time_step;
  const auto c = e.contacts();
  for (Eigen::Index a = 0; a < k; ++a) {
    const int carried =
        c.j[static_cast<std::size_t>(a)] < 0 ? k : k - 1 - c.i[static_cast<std::size_t>(a)];
    EXPECT_NEAR(r[2 * a], carried * mgh, 1e-9 * k * mgh) << "contact " << a;
    EXPECT_NEAR(r[2 * a], engine_r[2 * a], 1e-9 * k * mgh) << "contact " << a;
    EXPECT_NEAR(r[2 * a + 1], 0.0, 1e-12 * mgh) << "contact " << a;
  }
}

// --- adaptive sub-steps (docs/method.md, "Sub-steps") --------------------------------

namespace {

/// A column of `k` disks on the floor with the contact stiffness `stiffness` m g / D and
/// sub-steps down to h / max_substeps after `after` sweeps.
cd::Engine stiff_column(int k, double stiffness, int max_substeps, int after, int cap) {
  Grains g;
  for (int n = 0; n < k; ++n) g.add_disk(kR, kRho, Vec2(0.01, kR + 2 * kR * n));
  cd::Settings s = settings();
  s.tolerance = 1e-8;
  s.contact_stiffness = stiffness * g.mass[0] * 9.81 / (2 * kR);
  s.max_substeps = max_substeps;
  s.substep_after = after;
  s.max_sweeps = cap;
  return cd::Engine(Box{0.02, 0.1}, g, s);
}

/// The contacts of a settled column of k disks carry its weight, n m g under the n-th disk
/// from the top (the floor k m g), within 1e-3 of the column's weight.
void expect_column_carries_its_weight(const cd::Engine& e, int k) {
  const double mg = e.grains().mass[0] * 9.81;
  const auto c = e.contacts();
  ASSERT_EQ(c.size(), static_cast<std::size_t>(k));
  for (std::size_t q = 0; q < c.size(); ++q) {
    const int carried = c.j[q] < 0 ? k : k - 1 - c.i[q];
    EXPECT_NEAR(c.fn[q], carried * mg, 1e-3 * k * mg) << "contact " << q;
  }
}

}  // namespace

// Steps that converge within the budget are never split: with sub-steps allowed the run is
// the unsplit one, bit for bit.
TEST(Substeps, StepsWithinTheBudgetAreNotSplit) {
  cd::Engine a = stiff_column(10, 1e5, 1, 200, 100000),
             b = stiff_column(10, 1e5, 64, 100000, 100000);
  for (int step = 0; step < 200; ++step) {
    const cd::StepReport ra = a.step(0.0), rb = b.step(0.0);
    EXPECT_EQ(rb.substeps, 1);
    EXPECT_EQ(ra.sweeps, rb.sweeps);
  }
  EXPECT_EQ(a.grains().position, b.grains().position);
  EXPECT_EQ(a.grains().velocity, b.grains().velocity);
  EXPECT_EQ(a.state().substep_level, 0);
}

// A column of 30 disks at k = 1e8 m g / D (k h^2 / m = 1e4: Gauss-Seidel's error decays by
// about 1 - 1e-4 per sweep) settles from rest. Capped at 300 sweeps, the unsplit steps
// stop short of the tolerance; split after 30 sweeps, down to h / 256, every step
// converges, in sub-steps (the sub-step's compliance 1/(k h_s^2) is 4 times larger per
// halving), and the contacts carry the column's weight, n m g under the n-th disk from
// the top: the forces are the impulses of the last sub-step over its own h_s.
TEST(Substeps, AStiffColumnSplitsConvergesAndCarriesItsWeight) {
  const int k = 30;
  cd::Engine unsplit = stiff_column(k, 1e8, 1, 30, 300), split = stiff_column(k, 1e8, 256, 30, 300);
  int capped = 0, split_steps = 0;
  for (int step = 0; step < 400; ++step) {
    capped += unsplit.step(0.0).converged ? 0 : 1;
    const cd::StepReport r = split.step(0.0);
    EXPECT_TRUE(r.converged) << "step " << step;
    EXPECT_GE(r.substeps, 1);
    EXPECT_LE(r.substeps, 256);
    split_steps += r.substeps > 1 ? 1 : 0;
  }
  EXPECT_GT(capped, 0);
  EXPECT_GT(split_steps, 0);
  EXPECT_GE(split.profile().substeps, split.profile().steps);
  expect_column_carries_its_weight(split, k);
}

// With the sub-steps starting at h every step (SubstepStart::h), a split step is one whose
// attempt at h failed: it took at least substep_after sweeps there first, and a step
// after a split one that converges at h is not split. Started at the last level, the
// column stays split across steps instead: fewer of its steps are at h, and some split steps
// made no attempt at h. Both converge every step and carry the column's weight.
TEST(Substeps, StartingEachStepAtHSplitsOnlyTheStepsThatFailThere) {
  const int k = 30, after = 30;
  cd::Engine last = stiff_column(k, 1e7, 256, after, 300), at_h = last;
  cd::Settings s = at_h.settings();
  s.substep_start = cd::SubstepStart::h;
  at_h = cd::Engine(at_h.box(), at_h.grains(), s);
  int whole_last = 0, whole_h = 0, split_h = 0, split_without_attempt_last = 0;
  for (int step = 0; step < 400; ++step) {
    const cd::StepReport a = last.step(0.0), b = at_h.step(0.0);
    EXPECT_TRUE(a.converged && b.converged) << "step " << step;
    whole_last += a.substeps == 1;
    whole_h += b.substeps == 1;
    split_without_attempt_last += a.substeps > 1 && a.sweeps < after;
    if (b.substeps > 1) {
      ++split_h;
      EXPECT_GE(b.sweeps, after) << "step " << step;
    }
  }
  EXPECT_GT(split_h, 0);
  EXPECT_GT(whole_h, whole_last);
  EXPECT_GT(split_without_attempt_last, 0);
  expect_column_carries_its_weight(at_h, k);
  EXPECT_EQ(cd::substep_start_from_name("h"), cd::SubstepStart::h);
  EXPECT_STREQ(cd::substep_start_name(cd::SubstepStart::last), "last");
  EXPECT_THROW(cd::substep_start_from_name("first"), cdpile::UsageError);
}

// The sub-step level is part of the state: an engine rebuilt from the grains and state of
// a split run continues it bit for bit; a level beyond the settings' max_substeps is
// refused; and a split step cancelled half way leaves the last completed step's grains
// and impulses.
TEST(Substeps, StateAndCancelKeepTheLastCompletedStep) {
  cd::Engine a = stiff_column(30, 1e8, 256, 30, 300);
  for (int step = 0; step < 20; ++step) a.step(0.0);
  ASSERT_GT(a.state().substep_level, 0);
  cd::Engine b = stiff_column(30, 1e8, 256, 30, 300);
  b = cd::Engine(b.box(), a.grains(), b.settings());
  b.set_state(a.state());
  cd::Engine c = b;
  for (int step = 0; step < 20; ++step) {
    const cd::StepReport ra = a.step(0.0), rb = b.step(0.0);
    EXPECT_EQ(ra.substeps, rb.substeps);
    EXPECT_EQ(ra.sweeps, rb.sweeps);
  }
  EXPECT_EQ(a.grains().position, b.grains().position);
  EXPECT_EQ(a.grains().velocity, b.grains().velocity);

  cd::EngineState deep = a.state();
  deep.substep_level = 9;  // 512 > 256
  EXPECT_THROW(b.set_state(deep), cdpile::Error);

  const Grains before = c.grains();
  const cd::EngineState state = c.state();
  int polls = 0;
  c.set_cancel([&] { return ++polls > 200; });  // past the first sub-step's sweeps
  EXPECT_THROW(c.step(10 * kDeg), cd::StepCancelled);
  EXPECT_EQ(c.grains().position, before.position);
  EXPECT_EQ(c.grains().velocity, before.velocity);
  ASSERT_EQ(c.state().impulses.size(), state.impulses.size());
  for (std::size_t q = 0; q < state.impulses.size(); ++q)
    EXPECT_EQ(c.state().impulses[q].rn, state.impulses[q].rn);
  EXPECT_EQ(c.state().substep_level, state.substep_level);
}

TEST(Substeps, SettingsAreChecked) {
  cd::Settings s = settings();
  s.max_substeps = 3;
  EXPECT_THROW(cd::validate(s), cdpile::UsageError);
  s.max_substeps = 2 * cd::max_substeps_limit;
  EXPECT_THROW(cd::validate(s), cdpile::UsageError);
  s.max_substeps = 16;
  s.substep_after = 0;
  EXPECT_THROW(cd::validate(s), cdpile::UsageError);
  s.substep_after = 1;
  EXPECT_NO_THROW(cd::validate(s));
}

// A locked disk resting on a 20-degree incline with a budget of one sweep: every step
// needs two (the second confirms the first) and is split, down to h / 4. The impulses of
// a sub-step are its force times h / 4, the warm start of the next step rescales them to
// h, and the reported forces are the last sub-step's impulses over h / 4:
// f = m g (cos, sin) as without sub-steps.
TEST(Substeps, ForcesAreTheLastSubstepsImpulsesOverItsStep) {
  Grains g = one_disk();
  const double m = g.mass[0];
  cd::Settings s = settings();
  s.contact_stiffness = 1e6 * m * 9.81 / (2 * kR);
  s.max_substeps = 4;
  s.substep_after = 1;
  cd::Engine e(Box{0.1, 0.05}, g, s);
  e.lock_rotation(0);
  cd::StepReport r;
  for (int n = 0; n < 300; ++n) r = e.step(20 * kDeg);
  EXPECT_EQ(r.substeps, 4);
  EXPECT_TRUE(r.converged);
  const auto c = e.contacts();
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(c.fn[0], m * 9.81 * std::cos(20 * kDeg), 1e-8 * m * 9.81);
  EXPECT_NEAR(std::abs(c.ft[0]), m * 9.81 * std::sin(20 * kDeg), 1e-8 * m * 9.81);
  ASSERT_EQ(e.state().impulses.size(), 1u);  // stored over h, as the state keeps them
  EXPECT_NEAR(e.state().impulses[0].rn, m * 9.81 * std::cos(20 * kDeg) * s.time_step,
              1e-8 * m * 9.81 * s.time_step);
}

// --- a state that is not finite -----------------------------------------------------

// --- the active-set finish (docs/method.md, "Finishing a step by its active set") --------

namespace {

/// The step's problem of a uniform disk on a floor tilted by `deg`, in Delassus form: one
/// contact, W = diag(1/m, 1/m + R^2/I) (I = m R^2 / 2: W_tt = 3/m), q = -g h (cos, sin).
cd::DelassusProblem disk_on_incline(double deg, double mu) {
  const double m = 1.0, gh = 9.81e-4;
  cd::DelassusProblem p;
  p.W.resize(2, 2);
  p.W.insert(0, 0) = 1.0 / m;
  p.W.insert(1, 1) = 3.0 / m;
  p.q = Eigen::Vector2d(-gh * std::cos(deg * kDeg), -gh * std::sin(deg * kDeg));
  p.mu = Eigen::VectorXd::Constant(1, mu);
  return p;
}

}  // namespace

// Rolling without slip needs R_t = m g h sin / 3 (u_t = 0 with W_tt = 3/m), within the cone
// while tan(theta) <= 3 mu; beyond, the disk slides with R_t = mu R_n. The active-set
// Newton from zero impulses finds either exactly, R_n = m g h cos in both.
TEST(ActiveSet, ADiskOnAnInclineRollsOrSlidesAsTheLawSays) {
  const double gh = 9.81e-4, mu = 0.2;  // rolls up to atan(0.6) = 31 degrees
  for (const double deg : {10.0, 30.0, 40.0, 60.0}) {
    const cd::DelassusProblem p = disk_on_incline(deg, mu);
    Eigen::VectorXd r;
    cd::ActiveSetOptions o;
    o.tolerance = 1e-12;
    o.velocity_floor = gh;
    const cd::ActiveSetReport rep = cd::solve_active_set(p, r, o);
    ASSERT_TRUE(rep.converged) << deg << " deg";
    EXPECT_LE(rep.factorisations, 3);
    const double rn = gh * std::cos(deg * kDeg), rolling = gh * std::sin(deg * kDeg) / 3.0;
    EXPECT_NEAR(r[0], rn, 1e-15) << deg << " deg";
    EXPECT_NEAR(r[1], std::tan(deg * kDeg) <= 3 * mu ? rolling : mu * rn, 1e-15) << deg << " deg";
  }
}

// The Newton stops when a set differs from the last by more than max_status_changes
// contacts. 30 disks rolling on an incline at 30 degrees (mu = 0.2: within the cone since
// tan 30 <= 3 mu), independent: from zero impulses Alart and Curnier's projection reads them
// all sliding, the first set's solution all sticking, 30 changes at once. With the cap at
// 20 the Newton stops after one LU, unconverged; with the cap at 30 it solves them all.
TEST(ActiveSet, ANewtonThatChangesMoreStatusesThanItsCapStops) {
  const cd::DelassusProblem one = disk_on_incline(30.0, 0.2);
  const int n = 30;
  cd::DelassusProblem p;
  p.W.resize(2 * n, 2 * n);
  p.q.resize(2 * n);
  p.mu.resize(n);
  for (int a = 0; a < n; ++a) {
    p.W.insert(2 * a, 2 * a) = one.W.coeff(0, 0);
    p.W.insert(2 * a + 1, 2 * a + 1) = one.W.coeff(1, 1);
    p.q.segment<2>(2 * a) = one.q;
    p.mu[a] = one.mu[0];
  }
  cd::ActiveSetOptions o;
  o.tolerance = 1e-12;
  o.velocity_floor = 9.81e-4;
  for (const int cap : {20, 30}) {
    o.max_status_changes = cap;
    Eigen::VectorXd r;
    const cd::ActiveSetReport rep = cd::solve_active_set(p, r, o);
    if (cap < n) {
      EXPECT_FALSE(rep.converged);
      EXPECT_EQ(rep.factorisations, 1);
    } else {
      ASSERT_TRUE(rep.converged);
      EXPECT_EQ(rep.factorisations, 2);
      for (int a = 0; a < n; ++a)  // rolling: R_t = m g h sin / 3
        EXPECT_NEAR(r[2 * a + 1], 9.81e-4 * std::sin(30 * kDeg) / 3.0, 1e-15);
    }
  }
}

namespace {

/// A rigid contact counted twice (two identical rows) pressed by 1e-3 normal and 1e-4
/// tangential velocity: sticking, its sets' systems are singular, and any split of the
/// impulse R_n = 1e-3, R_t = 1e-4 / 3 between the two rows within their cones solves it.
cd::DelassusProblem a_contact_counted_twice() {
  cd::DelassusProblem p;
  p.W.resize(4, 4);
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b) {
      p.W.insert(2 * a, 2 * b) = 1.0;
      p.W.insert(2 * a + 1, 2 * b + 1) = 3.0;
    }
  p.q = Eigen::Vector4d(-1e-3, -1e-4, -1e-3, -1e-4);
  p.mu = Eigen::Vector2d(0.5, 0.5);
  return p;
}

}  // namespace

// A set whose system is singular stops the Newton unconverged instead of returning what the
// LU made of it.
TEST(ActiveSet, ASingularSetStopsUnconverged) {
  const cd::DelassusProblem p = a_contact_counted_twice();
  Eigen::VectorXd r;
  cd::ActiveSetOptions o;
  o.velocity_floor = 9.81e-4;
  const cd::ActiveSetReport rep = cd::solve_active_set(p, r, o);
  EXPECT_FALSE(rep.converged);
  EXPECT_EQ(rep.proximal_solves, 0);
  EXPECT_TRUE(r.allFinite());
}

// With the proximal term (the option measured on rigid steps, docs/performance.md), the
// singular set is solved and the part the law leaves free keeps its start: from equal
// impulses the two rows share the load equally, from (2, 1) they keep that ratio's excess
// (R1 - R2 is the self-stress, which the iterates do not move).
TEST(ActiveSet, TheProximalTermSolvesASingularSetKeepingItsFreePart) {
  const cd::DelassusProblem p = a_contact_counted_twice();
  cd::ActiveSetOptions o;
  o.velocity_floor = 9.81e-4;
  o.tolerance = 1e-12;
  o.proximal = 1e-6;
  o.proximal_iterations = 200;
  for (const double split : {0.5, 2.0 / 3.0}) {
    Eigen::VectorXd r(4);
    r << split * 1e-3, split * 1e-4 / 3, (1 - split) * 1e-3, (1 - split) * 1e-4 / 3;
    r *= 0.9;  // below the load: the Newton has to move the determined part
    const cd::ActiveSetReport rep = cd::solve_active_set(p, r, o);
    ASSERT_TRUE(rep.converged) << split;
    EXPECT_GE(rep.proximal_solves, 1);
    EXPECT_NEAR(r[0] + r[2], 1e-3, 1e-14) << split;
    EXPECT_NEAR(r[1] + r[3], 1e-4 / 3, 1e-14) << split;
    // the free part R1 - R2 as started: 0.9 (2 split - 1) 1e-3
    EXPECT_NEAR(r[0] - r[2], 0.9 * (2 * split - 1) * 1e-3, 1e-12) << split;
  }
}

// The stiff column of "AStiffColumnSplitsConvergesAndCarriesItsWeight", unsplit and capped
// at 300 sweeps, stops short on some steps; handed to the active-set Newton after 100
// sweeps, every step converges at h, the hard ones by the finish (counted per step), and
// the contacts carry the column's weight. Rigid contacts (k = 0) the same: a column is
// isostatic, so its sticking set's system is regular.
TEST(ActiveSet, AStiffColumnConvergesUnsplitByTheFinish) {
  const int k = 30;
  for (const double stiffness : {1e8, 0.0}) {
    cd::Engine plain = stiff_column(k, stiffness, 1, 30, 300), finished = plain;
    cd::Settings s = finished.settings();
    s.finish_after = 100;
    finished = cd::Engine(finished.box(), finished.grains(), s);
    int capped = 0, finishes = 0;
    for (int step = 0; step < 100; ++step) {
      const cd::StepReport a = plain.step(0.0), b = finished.step(0.0);
      capped += a.converged ? 0 : 1;
      EXPECT_EQ(a.finishes, 0);
      EXPECT_TRUE(b.converged) << "k " << stiffness << " step " << step;
      EXPECT_EQ(b.substeps, 1);
      EXPECT_LE(b.sweeps, 300);
      EXPECT_LE(b.law_residual, 1e-6) << "k " << stiffness << " step " << step;
      finishes += b.finishes;
    }
    EXPECT_GT(capped, 0) << "k " << stiffness;
    EXPECT_GT(finishes, 0) << "k " << stiffness;
    expect_column_carries_its_weight(finished, k);
  }
  cd::Settings bad = settings();
  bad.finish_after = -1;
  EXPECT_THROW(cd::Engine(Box{0.02, 0.1}, one_disk(), bad), cdpile::UsageError);
}

TEST(Checks, AStateThatIsNotFiniteStopsTheStepNamed) {
  // A grain thrown with a velocity whose norm overflows (a warm start of 1e300 N, say):
  // the step stops before contact detection indexes its grid with the positions.
  for (double v : {1e300, std::numeric_limits<double>::infinity(),
                   std::numeric_limits<double>::quiet_NaN()}) {
    Grains g = one_disk();
    g.add_disk(kR, kRho, Vec2(0.02, kR));
    g.velocity[1] = Vec2(v, -v);
    cd::Engine e(Box{0.1, 0.05}, g, settings());
    try {
      e.step(0.0);
      FAIL() << "a velocity of " << v << " was stepped";
    } catch (const cdpile::Error& err) {
      EXPECT_EQ(std::string(err.what()).rfind("the state is not finite at tilt 0 deg: grain 1 at ", 0),
                0u)
          << err.what();
    }
  }
}

// --- the contact dashpot (docs/method.md, "The contact dashpot") -------------------

namespace {

/// One disk set on the floor with no force at t = 0, at rest, under gravity, with the
/// spring k [N/m^2] and the dashpot of ratio zeta: step h, fully converged.
cd::Engine disk_set_on_the_floor(double k, double zeta, double h) {
  cd::Settings s = settings();
  s.time_step = h;
  s.contact_stiffness = k;
  s.contact_damping_ratio = zeta;
  return cd::Engine(Box{0.1, 0.1}, one_disk(), s);
}

/// The floor's force on a disk of mass m set on it at rest with no force at t = 0: with
/// the overlap d, m d'' = m g - k d - eta d', d(0) = d'(0) = 0, the force k d + eta d'
/// (underdamped: eta < 2 sqrt(k m)).
double damped_oscillator_force(double k, double eta, double m, double t) {
  const double w0 = std::sqrt(k / m), a = eta / (2 * m), wd = std::sqrt(w0 * w0 - a * a);
  const double g = 9.81, e = std::exp(-a * t);
  const double d = g / (w0 * w0) * (1 - e * (std::cos(wd * t) + a / wd * std::sin(wd * t)));
  const double v = g / wd * e * std::sin(wd * t);
  return k * d + eta * v;
}

}  // namespace

// A disk set on the floor rings as a mass on a spring and dashpot. The dashpot's eta is
// 2 zeta sqrt(k m / 2) (zeta the ratio of a contact between two grains of the mean mass;
// the floor's contact has the reduced mass m, so its own ratio is zeta / sqrt 2). With
// 10 000 steps a period (the backward spring's own damping, (omega h)^2 / 2 a step, then
// 0.4 % over the test), the floor's force follows the damped oscillator to 1 % of m g over
// two periods for zeta = 0 (the spring alone: it rings up to 2 m g), 0.5 and 1; the
// same scene with k h^2 / m = 100, the tools' default at k = 1e6 m g / D, rings not at all
// without the dashpot: the backward spring damps it within the first steps.
TEST(Dashpot, ADiskSetOnTheFloorRingsAsASpringAndDashpot) {
  const Grains g = one_disk();
  const double m = g.mass[0], mg = m * 9.81, h = 1e-6;
  const double w0 = 2 * std::numbers::pi / (10000 * h), k = m * w0 * w0;
  for (const double zeta : {0.0, 0.5, 1.0}) {
    cd::Engine e = disk_set_on_the_floor(k, zeta, h);
    const double eta = 2 * zeta * std::sqrt(k * m / 2);
    double largest = 0.0, worst = 0.0;
    for (int n = 1; n <= 20000; ++n) {
      const cd::StepReport r = e.step(0.0);
      ASSERT_TRUE(r.converged) << zeta << " step " << n;
      const auto c = e.contacts();
      ASSERT_EQ(c.size(), 1u);
      largest = std::max(largest, c.fn[0]);
      worst = std::max(worst, std::abs(c.fn[0] - damped_oscillator_force(k, eta, m, n * h)));
    }
    EXPECT_LT(worst, 0.01 * mg) << "zeta " << zeta;
    const double ratio = zeta / std::sqrt(2.0);
    const double overshoot = std::exp(-ratio * std::numbers::pi / std::sqrt(1 - ratio * ratio));
    if (zeta == 0.0) EXPECT_NEAR(largest, 2 * mg, 0.01 * mg);
    else EXPECT_GT(largest, mg * (1 + 0.5 * overshoot)) << "zeta " << zeta;
  }
  // The same disk at the default's k h^2 / m = 100 (omega h = 10): the force is m g within
  // 1 % from the second step on, with or without the dashpot.
  const double coarse = 10 / w0;
  for (const double zeta : {0.0, 1.0}) {
    cd::Engine e = disk_set_on_the_floor(k, zeta, coarse);
    e.step(0.0);
    for (int n = 2; n <= 50; ++n) {
      e.step(0.0);
      EXPECT_NEAR(e.contacts().fn[0], mg, 0.01 * mg) << "zeta " << zeta << " step " << n;
    }
  }
}

// A column at rest carries its weight with the dashpot as without (the dashpot's force
// vanishes at rest), and what the next step anchors at, the spring's part, is then the
// force itself; an engine rebuilt from its grains and state continues bit for bit.
TEST(Dashpot, AColumnAtRestCarriesItsWeightAndResumesBitForBit) {
  Grains g;
  const int n = 10;
  for (int q = 0; q < n; ++q) g.add_disk(kR, kRho, Vec2(0.01, kR + 2 * kR * q));
  cd::Settings s = settings();
  s.contact_stiffness = 1e6 * g.mass[0] * 9.81 / (2 * kR);
  s.contact_damping_ratio = 1.0;
  cd::Engine a(Box{0.02, 0.02}, g, s);
  for (int step = 0; step < 300; ++step) ASSERT_TRUE(a.step(0.0).converged);
  const double mg = g.mass[0] * 9.81;
  const auto c = a.contacts();
  const cd::EngineState state = a.state();
  ASSERT_EQ(c.size(), static_cast<std::size_t>(n));
  ASSERT_EQ(state.impulses.size(), static_cast<std::size_t>(n));
  for (std::size_t q = 0; q < c.size(); ++q) {
    const int carried = c.j[q] < 0 ? n : n - 1 - c.i[q];
    EXPECT_NEAR(c.fn[q], carried * mg, 1e-6 * n * mg) << "contact " << q;
    EXPECT_NEAR(state.impulses[q].rn / s.time_step, c.fn[q], 1e-6 * n * mg) << "contact " << q;
  }
  cd::Engine b(a.box(), a.grains(), s);
  b.set_state(state);
  for (int step = 0; step < 50; ++step) {
    a.step(5 * kDeg);
    b.step(5 * kDeg);
  }
  EXPECT_EQ(a.grains().position, b.grains().position);
  EXPECT_EQ(a.grains().velocity, b.grains().velocity);
}

// A locked disk sliding down a 30-degree incline with the dashpot: once the contact has
// loaded (a few steps at k = 1e6 m g / D), it slides at the Coulomb acceleration g (sin
// theta - mu cos theta), on the cone, and what the next step anchors at, the spring's part
// of a sliding contact, is its whole force, on the cone: the normal velocity is zero, so
// the dashpot carries nothing.
TEST(Dashpot, ASlidingBlockKeepsTheCoulombAccelerationAndItsSpringOnTheCone) {
  const Grains g = one_disk();
  const double m = g.mass[0], deg = 30.0;
  cd::Settings s = settings();
  s.contact_stiffness = 1e6 * m * 9.81 / (2 * kR);
  s.contact_damping_ratio = 1.0;
  cd::Engine e(Box{0.5, 0.05}, g, s);
  e.lock_rotation(0);
  for (int k = 0; k < 100; ++k) e.step(deg * kDeg);
  const double v0 = e.grains().velocity[0].x();
  for (int k = 0; k < 100; ++k) ASSERT_TRUE(e.step(deg * kDeg).converged);
  const double a = 9.81 * (std::sin(deg * kDeg) - 0.5 * std::cos(deg * kDeg));
  EXPECT_NEAR(e.grains().velocity[0].x() - v0, a * 100 * s.time_step, 1e-9);
  const auto c = e.contacts();
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c.status[0], ContactStatus::slide);
  EXPECT_NEAR(c.fn[0], m * 9.81 * std::cos(deg * kDeg), 1e-9 * m * 9.81);
  const cd::EngineState state = e.state();
  ASSERT_EQ(state.impulses.size(), 1u);
  EXPECT_NEAR(state.impulses[0].rn, c.fn[0] * s.time_step, 1e-9 * c.fn[0] * s.time_step);
  EXPECT_NEAR(std::abs(state.impulses[0].rt), 0.5 * state.impulses[0].rn, 1e-12 * state.impulses[0].rn);
}

// Sub-steps with the dashpot: every step split into 4 (`--substep-after 1`) rings as steps
// of h / 4 do: the compliance and the spring's share follow the sub-step. The disk set on
// the floor of the test above, 500 steps of h against 2000 of h / 4.
TEST(Dashpot, SubstepsRingAsTheFinerSteps) {
  const Grains g = one_disk();
  const double m = g.mass[0], mg = m * 9.81, h = 4e-6;
  const double w0 = 2 * std::numbers::pi / (1000 * h), k = m * w0 * w0;
  cd::Engine split = disk_set_on_the_floor(k, 0.5, h), fine = disk_set_on_the_floor(k, 0.5, h / 4);
  cd::Settings s = split.settings();
  s.max_substeps = 4;
  s.substep_after = 1;
  split = cd::Engine(split.box(), split.grains(), s);
  for (int n = 1; n <= 500; ++n) {
    const cd::StepReport r = split.step(0.0);
    ASSERT_EQ(r.substeps, 4) << "step " << n;
    for (int q = 0; q < 4; ++q) fine.step(0.0);
    ASSERT_EQ(fine.contacts().size(), 1u);
    EXPECT_NEAR(split.contacts().fn[0], fine.contacts().fn[0], 1e-9 * mg) << "step " << n;
  }
  EXPECT_NEAR(split.grains().position[0].y(), fine.grains().position[0].y(), 1e-15);
}

TEST(Dashpot, SettingsAreChecked) {
  cd::Settings s = settings();
  s.contact_damping_ratio = 1.0;  // rigid contacts: no spring to stand beside
  EXPECT_THROW(cd::validate(s), cdpile::UsageError);
  s.contact_stiffness = 1e3;
  EXPECT_NO_THROW(cd::validate(s));
  s.contact_damping_ratio = -0.1;
  EXPECT_THROW(cd::validate(s), cdpile::UsageError);
  s.contact_damping_ratio = std::numeric_limits<double>::infinity();
  EXPECT_THROW(cd::validate(s), cdpile::UsageError);
}
