// The per-frame analyses behind to-xdmf's fields (frame_fields) and critical's frame table
// (frame_record), on a frame built by hand: three grains in a row on the floor.
#include "cdpile/analysis/frame_fields.hpp"
#include "cdpile/analysis/studies.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

using namespace cdpile;
using namespace cdpile::analysis;

namespace {
// Grains 0, 1, 2 of diameter 1 m at x = 0.5, 1.5, 2.5, at rest on the floor. Contacts:
//   0: (0, 1) at x = 1, f_n = 2, f_t = 1, sliding: on the cone of mu_grain = 0.5, critical
//   1: (1, 2) at x = 2, f_n = 2, f_t = 0.5: mobilisation 0.5
//   2: (0, floor), f_n = 1, f_t = 0: mobilisation 0
//   3: (2, floor), f_n = 4, f_t = 1: on the cone of mu_wall = 0.25, critical
Frame frame() {
  Frame f;
  for (int k = 0; k < 3; ++k) f.grains.add_disk(0.5, 1.0, Vec2(k + 0.5, 0.5));
  const Vec2 left(-1, 0), up(0, 1);
  f.contacts.push_back(0, 1, Vec2(1, 0.5), left, 2.0, 1.0, 0.0, ContactStatus::slide);
  f.contacts.push_back(1, 2, Vec2(2, 0.5), left, 2.0, 0.5, 0.0, ContactStatus::stick);
  f.contacts.push_back(0, wall_floor, Vec2(0.5, 0), up, 1.0, 0.0, 0.0, ContactStatus::stick);
  f.contacts.push_back(2, wall_floor, Vec2(2.5, 0), up, 4.0, 1.0, 0.0, ContactStatus::stick);
  return f;
}
const Friction mu{0.5, 0.25};
}  // namespace

TEST(FrameFields, ByHand) {
  const Frame fr = frame();
  const FrameFields f = frame_fields(fr.contacts, fr.grains, mu, CriticalRule{}, 0.6);
  EXPECT_EQ(f.critical, (std::vector<std::uint8_t>{1, 0, 0, 1}));
  EXPECT_EQ(f.mobilisation, (std::vector<double>{1.0, 0.5, 0.0, 1.0}));
  // <f_n> = 9 / 4 over the four active contacts
  EXPECT_EQ(f.fn_rel, (std::vector<double>{2 / 2.25, 2 / 2.25, 1 / 2.25, 4 / 2.25}));
  // nu within 0.6 m of each centre, over the two grain-grain contacts (walls left out):
  // grain 0 sees contact 0 (critical), grain 1 both, grain 2 contact 1
  EXPECT_EQ(f.nu, (std::vector<double>{1.0, 0.5, 0.0}));
  // with the walls counted, grain 0 sees its floor contact too (0.5 m away)
  CriticalRule walls;
  walls.include_walls = true;
  EXPECT_EQ(frame_fields(fr.contacts, fr.grains, mu, walls, 0.6).nu,
            (std::vector<double>{0.5, 0.5, 0.5}));
}

TEST(FrameFields, NoActiveContactAndNoContactInReach) {
  Frame fr = frame();
  for (double& fn : fr.contacts.fn) fn = 0.0;
  for (double& ft : fr.contacts.ft) ft = 0.0;
  const FrameFields f = frame_fields(fr.contacts, fr.grains, mu, CriticalRule{}, 0.6);
  EXPECT_EQ(f.critical, (std::vector<std::uint8_t>{0, 0, 0, 0}));
  for (double m : f.mobilisation) EXPECT_TRUE(std::isnan(m));
  EXPECT_EQ(f.fn_rel, (std::vector<double>{0, 0, 0, 0}));
  for (double v : f.nu) EXPECT_TRUE(std::isnan(v));
}

// to-xdmf's colour ranges over frames: nu up to its largest value (NaN, no contact in
// reach, left out), f_n / <f_n> up to the 99th percentile of all the frames' rows.
TEST(FrameFields, ColourRangesOverFrames) {
  ColourRanges none;
  EXPECT_EQ(none.nu_max(), 0.0);
  EXPECT_EQ(none.fn_rel_high(), 0.0);
  ColourRanges r;
  FrameFields a, b;
  a.nu = {0.25, std::nan(""), 0.5};
  b.nu = {0.125};
  for (int k = 1; k <= 100; ++k) (k % 2 ? a : b).fn_rel.push_back(k);  // 1..100, split
  r.add(a);
  r.add(b);
  EXPECT_EQ(r.nu_max(), 0.5);
  EXPECT_EQ(r.fn_rel_high(), 99.0);  // the element at 0.99 (n - 1), rounded down
}

namespace {
// frame_record of frame() in a run of 3 free grains of D = 1 m under gravity `g` [m/s^2]
// (0: unknown), with the default rule; grain 0 moving up at `speed` [m/s] (at g = 9.81 the
// slip speed 1e-4 sqrt(g D) is 3.1e-4 m/s); with `per_contact`, each contact's state kept.
FrameRecord record(double g, bool per_contact = false, double speed = 0.0) {
  Frame fr = frame();
  fr.grains.velocity[0] = Vec2(0.0, speed);
  RunRecord run;
  run.free_grains = 3;
  run.diameter = 1.0;
  run.gravity = g;
  run.mu = mu;
  const ContactSet set = select_contacts(fr.contacts, fr.grains.species, mu, CriticalRule{});
  return frame_record(fr.contacts, fr.grains, set, run, default_eps, RattlerRule::exclude,
                      default_slip_speed, RestRule{}.speed, per_contact);
}
}  // namespace

TEST(FrameRecord, ByHand) {
  const FrameRecord f = record(9.81);
  // the two grain-grain contacts count; contact 0 is critical and sliding
  EXPECT_EQ(f.state.contacts, 2);
  EXPECT_EQ(f.state.critical, 1);
  EXPECT_EQ(f.state.sliding, 1);
  EXPECT_EQ(f.state.loaded_grains, 1);
  EXPECT_EQ(f.state.nu, 0.5);
  // at rest: no energy, nothing slips, both counted contacts at rest
  EXPECT_EQ(f.kinetic_energy, 0.0);
  EXPECT_EQ(f.agitation, 0.0);
  EXPECT_EQ(f.max_speed, 0.0);
  EXPECT_EQ(f.grains_without_contact, 0);
  EXPECT_EQ(f.z_paper, 2.0);  // 2 active contacts each, walls included
  EXPECT_EQ(f.slipping, 0);
  EXPECT_EQ(f.critical_slipping, 0);
  EXPECT_EQ(f.contacts_at_rest, 2);
  EXPECT_EQ(f.critical_at_rest, 1);
  // mobilisation 1 in the last of the 20 bins, 0.5 in bin 10
  std::vector<std::int64_t> bins(mobilisation_bins, 0);
  bins[10] = 1;
  bins[19] = 1;
  EXPECT_EQ(f.mobilisation, bins);
  // every grain bears load (two active contacts each): M = 4, N = 3, B = -1 < Nc = 2
  ASSERT_TRUE(f.bound);
  EXPECT_EQ(f.bound->contacts, 4);
  EXPECT_EQ(f.bound->grains, 3);
  EXPECT_EQ(f.bound->critical, 2);
  EXPECT_EQ(f.bound->bound(), -1);
  EXPECT_TRUE(f.bound->above());
}

TEST(FrameRecord, WithoutGravityNothingIsCountedAsSlippingOrAtRest) {
  const FrameRecord f = record(0.0);
  EXPECT_FALSE(f.slipping);
  EXPECT_FALSE(f.contacts_at_rest);
  EXPECT_EQ(f.state.critical, 1);
}

// critical --contacts: each counted contact's flags are those the frame's counts add up.
TEST(FrameRecord, PerContactStatesAddUpToTheCounts) {
  EXPECT_FALSE(record(9.81).contacts);  // kept only when asked
  const FrameRecord f = record(9.81, true, 1.0);
  ASSERT_TRUE(f.contacts);
  const FrameContacts& c = *f.contacts;
  // the two grain-grain contacts, in the frame's order
  EXPECT_EQ(c.i, (std::vector<std::int32_t>{0, 1}));
  EXPECT_EQ(c.j, (std::vector<std::int32_t>{1, 2}));
  EXPECT_EQ(c.critical, (std::vector<std::uint8_t>{1, 0}));
  EXPECT_EQ(c.sliding, (std::vector<std::uint8_t>{1, 0}));
  // grain 0 moves across contact 0's normal (along x): it slips; contact 1 does not
  EXPECT_EQ(c.slip, (std::vector<std::uint8_t>{1, 0}));
  EXPECT_EQ(f.slipping, 1);
  EXPECT_EQ(f.critical_slipping, 1);
  // without g nothing is known to slip: no flags, as no count
  const FrameRecord unknown = record(0.0, true, 1.0);
  ASSERT_TRUE(unknown.contacts);
  EXPECT_FALSE(unknown.contacts->slip);
  EXPECT_FALSE(unknown.slipping);
}

TEST(CriticalContacts, OneRowPerCountedContactOfEveryFrame) {
  RunRecord a, b;
  FrameRecord f = record(9.81, true, 1.0);
  f.frame = 3;
  f.theta = 12.5;
  a.frames = {f};
  f.contacts->sliding.reset();  // a contact table without a status column
  f.contacts->slip.reset();
  b.frames = {f, f};
  const Product p = critical_contacts({a, b}, CriticalOptions{});
  EXPECT_EQ(p.kind, "critical_contacts");
  const Table& t = p.table("contacts");
  ASSERT_EQ(t.column("run").num.size(), 6u);  // 2 contacts in each of the 3 frames
  EXPECT_EQ(t.column("run").num, (std::vector<double>{0, 0, 1, 1, 1, 1}));
  EXPECT_EQ(t.column("frame").num, (std::vector<double>{3, 3, 3, 3, 3, 3}));
  EXPECT_EQ(t.column("theta").num[0], 12.5);
  EXPECT_EQ(t.column("i").num, (std::vector<double>{0, 1, 0, 1, 0, 1}));
  EXPECT_EQ(t.column("j").num, (std::vector<double>{1, 2, 1, 2, 1, 2}));
  EXPECT_EQ(t.column("critical").num, (std::vector<double>{1, 0, 1, 0, 1, 0}));
  EXPECT_EQ(t.column("slip").num[0], 1.0);
  EXPECT_EQ(t.column("slip").num[1], 0.0);
  // NA where the frame says nothing
  EXPECT_TRUE(std::isnan(t.column("sliding").num[2]));
  EXPECT_TRUE(std::isnan(t.column("slip").num[5]));
  EXPECT_EQ(p.parameters.at("eps"), Value(default_eps));
  // a frame read without its contacts is the caller's bug
  RunRecord without;
  without.frames = {record(9.81)};
  EXPECT_THROW(critical_contacts({without}, CriticalOptions{}), std::logic_error);
}
