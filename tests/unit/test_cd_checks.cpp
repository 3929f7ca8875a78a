// The debug-build checks of the contact system's invariants (contact_system.hpp,
// check.hpp): a system a solver has solved passes them, and each fires on the invariant
// it guards when that invariant is broken. The death tests are skipped in Release builds
// (NDEBUG), where the checks are compiled out; the asan preset (Debug) runs them.
#include "cdpile/cd/contact_system.hpp"
#include "cdpile/cd/solver.hpp"
#include "cdpile/model.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace cd = cdpile::cd;

namespace {

constexpr double kM = 2e-3, kI = 2.5e-10, kR = 5e-4;  // a 1 mm glass disk per metre
constexpr double kGh = 9.81e-4;                       // g h at h = 1e-4 s

/// Two disks, one on the floor and one on top of it, just touching (gap 0), falling at
/// g h after the free-velocity stage: rows (0, floor) and (0, 1), in pair order, and the
/// walls' static body last. The impulses are zero, so the bodies hold v_free.
cd::ContactSystem two_disks() {
  cd::ContactSystem s;
  s.bodies = {{0.0, -kGh, 0.0, 1 / kM, 1 / kI},
              {0.0, -kGh, 0.0, 1 / kM, 1 / kI},
              {0.0, 0.0, 0.0, 0.0, 0.0}};
  auto row = [](std::int32_t i, std::int32_t j, std::int32_t bj, double ny, double rj,
                double inv_m_j, double inv_i_j) {
    cd::ContactRow r{};
    r.i = i;
    r.j = j;
    r.bi = i;
    r.bj = bj;
    r.nx = 0.0;
    r.ny = ny;
    r.ri = kR;
    r.rj = rj;
    r.w_nn = 1 / kM + inv_m_j;
    r.w_tt = 1 / kM + kR * kR / kI + inv_m_j + rj * rj * inv_i_j;
    r.mu = 0.5;
    r.status = cdpile::ContactStatus::open;
    return r;
  };
  // Grain 0 is the lower one: the normal of (0, 1) points from 1 to 0, downwards.
  s.rows = {row(0, cdpile::wall_floor, 2, 1.0, 0.0, 0.0, 0.0),
            row(0, 1, 1, -1.0, kR, 1 / kM, 1 / kI)};
  return s;
}

/// two_disks() solved by NSGS: the floor carries both disks, the pair one.
cd::ContactSystem solved() {
  cd::ContactSystem s = two_disks();
  cd::SolverSettings settings;
  settings.tolerance = 1e-12;
  cd::make_solver(settings)->solve(s, kGh);
  return s;
}

}  // namespace

// In the test's own body: GTEST_SKIP returns from the function it is written in.
#ifdef NDEBUG
#define SKIP_IN_RELEASE() GTEST_SKIP() << "the checks are compiled out in this build (NDEBUG)"
#else
#define SKIP_IN_RELEASE() static_cast<void>(0)
#endif

TEST(ContactSystemChecks, ASolvedSystemPassesThemRoundingIncluded) {
  cd::ContactSystem s = solved();
  // The solve did something: both contacts carry the weight above them.
  ASSERT_NEAR(s.rows[0].rn, 2 * kM * kGh, 1e-9 * kM * kGh);
  ASSERT_NEAR(s.rows[1].rn, kM * kGh, 1e-9 * kM * kGh);
  cd::debug_check_rows(s);
  cd::debug_check_admissible(s);
  cd::debug_check_velocities(s, two_disks().bodies, kGh);
  // A rounding-sized difference (1e-12 of g h) is not a broken invariant.
  s.bodies[1].vy += 1e-12 * kGh;
  cd::debug_check_velocities(s, two_disks().bodies, kGh);
}

TEST(ContactSystemChecksDeathTest, RowsOutOfPairOrder) {
  SKIP_IN_RELEASE();
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  cd::ContactSystem s = two_disks();
  std::swap(s.rows[0], s.rows[1]);
  EXPECT_DEATH(cd::debug_check_rows(s), "invariant broken: row 1 \\(0, -1\\) is not after");
}

TEST(ContactSystemChecksDeathTest, APairTwice) {
  SKIP_IN_RELEASE();
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  cd::ContactSystem s = two_disks();
  s.rows.push_back(s.rows[1]);
  EXPECT_DEATH(cd::debug_check_rows(s), "invariant broken: row 2 \\(0, 1\\) is not after");
}

TEST(ContactSystemChecksDeathTest, ADelassusBlockThatIsNotPositive) {
  SKIP_IN_RELEASE();
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  cd::ContactSystem s = two_disks();
  s.rows[1].w_nn = 0.0;
  EXPECT_DEATH(cd::debug_check_rows(s), "invariant broken: row 1 \\(0, 1\\): W_nn 0");
}

TEST(ContactSystemChecksDeathTest, AnImpulseOutsideTheCone) {
  SKIP_IN_RELEASE();
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  cd::ContactSystem s = solved();
  s.rows[0].rt = 0.6 * s.rows[0].rn;  // mu = 0.5
  EXPECT_DEATH(cd::debug_check_admissible(s), "invariant broken: row 0 .*outside the Coulomb cone");
}

TEST(ContactSystemChecksDeathTest, VelocitiesThatTheImpulsesDoNotMake) {
  SKIP_IN_RELEASE();
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  cd::ContactSystem s = solved();
  // An impulse changed without its velocity change (a solver that forgot apply_impulse).
  s.rows[1].rn *= 1.001;
  EXPECT_DEATH(cd::debug_check_velocities(s, two_disks().bodies, kGh),
               "invariant broken: body 0 .* away from v_free \\+ M\\^-1 H\\^T R");
}
