// Threads (docs/method.md, "Threads"): the team and its barrier, the strips schedule, and
// the same numbers, bit for bit, on 1, 2 and 3 threads on the analytic scenes and on
// piles that rearrange. The `tsan` preset runs these under ThreadSanitizer.
#include "cd_scenes.hpp"
#include "cdpile/cd/engine.hpp"
#include "cdpile/cd/nsgs.hpp"
#include "cdpile/cd/schedule.hpp"
#include "cdpile/cd/team.hpp"
#include "cdpile/error.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace cd = cdpile::cd;
using cdpile::Box;
using cdpile::Grains;
using cdpile::Vec2;

namespace {

using cd_scenes::kDeg;
using cd_scenes::kG;
using cd_scenes::kR;
using cd_scenes::kRho;
using cd_scenes::triangular_stack;

cd::Settings in_strips(cd::SolverKind solver, int threads) {
  cd::Settings s;
  s.solver = solver;
  s.sweep_order = cd::SweepOrder::strips;
  s.threads = threads;
  return s;
}

/// What a run leaves: every grain's state and every contact's force, to compare bit for bit.
struct Outcome {
  std::vector<double> numbers;
  std::vector<int> sweeps;
  int unconverged = 0;  ///< steps whose solve stopped at the cap
};

/// Runs `steps` steps of an engine on `threads` threads, the team sharing even the small
/// schedules of these scenes (Team::set_smallest_shared(0)).
template <class Tilt>
Outcome run(const Box& box, const Grains& g, cd::Settings s, int steps, Tilt tilt) {
  cd::Engine e(box, g, s);
  e.set_smallest_shared(0);
  Outcome out;
  for (int n = 0; n < steps; ++n) {
    const cd::StepReport r = e.step(tilt(n));
    out.sweeps.push_back(r.sweeps);
    out.unconverged += r.converged ? 0 : 1;
  }
  const Grains& end = e.grains();
  for (std::size_t i = 0; i < end.size(); ++i)
    out.numbers.insert(out.numbers.end(), {end.position[i].x(), end.position[i].y(),
                                           end.velocity[i].x(), end.velocity[i].y(),
                                           end.angular_velocity[i], end.orientation[i]});
  // The contact table (made on the team's threads), and the impulses kept for the next
  // step's warm start (also gathered on the threads); ids and statuses are exact as doubles
  const cdpile::Contacts c = e.contacts();
  for (std::size_t k = 0; k < c.size(); ++k)
    out.numbers.insert(out.numbers.end(),
                       {double(c.i[k]), double(c.j[k]), c.point[k].x(), c.point[k].y(),
                        c.normal[k].x(), c.normal[k].y(), c.fn[k], c.ft[k], c.gap[k],
                        double(static_cast<int>(c.status[k]))});
  for (const cd::StoredImpulse& p : e.state().impulses)
    out.numbers.insert(out.numbers.end(), {double(p.i), double(p.j), p.rn, p.rt});
  return out;
}

/// A loose heap: disks of radii 0.8 to 1.2 kR on a jittered grid, dropped from rest.
Grains heap(int columns, int rows, unsigned seed) {
  Grains g;
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> radius(0.8 * kR, 1.2 * kR), jitter(-0.1 * kR, 0.1 * kR);
  for (int row = 0; row < rows; ++row)
    for (int k = 0; k < columns; ++k)
      g.add_disk(radius(random), kRho,
                 Vec2((1.3 + 2.6 * k) * kR + jitter(random), (1.3 + 2.6 * row) * kR));
  return g;
}

/// A 12 x 6 lattice of bodies, spacing 1, in 4 strips of width 3, with contacts between
/// neighbours (across, up and diagonal) and from the left column to the walls; the bottom
/// row is glued (static), the walls one static body.
constexpr int kLatticeColumns = 12, kLatticeRows = 6;
cd::ContactSystem lattice() {
  cd::ContactSystem s;
  const int nx = kLatticeColumns, ny = kLatticeRows;
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x)
      s.bodies.push_back(y == 0 ? cd::Body{0, 0, 0, 0, 0} : cd::Body{0, 0, 0, 1, 1});
  s.bodies.push_back({0, 0, 0, 0, 0});  // the walls
  const int walls = nx * ny;
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) s.strip.push_back(y == 0 ? -1 : x / 3);
  s.strip.push_back(-1);
  auto add = [&](int a, int b) {
    cd::ContactRow r{};
    r.i = a;
    r.j = b == walls ? cdpile::wall_left : b;
    r.bi = a;
    r.bj = b;
    s.rows.push_back(r);
  };
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      const int a = y * nx + x;
      if (x == 0) add(a, walls);
      if (x + 1 < nx) add(a, a + 1);
      if (y + 1 < ny) add(a, a + nx);
      if (x + 1 < nx && y + 1 < ny) add(a, a + nx + 1);
    }
  return s;
}

}  // namespace

// Every thread runs the job once per run(), and a barrier separates what the threads wrote
// before it from what they read after it.
TEST(Team, RunsEveryThreadOnceAndTheBarrierSeparatesPhases) {
  for (const int n : {1, 2, 3, 5}) {
    cd::Team team(n);
    std::vector<int> wrote(static_cast<std::size_t>(n), 0), calls(static_cast<std::size_t>(n), 0);
    std::vector<int> read(static_cast<std::size_t>(n * n), -1);
    for (int round = 1; round <= 50; ++round) {
      team.run([&](int t) {
        const auto u = static_cast<std::size_t>(t);
        ++calls[u];
        wrote[u] = round;
        team.barrier();
        for (std::size_t v = 0; v < wrote.size(); ++v) read[u * wrote.size() + v] = wrote[v];
      });
      for (const int v : read) ASSERT_EQ(v, round) << n << " threads";
    }
    for (const int c : calls) EXPECT_EQ(c, 50);
  }
  EXPECT_THROW(cd::Team(0), cdpile::UsageError);
}

// The strips schedule: a permutation of the rows, the even strips first, each strip one
// block in pair order, and no moving body in two blocks of one colour; a contact across
// more than one strip makes the step one group.
TEST(Schedule, StripsShareNoMovingBodyWithinAColour) {
  cd::ContactSystem s = lattice();
  const int nx = kLatticeColumns;
  auto add = [&](int a, int b) {
    cd::ContactRow r{};
    r.i = a;
    r.j = b;
    r.bi = a;
    r.bj = b;
    s.rows.push_back(r);
  };
  const cd::Schedule plan = cd::row_schedule(s, cd::SweepOrder::strips, {});
  ASSERT_TRUE(plan.coloured);
  ASSERT_EQ(plan.colours(), 2u);
  ASSERT_EQ(plan.blocks(), 4u);
  std::vector<std::uint32_t> sorted = plan.positions;
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t q = 0; q < sorted.size(); ++q) ASSERT_EQ(sorted[q], q);
  const int strip_of_block[] = {0, 2, 1, 3};  // even strips, then odd
  for (std::size_t c = 0; c < plan.colours(); ++c) {
    std::vector<int> block_of(s.bodies.size(), -1);
    for (std::uint32_t b = plan.colour_start[c]; b < plan.colour_start[c + 1]; ++b) {
      for (std::uint32_t q = plan.block_start[b]; q < plan.block_start[b + 1]; ++q) {
        const cd::ContactRow& r = s.rows[plan.positions[q]];
        const std::int32_t a = s.strip[r.bi], d = s.strip[r.bj];
        EXPECT_EQ(a < 0 ? std::max(d, 0) : d < 0 ? a : std::min(a, d), strip_of_block[b]);
        if (q > plan.block_start[b]) {
          EXPECT_LT(plan.positions[q - 1], plan.positions[q]);
        }
        for (const std::int32_t body : {r.bi, r.bj}) {
          if (!cd::moves(s.bodies[body])) continue;
          if (block_of[body] < 0) block_of[body] = static_cast<int>(b);
          EXPECT_EQ(block_of[body], static_cast<int>(b)) << "body " << body << " colour " << c;
        }
      }
    }
  }
  // A candidate reaching two strips away: one group, in pair order.
  add(nx + 1, nx + 7);
  const cd::Schedule one = cd::row_schedule(s, cd::SweepOrder::strips, {});
  EXPECT_FALSE(one.coloured);
  EXPECT_EQ(one.blocks(), 1u);
  // as many as fit 4 r_max wide (0), or fewer
  EXPECT_EQ(cd::strip_count(120.0, 0.6, 0), 50);
  EXPECT_EQ(cd::strip_count(120.0, 0.6, 16), 16);
  EXPECT_EQ(cd::strip_count(120.0, 0.6, 51), 50);
  EXPECT_EQ(cd::strip_count(1.0, 1.0, 0), 1);
  EXPECT_EQ(cd::strip_count(1.0, 1.0, 16), 1);
  EXPECT_EQ(cd::sweep_order_from_name("strips"), cd::SweepOrder::strips);
  EXPECT_THROW(cd::sweep_order_from_name("colour"), cdpile::UsageError);
}

// With the bodies stored strip by strip during a solve (RowsInScheduleOrder), the sweeps
// give the same impulses and velocities, bit for bit, as with the bodies in grain order,
// and both are put back: rows in pair order with their body indices, bodies in grain
// order.
TEST(Schedule, BodiesInStripOrderSameSweeps) {
  cd::ContactSystem base = lattice();
  for (std::size_t k = 0; k < base.rows.size(); ++k) {
    cd::ContactRow& r = base.rows[k];
    const double angle = 0.3 * static_cast<double>(k % 7);
    r.nx = std::cos(angle);
    r.ny = std::sin(angle);
    r.ri = 0.5;
    r.rj = r.bj == kLatticeColumns * kLatticeRows ? 0.0 : 0.5;
    r.w_nn = 2.5;
    r.w_tt = 4.0;
    r.mu = 0.5;
    r.gap_velocity = -0.01 * static_cast<double>(1 + k % 5);  // approaching: impulses
  }
  for (std::size_t b = 0; b < base.bodies.size(); ++b)
    if (cd::moves(base.bodies[b])) base.bodies[b].vx = 0.001 * static_cast<double>(b);
  cd::ContactSystem grain_order = base, strip_order = base;
  for (const bool bodies_too : {false, true}) {
    cd::ContactSystem& s = bodies_too ? strip_order : grain_order;
    cd::Schedule plan = cd::row_schedule(s, cd::SweepOrder::strips, {});
    ASSERT_TRUE(plan.coloured);
    const cd::RowsInScheduleOrder in_order(s, plan, bodies_too);
    if (bodies_too) {
      // the static bodies after the moving ones (the bottom row was first)
      EXPECT_TRUE(cd::moves(s.bodies[0]));
      for (std::size_t b = 1; b < s.bodies.size(); ++b)
        if (cd::moves(s.bodies[b])) {
          EXPECT_TRUE(cd::moves(s.bodies[b - 1])) << "a static body before a moving one";
        }
    }
    for (int k = 0; k < 6; ++k) cd::nsgs_sweep(s, k % 2 == 1, plan);
  }
  ASSERT_EQ(strip_order.rows.size(), grain_order.rows.size());
  for (std::size_t k = 0; k < grain_order.rows.size(); ++k) {
    const cd::ContactRow &a = grain_order.rows[k], &b = strip_order.rows[k];
    EXPECT_EQ(a.bi, base.rows[k].bi);
    EXPECT_EQ(b.bi, a.bi);
    EXPECT_EQ(b.bj, a.bj);
    EXPECT_EQ(b.rn, a.rn) << "row " << k;
    EXPECT_EQ(b.rt, a.rt) << "row " << k;
  }
  double moved = 0.0;
  for (std::size_t b = 0; b < grain_order.bodies.size(); ++b) {
    EXPECT_EQ(strip_order.bodies[b].vx, grain_order.bodies[b].vx) << "body " << b;
    EXPECT_EQ(strip_order.bodies[b].vy, grain_order.bodies[b].vy) << "body " << b;
    EXPECT_EQ(strip_order.bodies[b].w, grain_order.bodies[b].w) << "body " << b;
    EXPECT_EQ(strip_order.bodies[b].inv_m, base.bodies[b].inv_m) << "body " << b;
    moved += std::abs(grain_order.bodies[b].vy - base.bodies[b].vy);
  }
  EXPECT_GT(moved, 0.0);  // the sweeps did something to compare
}

// A face's sub-schedule keeps the colours and blocks and, in each block, the kept
// positions in order; made on a team it is the same as on one thread. The blocks of a
// pass are shared among the threads in ranges of unequal numbers of blocks (about equal
// positions): every block is visited once, its colour after the colour before.
TEST(Schedule, SubScheduleAndPassesSameOnEveryTeam) {
  cd::Schedule plan;
  plan.coloured = true;
  // 2 colours of 5 and 4 blocks of 0 to 40 positions, reversed inside each block
  const std::vector<std::uint32_t> sizes = {3, 40, 0, 7, 12, 25, 1, 9, 30};
  plan.block_start = {0};
  for (const std::uint32_t n : sizes) {
    const std::uint32_t first = plan.block_start.back();
    for (std::uint32_t k = 0; k < n; ++k) plan.positions.push_back(first + n - 1 - k);
    plan.block_start.push_back(first + n);
  }
  plan.colour_start = {0, 5, 9};
  auto keep = [](std::uint32_t p) { return p % 3 != 1; };
  std::vector<std::uint32_t> kept_one;
  cd::Schedule face_one;
  cd::sub_schedule(plan, keep, nullptr, kept_one, face_one);
  ASSERT_EQ(face_one.blocks(), plan.blocks());
  EXPECT_EQ(face_one.colour_start, plan.colour_start);
  for (std::size_t b = 0; b < plan.blocks(); ++b) {
    std::vector<std::uint32_t> expect;
    for (std::uint32_t q = plan.block_start[b]; q < plan.block_start[b + 1]; ++q)
      if (keep(plan.positions[q])) expect.push_back(plan.positions[q]);
    const std::vector<std::uint32_t> got(kept_one.begin() + face_one.block_start[b],
                                         kept_one.begin() + face_one.block_start[b + 1]);
    EXPECT_EQ(got, expect) << "block " << b;
  }
  for (std::size_t k = 0; k < face_one.size(); ++k) EXPECT_EQ(face_one.positions[k], k);
  for (const int n : {2, 3, 4}) {
    cd::Team team(n);
    team.set_smallest_shared(0);
    std::vector<std::uint32_t> kept;
    cd::Schedule face;
    cd::sub_schedule(plan, keep, &team, kept, face);
    EXPECT_EQ(kept, kept_one) << n << " threads";
    EXPECT_EQ(face.block_start, face_one.block_start) << n << " threads";
    EXPECT_EQ(face.positions, face_one.positions) << n << " threads";
    for (const bool backward : {false, true}) {
      // each block visited once; every block of the first colour before any of the second
      std::vector<std::atomic<int>> visits(plan.blocks());
      std::atomic<int> order{0};
      std::vector<int> at(plan.blocks(), -1);
      cd::for_each_block(plan, &team, backward, [&](std::size_t first, std::size_t last, std::size_t b) {
        EXPECT_EQ(first, plan.block_start[b]);
        EXPECT_EQ(last, plan.block_start[b + 1]);
        ++visits[b];
        at[b] = order++;
      });
      const std::size_t first_colour = backward ? 1 : 0;
      int last_of_first = -1, first_of_second = 1 << 30;
      for (std::size_t b = 0; b < plan.blocks(); ++b) {
        EXPECT_EQ(visits[b].load(), 1) << "block " << b;
        const bool in_first = (b < plan.colour_start[1]) == (first_colour == 0);
        if (in_first)
          last_of_first = std::max(last_of_first, at[b]);
        else
          first_of_second = std::min(first_of_second, at[b]);
      }
      EXPECT_LT(last_of_first, first_of_second) << n << " threads";
    }
  }
}

// More than one thread needs the strips: pair order is sequential.
TEST(Threads, PairOrderTakesOneThread) {
  cd::Settings s;
  s.threads = 2;
  EXPECT_THROW(cd::validate(s), cdpile::UsageError);
  s.sweep_order = cd::SweepOrder::strips;
  EXPECT_NO_THROW(cd::validate(s));
  s.threads = 0;
  EXPECT_THROW(cd::validate(s), cdpile::UsageError);
}

// The analytic scenes in strips: a locked disk on a 20-degree incline sticks with
// f = m g (cos, sin); a column of 10 disks carries n m g under the n-th from the top; and
// each scene's numbers are the same on 1, 2 and 3 threads.
TEST(Threads, AnalyticScenesSameOnEveryTeam) {
  for (const cd::SolverKind kind : {cd::SolverKind::nsgs, cd::SolverKind::pcg, cd::SolverKind::newton}) {
    Grains disk;
    disk.add_disk(kR, kRho, Vec2(0.05, kR));
    const double m = disk.mass[0];
    cd::Settings s = in_strips(kind, 1);
    s.newton_after = 0;  // newton's steps from the first round
    s.tolerance = 1e-10;
    s.contact_stiffness = 1e6 * m * kG / (2 * kR);
    {
      cd::Engine e(Box{0.1, 0.05}, disk, s);
      e.lock_rotation(0);
      for (int n = 0; n < 300; ++n) e.step(20 * kDeg);
      const auto c = e.contacts();
      ASSERT_EQ(c.size(), 1u);
      EXPECT_NEAR(c.fn[0], m * kG * std::cos(20 * kDeg), 1e-8 * m * kG);
      EXPECT_NEAR(std::abs(c.ft[0]), m * kG * std::sin(20 * kDeg), 1e-8 * m * kG);
    }
    Outcome one;
    for (const int threads : {1, 2, 3}) {
      s.threads = threads;
      const Outcome o = run(Box{0.1, 0.05}, disk, s, 60, [](int) { return 30 * kDeg; });
      if (threads == 1) one = o;
      EXPECT_EQ(o.numbers, one.numbers) << threads << " threads";
    }
    const int k = 10;
    Grains column;
    for (int n = 0; n < k; ++n) column.add_disk(kR, kRho, Vec2(0.01, kR + 2 * kR * n));
    s = in_strips(kind, 1);
    s.tolerance = 1e-10;
    s.max_sweeps = 100000;
    s.contact_stiffness = 1e5 * column.mass[0] * kG / (2 * kR);
    {
      cd::Engine e(Box{0.02, 0.02}, column, s);
      for (int step = 0; step < 400; ++step) e.step(0.0);
      const auto c = e.contacts();
      ASSERT_EQ(c.size(), static_cast<std::size_t>(k));
      const double mg = column.mass[0] * kG;
      for (std::size_t q = 0; q < c.size(); ++q) {
        const int carried = c.j[q] < 0 ? k : k - 1 - c.i[q];
        EXPECT_NEAR(c.fn[q], carried * mg, 1e-6 * k * mg) << "contact " << q;
      }
    }
    for (const int threads : {1, 2, 3}) {
      s.threads = threads;
      const Outcome o = run(Box{0.02, 0.02}, column, s, 50, [](int) { return 0.0; });
      if (threads == 1) one = o;
      EXPECT_EQ(o.numbers, one.numbers) << threads << " threads";
    }
  }
}

// A hyperstatic stack tilted by 10 degrees at k = 1e7 m g / D, and a loose heap of 150
// disks dropped from rest and tilted (it falls, collides and rearranges) at k = 1e6 and
// 1e8 with the tools' solver (pcg, tolerance 1e-6, sub-steps): every number the same on
// 1, 2 and 3 threads, for NSGS and pcg, and every step of the heap converged, at 1e8 too.
TEST(Threads, RearrangingPilesSameOnEveryTeam) {
  const Grains stack = triangular_stack(8);
  const double mg = stack.mass[0] * kG;
  for (const cd::SolverKind kind : {cd::SolverKind::nsgs, cd::SolverKind::pcg, cd::SolverKind::newton}) {
    Outcome one;
    for (const int threads : {1, 2, 3}) {
      cd::Settings s = in_strips(kind, threads);
      s.newton_after = 0;  // newton's steps from the first round
      s.tolerance = 1e-8;
      s.max_sweeps = 1000000;
      s.contact_stiffness = 1e7 * mg / (2 * kR);
      const Outcome o = run(Box{16 * kR, 0.03}, stack, s, 40, [](int) { return 10.0 * kDeg; });
      if (threads == 1) one = o;
      EXPECT_EQ(o.numbers, one.numbers) << cd::solver_name(kind) << ", " << threads << " threads";
      EXPECT_EQ(o.sweeps, one.sweeps) << cd::solver_name(kind) << ", " << threads << " threads";
    }
  }
  const Grains pile = heap(15, 10, 7);
  const double m = pile.mass[0];
  for (const double k : {1e6, 1e8}) {
    Outcome one;
    for (const int threads : {1, 2, 3}) {
      cd::Settings s = in_strips(cd::SolverKind::pcg, threads);
      s.tolerance = 1e-6;
      s.contact_stiffness = k * m * kG / (2 * kR);
      s.max_substeps = 64;
      s.substep_after = 200;
      const Outcome o =
          run(Box{40 * kR, 0.05}, pile, s, 100, [](int n) { return 0.15 * n * kDeg; });
      EXPECT_EQ(o.unconverged, 0) << "k " << k;
      if (threads == 1) one = o;
      EXPECT_EQ(o.numbers, one.numbers) << "k " << k << ", " << threads << " threads";
      EXPECT_EQ(o.sweeps, one.sweeps) << "k " << k << ", " << threads << " threads";
    }
  }
  // Fewer strips than fit (3 of 8: two of one parity, one of the other), on 1 to 3 threads.
  Outcome one;
  for (const int threads : {1, 2, 3}) {
    cd::Settings s = in_strips(cd::SolverKind::pcg, threads);
    s.strips = 3;
    s.contact_stiffness = 1e6 * m * kG / (2 * kR);
    const Outcome o = run(Box{40 * kR, 0.05}, pile, s, 60, [](int n) { return 0.15 * n * kDeg; });
    EXPECT_EQ(o.unconverged, 0);
    if (threads == 1) one = o;
    EXPECT_EQ(o.numbers, one.numbers) << "3 strips, " << threads << " threads";
    EXPECT_EQ(o.sweeps, one.sweeps) << "3 strips, " << threads << " threads";
  }
}
