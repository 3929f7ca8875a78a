// The deposition protocol: a settled pile is static and obeys the contact laws, the
// placement is reproducible to the bit from the seed, and the options are checked.
#include "cdpile/cd/engine.hpp"
#include "cdpile/error.hpp"
#include "cdpile/sim/common.hpp"
#include "cdpile/sim/deposit.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace sim = cdpile::sim;
namespace cd = cdpile::cd;
using cdpile::Contacts;
using cdpile::Grains;
using cdpile::Species;
using cdpile::Vec2;

namespace {

/// A few hundred grains in a box 15 D wide: about 15 layers deep, so the pile has a
/// bulk and its bottom grains carry the weight of the column above them.
sim::DepositOptions small(std::uint64_t seed = 3, std::int64_t grains = 200) {
  sim::DepositOptions o;
  o.grains = grains;
  o.width = 15.0;
  o.seed = seed;
  return o;
}

/// Net force and torque on every grain from the contacts (force on i is +F, on j -F;
/// the torque of F = f_n n + f_t t at the contact is -r f_t on both bodies, engine.cpp).
struct Balance {
  std::vector<Vec2> force;
  std::vector<double> torque;
};
Balance balance(const Grains& g, const Contacts& c, double gravity) {
  Balance b;
  b.force.assign(g.size(), Vec2::Zero());
  b.torque.assign(g.size(), 0.0);
  for (std::size_t i = 0; i < g.size(); ++i) b.force[i] = Vec2(0.0, -gravity * g.mass[i]);
  for (std::size_t k = 0; k < c.size(); ++k) {
    const Vec2 t(-c.normal[k].y(), c.normal[k].x());
    const Vec2 f = c.fn[k] * c.normal[k] + c.ft[k] * t;
    const auto i = static_cast<std::size_t>(c.i[k]);
    b.force[i] += f;
    b.torque[i] -= g.radius[i] * c.ft[k];
    if (c.j[k] >= 0) {
      const auto j = static_cast<std::size_t>(c.j[k]);
      b.force[j] -= f;
      b.torque[j] -= g.radius[j] * c.ft[k];
    }
  }
  return b;
}

void settles_within_the_step_cap(const sim::Pile& p) {
  EXPECT_TRUE(p.settled);
  EXPECT_LT(p.steps, small().max_steps);
  // The rest criterion held at the end: the last rest_steps steps are all quiet.
  const auto& ek = p.series.real.at("kinetic_energy");
  const auto& er = p.series.real.at("rotational_energy");
  const sim::Agitation a(p.grains, small().settings.gravity);
  ASSERT_GE(ek.size(), static_cast<std::size_t>(small().rest_steps));
  for (std::size_t k = ek.size() - static_cast<std::size_t>(small().rest_steps); k < ek.size(); ++k)
    EXPECT_LT(a(ek[k] + er[k]), small().rest_energy);
}

// Every free grain is in equilibrium: contact forces (impulses / h of the last step)
// balance its weight. The imbalance is m dv / h, the velocity change of the last step;
// at rest (Ek < 1e-6 N m g D) it is a small fraction of the weight. Stated tolerance:
// 2 % of the grain's weight m g for the force, 2 % of m g r for the torque.
void balances_force_and_torque(const sim::Pile& p) {
  const double g = small().settings.gravity;
  const Balance b = balance(p.grains, p.contacts, g);
  double worst_f = 0.0, worst_t = 0.0;
  for (std::size_t i = 0; i < p.grains.size(); ++i) {
    if (p.grains.species[i] != Species::free) continue;
    const double w = p.grains.mass[i] * g;
    worst_f = std::max(worst_f, b.force[i].norm() / w);
    worst_t = std::max(worst_t, std::abs(b.torque[i]) / (w * p.grains.radius[i]));
  }
  std::printf("worst force imbalance %.3e m g, torque %.3e m g r\n", worst_f, worst_t);
  EXPECT_LT(worst_f, 0.02);
  EXPECT_LT(worst_t, 0.02);
}

// The contact laws at the end of the settling: f_n >= 0, |f_t| <= mu f_n (to round-off:
// the local solver puts a sliding contact on the cone exactly), overlaps below 1e-3 D.
void obeys_coulomb_with_small_overlaps(const sim::Pile& p) {
  const double D = small().diameter;
  const cd::Settings s = small().settings;
  double worst_overlap = 0.0;
  std::size_t active = 0;
  for (std::size_t k = 0; k < p.contacts.size(); ++k) {
    EXPECT_GE(p.contacts.fn[k], 0.0);
    const double mu = p.contacts.j[k] < 0 ? s.mu_wall : s.mu_grain;
    EXPECT_LE(std::abs(p.contacts.ft[k]), mu * p.contacts.fn[k] * (1.0 + 1e-12)) << "contact " << k;
    if (p.contacts.fn[k] > 0.0) {
      ++active;
      worst_overlap = std::max(worst_overlap, -p.contacts.gap[k]);
    }
  }
  EXPECT_GT(active, p.grains.size());  // a connected pile: more contacts than grains
  std::printf("largest overlap %.3e D\n", worst_overlap / D);
  EXPECT_LT(worst_overlap, 1e-3 * D);
}

// No energy gain at rest: continuing the settled pile (warm-started, as tilt-cd does),
// the mechanical energy E = Ek + Erot + sum m g y of the free grains falls over 200
// steps, and no single step gains more than 1e-6 m g D per grain. That bound is 50
// times below the kinetic energy gravity gives a grain in one free step, g h^2 / (2 D)
// = 4.9e-5 m g D, and about 7 times the jitter the solver tolerance allows: velocity
// errors of tol x the mean W_nn R_n (about 15 layers x g h here) move grains by h times
// that, 1.5e-7 D per step. Restitution 0 and the gap treatment inject nothing else.
void gains_no_energy_at_rest(const sim::Pile& p) {
  const cd::Settings s = small().settings;
  cd::Engine e(p.box, p.grains, s);
  // Warm start from the pile's last impulses, as tilt-cd does: the continuation is the
  // same dynamics as the end of the settling, not a restart from zero impulses.
  cd::EngineState st;
  for (std::size_t k = 0; k < p.contacts.size(); ++k)
    if (p.contacts.fn[k] != 0.0 || p.contacts.ft[k] != 0.0)
      st.impulses.push_back({p.contacts.i[k], p.contacts.j[k], p.contacts.fn[k] * s.time_step,
                             p.contacts.ft[k] * s.time_step});
  e.set_state(st);
  const double scale =
      static_cast<double>(small().grains) * p.grains.mass[0] * s.gravity * small().diameter;
  auto energy = [&](const cd::StepReport& r) {
    double pot = 0.0;
    for (std::size_t i = 0; i < e.grains().size(); ++i)
      if (e.grains().species[i] == Species::free)
        pot += e.grains().mass[i] * s.gravity * e.grains().position[i].y();
    return r.kinetic_energy + r.rotational_energy + pot;
  };
  double first = 0.0, previous = 0.0, worst_gain = -1e300;
  for (int k = 0; k < 200; ++k) {
    const double en = energy(e.step(0.0));
    if (k == 0)
      first = en;
    else
      worst_gain = std::max(worst_gain, (en - previous) / scale);
    previous = en;
  }
  std::printf("largest energy gain per step %.3e N m g D\n", worst_gain);
  EXPECT_LT(worst_gain, 1e-6);
  EXPECT_LE(previous, first);
}

}  // namespace

// One settled pile of 200 grains (about 15 layers in a box 15 D wide), checked four ways;
// one test, so the pile is settled once per test process.
TEST(Deposit, SettledPileIsStaticAndObeysTheContactLaws) {
  const sim::Pile p = sim::deposit(small());
  {
    SCOPED_TRACE("rest criterion");
    settles_within_the_step_cap(p);
  }
  {
    SCOPED_TRACE("force and torque balance");
    balances_force_and_torque(p);
  }
  {
    SCOPED_TRACE("Coulomb and overlaps");
    obeys_coulomb_with_small_overlaps(p);
  }
  {
    SCOPED_TRACE("energy at rest");
    gains_no_energy_at_rest(p);
  }
}

// A pile may settle without friction (a denser preparation; tilt-cd --mu then sets
// the friction of the tilt). Without friction no contact carries a tangential force, the
// grains find the denser packing, and the contact network is near isostatic for
// frictionless disks (z = 4 rattlers excluded, less at the walls and the free surface),
// so z and the packing fraction both exceed those of the same grains settled with mu = 0.5.
TEST(Deposit, AFrictionlessPileIsDenserAndBetterConnected) {
  auto o = small(5, 200);
  const sim::Pile rough = sim::deposit(o);
  o.settings.mu_grain = 0.0;
  o.settings.mu_wall = 0.0;
  const sim::Pile smooth = sim::deposit(o);
  ASSERT_TRUE(smooth.settled);
  std::size_t active = 0;
  for (std::size_t k = 0; k < smooth.contacts.size(); ++k) {
    EXPECT_EQ(smooth.contacts.ft[k], 0.0) << "contact " << k;
    if (smooth.contacts.fn[k] > 0.0) ++active;
  }
  EXPECT_GT(active, smooth.grains.size());
  const auto r = [](const sim::Pile& p, const char* k) {
    return std::get<double>(p.results.at(k));
  };
  std::printf("z %.3f (mu 0) against %.3f (mu 0.5); packing fraction %.4f against %.4f\n",
              r(smooth, "coordination_number"), r(rough, "coordination_number"),
              r(smooth, "packing_fraction"), r(rough, "packing_fraction"));
  EXPECT_GT(r(smooth, "coordination_number"), r(rough, "coordination_number") + 0.2);
  EXPECT_LE(r(smooth, "coordination_number"), 4.0);
  EXPECT_GT(r(smooth, "packing_fraction"), r(rough, "packing_fraction"));
  EXPECT_EQ(std::get<double>(smooth.parameters.at("mu_grain")), 0.0);
}

TEST(Deposit, PlacementHasNoOverlapAndStaysInTheBox) {
  const sim::Placement pl = sim::place_grains(small(7, 300));
  const Grains& g = pl.grains;
  for (std::size_t i = 0; i < g.size(); ++i) {
    EXPECT_GE(g.position[i].x() - g.radius[i], 0.0);
    EXPECT_LE(g.position[i].x() + g.radius[i], pl.box.width);
    EXPECT_GE(g.position[i].y() - g.radius[i], 0.0);
    for (std::size_t j = i + 1; j < g.size(); ++j)
      EXPECT_GT((g.position[i] - g.position[j]).norm(),
                g.radius[i] + g.radius[j] - 1e-15 * pl.box.width)
          << i << " " << j;
  }
  // Diameters in [Dmin, Dmax] with Dmax / Dmin = 1.5 and mean D: Dmin = 0.8 D.
  for (double r : g.radius) {
    EXPECT_GE(2.0 * r, 0.8e-3 * (1 - 1e-12));
    EXPECT_LE(2.0 * r, 1.2e-3 * (1 + 1e-12));
  }
  // The rough floor: glued grains resting on the floor plane, after the free grains.
  std::size_t glued = 0;
  for (std::size_t i = 0; i < g.size(); ++i)
    if (g.species[i] == Species::floor) {
      ++glued;
      EXPECT_GE(i, 300u);
      EXPECT_DOUBLE_EQ(g.position[i].y(), g.radius[i]);
    }
  EXPECT_GE(glued, 12u);  // 15 D wide, grains at most 1.2 D
  EXPECT_EQ(sim::place_grains([] {
              auto o = small(7, 300);
              o.rough_floor = false;
              return o;
            }())
                .grains.size(),
            300u);
}

// The random source is portable: the first draws of std::mt19937_64 seeded with 1 are
// fixed by the standard, and the doubles are made from them by a fixed rule, so these
// values hold on every platform and standard library.
TEST(Deposit, RandomDoublesArePortable) {
  sim::Random r(1);
  std::mt19937_64 ref(1);
  for (int k = 0; k < 5; ++k) EXPECT_EQ(r.uniform(), static_cast<double>(ref() >> 11) * 0x1.0p-53);
  sim::Random r2(5489);  // the standard's default seed; its 10000th draw is specified
  std::mt19937_64 ref2;
  ref2.discard(9999);
  EXPECT_EQ(ref2(), 9981545732273789042ull);
  EXPECT_EQ(r2.uniform(), static_cast<double>(std::mt19937_64(5489)() >> 11) * 0x1.0p-53);
}

TEST(Deposit, SameSeedSamePileToTheBitOtherSeedDiffers) {
  auto o = small(11, 80);
  const sim::Pile a = sim::deposit(o), b = sim::deposit(o);
  ASSERT_EQ(a.grains.size(), b.grains.size());
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_EQ(0, std::memcmp(a.grains.position.data(), b.grains.position.data(),
                           a.grains.size() * sizeof(Vec2)));
  EXPECT_EQ(a.grains.radius, b.grains.radius);
  EXPECT_EQ(a.contacts.fn, b.contacts.fn);
  EXPECT_EQ(a.contacts.ft, b.contacts.ft);
  EXPECT_EQ(a.series.real.at("kinetic_energy"), b.series.real.at("kinetic_energy"));
  o.seed = 12;
  const sim::Pile c = sim::deposit(o);
  EXPECT_NE(a.grains.radius, c.grains.radius);
}

TEST(Deposit, MeasuresOfAKnownLayout) {
  // A square lattice of equal disks touching: packing pi/4 in the bulk, z = 4 inside.
  Grains g;
  const double d = 1e-3;
  const int cols = 10, rows = 12;
  for (int y = 0; y < rows; ++y)
    for (int x = 0; x < cols; ++x) g.add_disk(0.5 * d, 2600, Vec2((x + 0.5) * d, (y + 0.5) * d));
  cdpile::Box box{cols * d, rows * d};
  Contacts c;  // grain-grain contacts of the lattice, all loaded
  for (int y = 0; y < rows; ++y)
    for (int x = 0; x < cols; ++x) {
      const int i = y * cols + x;
      if (x + 1 < cols)
        c.push_back(i + 1, i, Vec2::Zero(), Vec2(1, 0), 1.0, 0.0, 0.0,
                    cdpile::ContactStatus::stick);
      if (y + 1 < rows)
        c.push_back(i + cols, i, Vec2::Zero(), Vec2(0, 1), 1.0, 0.0, 0.0,
                    cdpile::ContactStatus::stick);
    }
  const sim::PileMeasures m = sim::measure_pile(box, g, c);
  EXPECT_NEAR(m.bed_height, rows * d, 1e-15);
  EXPECT_NEAR(m.packing_fraction, M_PI / 4, 1e-9);
  const double bonds = (cols - 1) * rows + cols * (rows - 1);
  EXPECT_NEAR(m.z_all, 2.0 * bonds / (cols * rows), 1e-12);
}

TEST(Deposit, BadOptionsAreUsageErrors) {
  auto bad = [](auto change) {
    auto o = small();
    change(o);
    EXPECT_THROW(sim::validate(o), cdpile::UsageError);
  };
  bad([](sim::DepositOptions& o) { o.grains = 0; });
  bad([](sim::DepositOptions& o) { o.diameter = -1e-3; });
  bad([](sim::DepositOptions& o) { o.ratio = 0.5; });
  bad([](sim::DepositOptions& o) { o.width = 1.0; });
  bad([](sim::DepositOptions& o) { o.density = 0.0; });
  bad([](sim::DepositOptions& o) { o.settings.time_step = -1.0; });
  bad([](sim::DepositOptions& o) { o.settings.mu_grain = -0.1; });
}

TEST(Deposit, TilingSideBySideShiftsCopiesAndDropsTheInnerWalls) {
  // Two grains in a box 3 mm wide: grain 0 leans on the left wall and the floor, grain 1
  // on the right wall, and they touch each other.
  const double w = 3e-3;
  Grains g;
  g.add_disk(0.5e-3, 2600, Vec2(0.5e-3, 0.5e-3));
  g.add_disk(0.5e-3, 2600, Vec2(1.5e-3, 0.5e-3));
  g.velocity[1] = Vec2(0.1, 0.0);
  Contacts c;
  using cdpile::ContactStatus;
  c.push_back(0, cdpile::wall_left, Vec2(0, 0.5e-3), Vec2(1, 0), 1.0, 0.0, 0.0,
              ContactStatus::stick);
  c.push_back(0, cdpile::wall_floor, Vec2(0.5e-3, 0), Vec2(0, 1), 2.0, 0.5, 0.0,
              ContactStatus::slide);
  c.push_back(1, cdpile::wall_right, Vec2(w, 0.5e-3), Vec2(-1, 0), 3.0, 0.0, 0.0,
              ContactStatus::stick);
  c.push_back(1, 0, Vec2(1e-3, 0.5e-3), Vec2(1, 0), 4.0, 0.0, -1e-9, ContactStatus::stick);
  const sim::Tiling t = sim::tile_side_by_side(cdpile::Box{w, 0.01}, g, c, 3);

  EXPECT_EQ(t.box.width, 3 * w);
  EXPECT_EQ(t.box.height, 0.01);
  ASSERT_EQ(t.grains.size(), 6u);
  for (std::size_t k = 0; k < 3; ++k)
    for (std::size_t i = 0; i < 2; ++i) {
      EXPECT_EQ(t.grains.position[2 * k + i],
                g.position[i] + Vec2(static_cast<double>(k) * w, 0.0));
      EXPECT_EQ(t.grains.velocity[2 * k + i], g.velocity[i]);
      EXPECT_EQ(t.grains.mass[2 * k + i], g.mass[i]);
    }
  // Kept: the left wall in copy 0 only, the right wall in copy 2 only, the floor and the
  // grain pair in every copy, renumbered; forces, gaps and status unchanged.
  ASSERT_EQ(t.contacts.size(), 8u);
  const std::vector<std::int32_t> i{0, 0, 1, 2, 3, 4, 5, 5};
  const std::vector<std::int32_t> j{
      cdpile::wall_left,  cdpile::wall_floor, 0, cdpile::wall_floor, 2,
      cdpile::wall_floor, cdpile::wall_right, 4};
  const std::vector<double> fn{1.0, 2.0, 4.0, 2.0, 4.0, 2.0, 3.0, 4.0};
  EXPECT_EQ(t.contacts.i, i);
  EXPECT_EQ(t.contacts.j, j);
  EXPECT_EQ(t.contacts.fn, fn);
  EXPECT_EQ(t.contacts.point[7], Vec2(1e-3 + 2 * w, 0.5e-3));
  EXPECT_EQ(t.contacts.gap[4], -1e-9);
  EXPECT_EQ(t.contacts.status[3], cdpile::ContactStatus::slide);
  EXPECT_EQ(t.contacts.ft[5], 0.5);

  // One copy is the pile itself; no copy is an error.
  const sim::Tiling one = sim::tile_side_by_side(cdpile::Box{w, 0.01}, g, c, 1);
  EXPECT_EQ(one.contacts.j, c.j);
  EXPECT_EQ(one.grains.position, g.position);
  EXPECT_THROW(sim::tile_side_by_side(cdpile::Box{w, 0.01}, g, c, 0), cdpile::UsageError);
}
