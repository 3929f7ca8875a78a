// Critical contacts and the pile state (eqs 1-2) on hand-built contact sets.
#include "cdpile/analysis/critical.hpp"
#include "cdpile/error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace cdpile;
using namespace cdpile::analysis;

namespace {
Contacts make(std::initializer_list<std::tuple<int, int, double, double, ContactStatus>> rows) {
  Contacts c;
  double x = 0.0;
  for (auto [i, j, fn, ft, st] : rows) {
    c.push_back(i, j, Vec2(x, 0.0), Vec2(0.0, 1.0), fn, ft, 0.0, st);
    x += 1.0;
  }
  return c;
}
}  // namespace

TEST(Critical, CoulombThresholdWithTolerance) {
  EXPECT_TRUE(is_critical(1.0, 0.5, 0.5, 0.0));
  EXPECT_TRUE(is_critical(1.0, -0.5, 0.5, 0.0));
  EXPECT_FALSE(is_critical(1.0, 0.4999, 0.5, 0.0));
  EXPECT_TRUE(is_critical(1.0, 0.4995, 0.5, 1e-3));  // (1 - 1e-3) * 0.5 = 0.4995
  EXPECT_FALSE(is_critical(1.0, 0.4994, 0.5, 1e-3));
  EXPECT_FALSE(is_critical(0.0, 0.0, 0.5, 0.0));  // not active
  EXPECT_FALSE(is_critical(-1.0, 0.5, 0.5, 0.0));
}

TEST(Critical, SelectsActiveGrainContactsAndClassifies) {
  using S = ContactStatus;
  // grains 0..4 free, 5 glued to the floor
  std::vector<Species> sp = {Species::free, Species::free, Species::free,
                             Species::free, Species::free, Species::floor};
  Contacts c = make({{0, 1, 2.0, 1.0, S::slide},           // critical (|ft| = mu fn)
                     {1, 2, 2.0, 0.2, S::stick},           // not critical
                     {2, 3, 0.0, 0.0, S::open},            // inactive
                     {0, 2, 1.0, -0.5, S::stick},          // critical by force, solver says stick
                     {3, wall_floor, 1.0, 0.3, S::slide},  // plane wall, mu_wall 0.3: critical
                     {4, 5, 1.0, 0.5, S::slide}});         // glued grain, critical
  Friction mu{0.5, 0.3};
  ContactSet s = select_contacts(c, sp, mu, {});
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s.row, (std::vector<std::size_t>{0, 1, 3}));
  EXPECT_EQ(s.critical, (std::vector<std::uint8_t>{1, 0, 1}));
  EXPECT_EQ(s.sliding, (std::vector<std::uint8_t>{1, 0, 0}));
  EXPECT_DOUBLE_EQ(s.mobilisation[1], 0.2);

  CriticalRule with_walls;
  with_walls.include_walls = true;
  s = select_contacts(c, sp, mu, with_walls);
  ASSERT_EQ(s.size(), 5u);
  EXPECT_EQ(s.critical_count(), 4u);
  EXPECT_EQ(s.sliding_count(), 3u);

  CriticalRule glued_are_grains;
  glued_are_grains.floor_grains_are_walls = false;
  s = select_contacts(c, sp, mu, glued_are_grains);
  EXPECT_EQ(s.size(), 4u);  // the glued-grain contact counts, the plane wall does not
}

TEST(Critical, PileStateByHand) {
  using S = ContactStatus;
  // 5 free grains; grain 4 has no contact and grain 3 one: two rattlers.
  std::vector<Species> sp(5, Species::free);
  Contacts c = make({{0, 1, 1.0, 0.5, S::slide},
                     {1, 2, 1.0, 0.1, S::stick},
                     {2, 3, 1.0, 0.1, S::stick},
                     {0, 2, 1.0, 0.1, S::stick}});
  ContactSet s = select_contacts(c, sp, Friction{0.5, 0.5}, {});
  const double d = 0.002;
  PileState p = pile_state(s, sp, 5, d, RattlerRule::exclude);
  EXPECT_EQ(p.contacts, 4);
  EXPECT_EQ(p.critical, 1);
  EXPECT_EQ(p.sliding, 1);
  EXPECT_EQ(p.loaded_grains, 3);
  EXPECT_DOUBLE_EQ(*p.nu, 0.25);
  EXPECT_DOUBLE_EQ(*p.z, 8.0 / 3.0);
  EXPECT_DOUBLE_EQ(*p.z_all, 8.0 / 5.0);
  EXPECT_NEAR(*p.lambda, std::sqrt(3.0) * d, 1e-15);  // sqrt(2 / (8/3 * 1/4)) D
  PileState q = pile_state(s, sp, 5, d, RattlerRule::include);
  EXPECT_DOUBLE_EQ(*q.z, 8.0 / 5.0);
}

TEST(Critical, EmptyAndNoCriticalGiveNoNaN) {
  ContactSet empty;
  PileState p = pile_state(empty, {}, 10, 1.0, RattlerRule::exclude);
  EXPECT_EQ(p.contacts, 0);
  EXPECT_FALSE(p.nu);
  EXPECT_FALSE(p.lambda);
  EXPECT_FALSE(p.z);  // no loaded grain
  EXPECT_DOUBLE_EQ(*p.z_all, 0.0);

  Contacts c =
      make({{0, 1, 1.0, 0.0, ContactStatus::stick}, {1, 2, 1.0, 0.0, ContactStatus::stick}});
  ContactSet s = select_contacts(c, {}, Friction{}, {});
  p = pile_state(s, {}, 3, 1.0, RattlerRule::exclude);
  EXPECT_DOUBLE_EQ(*p.nu, 0.0);
  EXPECT_FALSE(p.lambda);  // infinite: no critical contact
}

TEST(Critical, BadInputIsAnError) {
  Contacts c = make({{0, 1, 1.0, 0.5, ContactStatus::stick}});
  EXPECT_THROW(select_contacts(c, {}, Friction{0.0, 0.5}, {}), Error);
  EXPECT_THROW(select_contacts(c, {}, Friction{-0.5, 0.5}, {}), Error);
  EXPECT_THROW(select_contacts(c, {}, Friction{0.5, 0.0}, {}), Error);
  CriticalRule bad;
  bad.eps = 1.0;
  EXPECT_THROW(select_contacts(c, {}, Friction{}, bad), Error);
  c.fn[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(select_contacts(c, {}, Friction{}, {}), Error);
}

TEST(Critical, MeanDiameterOfFreeGrains) {
  Grains g;
  g.add_disk(0.5, 1.0, Vec2(0, 0));
  g.add_disk(1.0, 1.0, Vec2(0, 0));
  g.add_disk(5.0, 1.0, Vec2(0, 0), Species::floor);
  EXPECT_DOUBLE_EQ(mean_diameter(g), 1.5);
  EXPECT_EQ(free_grain_count(g), 2);
}

TEST(Critical, MeanKineticEnergyPerFreeGrain) {
  // Three free grains and one glued to the floor, masses and velocities chosen by hand:
  // Ek = (1/2 2 (3^2 + 4^2) + 1/2 1 1^2 + 0) / 3 = (25 + 0.5) / 3 per free grain.
  Grains g;
  for (int k = 0; k < 4; ++k)
    g.add_disk(0.5, 1.0, Vec2(k, 0.5), k == 3 ? Species::floor : Species::free);
  g.mass = {2.0, 1.0, 5.0, 7.0};
  g.velocity = {Vec2(3, -4), Vec2(0, 1), Vec2(0, 0), Vec2(10, 10)};  // the glued one is left out
  g.angular_velocity = {100.0, 100.0, 100.0, 100.0};                 // rotation is not Ek
  ASSERT_TRUE(mean_kinetic_energy(g));
  EXPECT_DOUBLE_EQ(*mean_kinetic_energy(g), 25.5 / 3.0);
  // no free grain, or no velocities: undefined
  Grains glued;
  glued.add_disk(0.5, 1.0, Vec2(0, 0.5), Species::floor);
  EXPECT_FALSE(mean_kinetic_energy(glued));
  g.velocity.clear();
  EXPECT_FALSE(mean_kinetic_energy(g));
}

// The static bound Nc <= 2M - 3N (McNamara & Herrmann 2004; docs/analysis.md, "Static bound").
namespace {
// Grains 0..5 free, 6 glued to the floor; mu_grain 0.5, mu_wall 0.3.
//
//   row  contact          fn   ft    critical?
//   0    0 - floor plane  1    0.3   yes (mu_wall: 0.3 >= 0.3)
//   1    0 - 1            1    0.5   yes
//   2    1 - 6 (glued)    1    0.4   no  (glued grain: mu_grain 0.5; mu_wall would say yes)
//   3    1 - 2            1    0.5   yes
//   4    2 - left wall    1    0.0   no
//   5    0 - 2            1   -0.5   yes
//   6    3 - 2            1    0.5   yes, but 3 has no other active contact: a rattler
//   7    3 - 4            0    0.0   inactive
//   8    4 - 5            1    0.5   yes, but 4 is a rattler (one contact) and, once it goes,
//   9    5 - right wall   1    0.0         5 is left with one contact: a rattler too
//   10   6 - floor plane  5    5.0   two fixed bodies: no unknown of the free grains
//
// Load-bearing: grains 0 (rows 0, 1, 5), 1 (1, 2, 3), 2 (3, 4, 5): N = 3, M = 6 (rows 0-5),
// Nc = 4 (rows 0, 1, 3, 5), B = 2 * 6 - 3 * 3 = 3: Nc > B, above the bound.
const std::vector<Species> bound_species = {Species::free, Species::free, Species::free,
                                            Species::free, Species::free, Species::free,
                                            Species::floor};
Contacts bound_contacts() {
  using S = ContactStatus;
  return make({{0, wall_floor, 1.0, 0.3, S::slide},
               {0, 1, 1.0, 0.5, S::slide},
               {1, 6, 1.0, 0.4, S::stick},
               {1, 2, 1.0, 0.5, S::slide},
               {2, wall_left, 1.0, 0.0, S::stick},
               {0, 2, 1.0, -0.5, S::slide},
               {3, 2, 1.0, 0.5, S::slide},
               {3, 4, 0.0, 0.0, S::open},
               {4, 5, 1.0, 0.5, S::slide},
               {5, wall_right, 1.0, 0.0, S::stick},
               {6, wall_floor, 5.0, 5.0, S::slide}});
}
}  // namespace

TEST(StaticBound, WallsGluedGrainAndRattlersByHand) {
  const StaticBound b = static_bound(bound_contacts(), bound_species, Friction{0.5, 0.3}, 0.0);
  EXPECT_EQ(b.contacts, 6);
  EXPECT_EQ(b.grains, 3);
  EXPECT_EQ(b.critical, 4);
  EXPECT_EQ(b.bound(), 3);
  EXPECT_TRUE(b.above());
}

TEST(StaticBound, AtOrBelowTheBoundIsStatic) {
  // Row 3 (1 - 2) made sticking: Nc = 3 = B, which a static packing may reach.
  Contacts c = bound_contacts();
  c.ft[3] = 0.1;
  StaticBound b = static_bound(c, bound_species, Friction{0.5, 0.3}, 0.0);
  EXPECT_EQ(b.critical, 3);
  EXPECT_EQ(b.bound(), 3);
  EXPECT_FALSE(b.above());
  // and row 1 too: Nc = 2 < B
  c.ft[1] = 0.1;
  b = static_bound(c, bound_species, Friction{0.5, 0.3}, 0.0);
  EXPECT_EQ(b.critical, 2);
  EXPECT_FALSE(b.above());
}

TEST(StaticBound, RattlersAreRemovedRepeatedly) {
  // A chain hanging off a load-bearing triangle: 0-1-2 a triangle, 2-3, 3-4, 4-5. Grain 5
  // has one contact; once it goes 4 has one, then 3: all three are rattlers. N = 3, M = 3
  // (the triangle), B = 6 - 9 = -3: even with no critical contact, a triangle of free
  // grains touching nothing else cannot be static (it has no support), so Nc = 0 > -3.
  using S = ContactStatus;
  Contacts c = make({{0, 1, 1.0, 0.0, S::stick},
                     {1, 2, 1.0, 0.0, S::stick},
                     {0, 2, 1.0, 0.0, S::stick},
                     {2, 3, 1.0, 0.5, S::slide},
                     {3, 4, 1.0, 0.5, S::slide},
                     {4, 5, 1.0, 0.5, S::slide}});
  StaticBound b = static_bound(c, {}, Friction{}, default_eps);
  EXPECT_EQ(b.grains, 3);
  EXPECT_EQ(b.contacts, 3);
  EXPECT_EQ(b.critical, 0);  // the critical contacts were all on the chain
  EXPECT_EQ(b.bound(), -3);
  EXPECT_TRUE(b.above());
  // A chain between two walls is load-bearing all along: wall-0-1-2-wall, N = 3, M = 4, B = -1.
  Contacts chain = make({{0, wall_left, 1.0, 0.0, S::stick},
                         {0, 1, 1.0, 0.0, S::stick},
                         {1, 2, 1.0, 0.0, S::stick},
                         {2, wall_right, 1.0, 0.0, S::stick}});
  b = static_bound(chain, {}, Friction{}, default_eps);
  EXPECT_EQ(b.grains, 3);
  EXPECT_EQ(b.contacts, 4);
  EXPECT_EQ(b.bound(), -1);
}

TEST(StaticBound, DiskInACorner) {
  // One disk on the floor against the left wall: N = 1, M = 2, B = 1. Gravity and the two
  // reactions (4 unknowns, 3 equations): one contact may slide, not both.
  using S = ContactStatus;
  Contacts c = make({{0, wall_floor, 2.0, 1.0, S::slide}, {0, wall_left, 1.0, 0.2, S::stick}});
  StaticBound b = static_bound(c, {}, Friction{0.5, 0.5}, default_eps);
  EXPECT_EQ(b.contacts, 2);
  EXPECT_EQ(b.grains, 1);
  EXPECT_EQ(b.critical, 1);
  EXPECT_EQ(b.bound(), 1);
  EXPECT_FALSE(b.above());
  c.ft[1] = 0.5;  // both on the cone
  b = static_bound(c, {}, Friction{0.5, 0.5}, default_eps);
  EXPECT_EQ(b.critical, 2);
  EXPECT_TRUE(b.above());
}

TEST(StaticBound, EmptyAndBadInput) {
  const StaticBound b = static_bound(Contacts{}, {}, Friction{}, default_eps);
  EXPECT_EQ(b.contacts, 0);
  EXPECT_EQ(b.grains, 0);
  EXPECT_EQ(b.bound(), 0);
  EXPECT_FALSE(b.above());
  Contacts c = make({{0, 1, 1.0, 0.5, ContactStatus::stick}});
  EXPECT_THROW(static_bound(c, {}, Friction{0.0, 0.5}, default_eps), Error);
  EXPECT_THROW(static_bound(c, {}, Friction{}, 1.0), Error);
  c.ft[0] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(static_bound(c, {}, Friction{}, default_eps), Error);
}

// Static and moving states (docs/analysis.md): how a frame's grains move, counted by hand.
TEST(FrameMotion, AgitationSpeedGrainsInFlightAndThePapersZ) {
  // Grains 0..5 free, 6 glued, with the contacts of the static-bound scene above: active
  // contacts per free grain 0: 3 (rows 0, 1, 5), 1: 3 (1, 2, 3), 2: 4 (3, 4, 5, 6),
  // 3: 1 (6), 4: 1 (8), 5: 2 (8, 9): 14 over 6 free grains, rattlers included.
  Grains g;
  for (int k = 0; k < 7; ++k)
    g.add_disk(0.5, 1.0, Vec2(k, 0.5), bound_species[static_cast<std::size_t>(k)]);
  g.mass.assign(7, 2.0);
  g.inertia.assign(7, 0.25);
  g.velocity.assign(7, Vec2(0, 0));
  g.angular_velocity.assign(7, 0.0);
  g.velocity[1] = Vec2(3, 4);    // |v| = 5, Ek = 25
  g.angular_velocity[2] = 2.0;   // Erot = 0.5 0.25 4 = 0.5
  g.velocity[6] = Vec2(100, 0);  // glued: not counted
  const FrameMotion m = frame_motion(g, bound_contacts());
  EXPECT_EQ(m.grains_without_contact, 0);
  ASSERT_TRUE(m.agitation && m.max_speed && m.contacts_per_grain);
  EXPECT_DOUBLE_EQ(*m.agitation, 25.5 / 6.0);
  EXPECT_DOUBLE_EQ(*m.max_speed, 5.0);
  EXPECT_DOUBLE_EQ(*m.contacts_per_grain, 14.0 / 6.0);
  // Grain 3 loses its only active contact (row 6 opens): it is in flight.
  Contacts c = bound_contacts();
  c.fn[6] = 0.0;
  EXPECT_EQ(frame_motion(g, c).grains_without_contact, 1);
  EXPECT_DOUBLE_EQ(*frame_motion(g, c).contacts_per_grain,
                   12.0 / 6.0);  // grains 2 and 3 lose one each
  g.velocity.clear();
  EXPECT_FALSE(frame_motion(g, c).agitation);
}

// Slip is kinematics: u_t = ((v_i + w_i x r_i) - (v_j + w_j x r_j)) . t at the contact point.
TEST(FrameMotion, SlipSpeedOfTwoDisksAndAWall) {
  Grains g;
  g.add_disk(0.5, 1.0, Vec2(0.0, 0.5));
  g.add_disk(0.5, 1.0, Vec2(1.0, 0.5));
  g.velocity = {Vec2(0.0, 2.0), Vec2(0.0, -1.0)};
  g.angular_velocity = {4.0, 0.0};
  Contacts c;
  // 0-1 touching at (0.5, 0.5), normal from 1 to 0 = (-1, 0), tangent (0, -1):
  // v_0 at the point = (0, 2) + 4 (-(0), 0.5) = (0, 4); v_1 = (0, -1): u = (0, 5), |u_t| = 5.
  c.push_back(0, 1, Vec2(0.5, 0.5), Vec2(-1.0, 0.0), 1.0, 0.5, 0.0, ContactStatus::slide);
  // 0 on the floor at (0, 0), normal (0, 1): v_0 there = (0, 2) + 4 (0.5, 0) = (2, 2), u_t = 2.
  c.push_back(0, wall_floor, Vec2(0.0, 0.0), Vec2(0.0, 1.0), 1.0, 0.1, 0.0, ContactStatus::stick);
  const ContactSet set =
      select_contacts(c, {}, Friction{}, CriticalRule{.eps = 1e-3, .include_walls = true});
  ASSERT_EQ(set.size(), 2u);
  const std::vector<double> u = slip_speeds(c, set, g);
  EXPECT_DOUBLE_EQ(u[0], 5.0);
  EXPECT_DOUBLE_EQ(u[1], 2.0);
}

TEST(FrameMotion, MobilisationHistogramBinsByHand) {
  using S = ContactStatus;
  // mu = 0.5: mobilisations 0, 0.2, 0.5, 0.999, 1 (on the cone) over 4 bins of 0.25
  const Contacts c = make({{0, 1, 1.0, 0.0, S::stick},
                           {0, 2, 1.0, 0.1, S::stick},
                           {1, 2, 1.0, -0.25, S::stick},
                           {1, 3, 1.0, 0.4995, S::stick},
                           {2, 3, 1.0, 0.5, S::slide},
                           {3, 4, 0.0, 0.0, S::open}});
  const ContactSet set = select_contacts(c, {}, Friction{}, CriticalRule{});
  const std::vector<std::int64_t> h = mobilisation_histogram(set, 4);
  EXPECT_EQ(h, (std::vector<std::int64_t>{2, 0, 1, 2}));
}

// A contact at rest has neither bodies in motion nor slip: two grains each slower than the
// rest speed can still slide on each other at up to twice that speed, which is motion.
TEST(FrameMotion, ContactsAtRestNeitherMoveNorSlip) {
  using S = ContactStatus;
  Grains g;
  g.add_disk(0.5, 1.0, Vec2(0.0, 0.5));
  g.add_disk(0.5, 1.0, Vec2(1.0, 0.5));
  g.add_disk(0.5, 1.0, Vec2(2.0, 0.5));
  g.add_disk(0.5, 1.0, Vec2(3.0, 0.5));
  // rest speed 0.01: grains 0 and 1 slow but sliding past each other (0.008 up, 0.008
  // down: |u_t| = 0.016); grain 2 slow and moving down with 1 (no slip); grain 3 fast.
  g.velocity = {Vec2(0.0, 0.008), Vec2(0.0, -0.008), Vec2(0.0, -0.008), Vec2(0.0, 0.5)};
  g.angular_velocity = {0.0, 0.0, 0.0, 0.0};
  Contacts c;
  // mu = 0.5; contacts 0-1 and 1-2 critical (|f_t| = mu f_n), 2-3 critical, 0-floor not
  c.push_back(0, 1, Vec2(0.5, 0.5), Vec2(-1.0, 0.0), 1.0, 0.5, 0.0, S::slide);
  c.push_back(1, 2, Vec2(1.5, 0.5), Vec2(-1.0, 0.0), 1.0, 0.5, 0.0, S::slide);
  c.push_back(2, 3, Vec2(2.5, 0.5), Vec2(-1.0, 0.0), 1.0, 0.5, 0.0, S::slide);
  c.push_back(0, wall_floor, Vec2(0.0, 0.0), Vec2(0.0, 1.0), 1.0, 0.1, 0.0, S::stick);
  const ContactSet set =
      select_contacts(c, {}, Friction{}, CriticalRule{.eps = 1e-3, .include_walls = true});
  ASSERT_EQ(set.size(), 4u);
  const std::vector<double> u = slip_speeds(c, set, g);
  EXPECT_DOUBLE_EQ(u[0], 0.016);  // 0-1: both slow, sliding
  EXPECT_DOUBLE_EQ(u[1], 0.0);    // 1-2: both slow, moving together
  // 0-1 slips, 2-3 has a fast body: at rest are 1-2 (critical) and 0-floor (not critical)
  const RestCount n = contacts_at_rest(c, set, g, u, 0.01, 1e-4);
  EXPECT_EQ(n.contacts, 2);
  EXPECT_EQ(n.critical, 1);
  // with a slip threshold above 0.016 the sliding pair counts as at rest
  const RestCount loose = contacts_at_rest(c, set, g, u, 0.01, 0.02);
  EXPECT_EQ(loose.contacts, 3);
  EXPECT_EQ(loose.critical, 2);
  EXPECT_THROW(contacts_at_rest(c, set, g, {}, 0.01, 1e-4), Error);
}
