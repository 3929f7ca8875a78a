// Local states nu_i(r), nu_bar (eq 3), the pdfs P_c and P_nc and the nu field, on contact
// sets small enough to count by hand, and against brute force on a random set.
#include "cdpile/analysis/local_state.hpp"
#include "cdpile/error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace cdpile;
using namespace cdpile::analysis;

namespace {
// Five contact points on a line, 1 apart; contacts 0 and 3 are critical.
struct Line {
  std::vector<Vec2> p = {Vec2(0, 0), Vec2(1, 0), Vec2(2, 0), Vec2(3, 0), Vec2(4, 0)};
  std::vector<std::uint8_t> c = {1, 0, 0, 1, 0};
  std::vector<double> r = {0.5, 1.0, 2.5};
};
}  // namespace

TEST(LocalState, ByHandOnALine) {
  Line l;
  LocalStates s = local_states(l.p, l.c, l.r);
  ASSERT_EQ(s.centres(), 5u);
  // contact 0: {0} -> 1/1; {0,1} -> 1/2 (distance exactly r counts); {0,1,2} -> 1/3
  EXPECT_DOUBLE_EQ(*s.nu(0, 0), 1.0);
  EXPECT_DOUBLE_EQ(*s.nu(0, 1), 0.5);
  EXPECT_DOUBLE_EQ(*s.nu(0, 2), 1.0 / 3.0);
  EXPECT_EQ(s.total(0, 2), 3);
  // contact 3: {3}; {2,3,4} -> 1/3; {1,2,3,4} -> 1/4
  EXPECT_DOUBLE_EQ(*s.nu(3, 0), 1.0);
  EXPECT_DOUBLE_EQ(*s.nu(3, 1), 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(*s.nu(3, 2), 0.25);
  // contact 2: {2} -> 0; {1,2,3} -> 1/3; {0,...,4} -> 2/5
  EXPECT_DOUBLE_EQ(*s.nu(2, 0), 0.0);
  EXPECT_DOUBLE_EQ(*s.nu(2, 1), 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(*s.nu(2, 2), 0.4);
}

TEST(LocalState, ExcludeSelf) {
  Line l;
  LocalStateOptions o;
  o.exclude_self = true;
  LocalStates s = local_states(l.p, l.c, l.r, o);
  EXPECT_FALSE(s.nu(0, 0));  // empty neighbourhood: no value, not NaN
  EXPECT_DOUBLE_EQ(*s.nu(0, 1), 0.0);
  EXPECT_DOUBLE_EQ(*s.nu(0, 2), 0.0);
  EXPECT_DOUBLE_EQ(*s.nu(2, 2), 0.5);  // {0,1,3,4}: 2/4
}

TEST(LocalState, MeanStateOverCriticalContactsEq3) {
  Line l;
  LocalStates s = local_states(l.p, l.c, l.r);
  auto sums = state_sums(s, l.c, 1);
  ASSERT_EQ(sums.size(), 3u);
  EXPECT_EQ(sums[1].n, 2);
  EXPECT_DOUBLE_EQ(*sums[0].summary().mean, 1.0);
  EXPECT_DOUBLE_EQ(*sums[1].summary().mean, (0.5 + 1.0 / 3.0) / 2.0);
  EXPECT_DOUBLE_EQ(*sums[2].summary().mean, (1.0 / 3.0 + 0.25) / 2.0);
  auto nc = state_sums(s, l.c, 0);
  EXPECT_EQ(nc[1].n, 3);  // contacts 1, 2, 4: 1/3, 1/3, 1/2
  EXPECT_DOUBLE_EQ(*nc[1].summary().mean, (1.0 / 3.0 + 1.0 / 3.0 + 0.5) / 3.0);
}

TEST(LocalState, PdfsAtOneRadius) {
  Line l;
  LocalStates s = local_states(l.p, l.c, l.r);
  Histogram pc(0, 1, 4), pnc(0, 1, 4);
  add_to_pdfs(s, l.c, 1, pc, pnc);
  // critical: 1/2, 1/3 -> bins 2, 1; non-critical: 1/3, 1/3, 1/2 -> bins 1, 1, 2
  EXPECT_EQ(pc.count, (std::vector<std::int64_t>{0, 1, 1, 0}));
  EXPECT_EQ(pnc.count, (std::vector<std::int64_t>{0, 2, 1, 0}));
  EXPECT_DOUBLE_EQ(pc.density(1), 1.0 / (2 * 0.25));
  EXPECT_DOUBLE_EQ(pnc.density(1), 2.0 / (3 * 0.25));
  Histogram h(0, 1, 4);
  h.add(1.0);  // the upper end falls in the last bin
  EXPECT_EQ(h.count[3], 1);
  EXPECT_DOUBLE_EQ(Histogram(0, 1, 4).density(0), 0.0);  // empty: 0, not NaN
}

TEST(LocalState, MatchesBruteForceOnRandomContacts) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> ux(0.0, 60.0), uy(0.0, 15.0), u(0.0, 1.0);
  const std::size_t n = 1500;
  std::vector<Vec2> p(n);
  std::vector<std::uint8_t> c(n);
  for (std::size_t k = 0; k < n; ++k) {
    p[k] = Vec2(ux(rng), uy(rng));
    c[k] = u(rng) < 0.1 ? 1 : 0;
  }
  p[7] = p[3];  // a duplicate point
  std::vector<double> r;
  for (int k = 1; k <= 20; ++k) r.push_back(k * 0.7);
  for (bool excl : {false, true}) {
    LocalStateOptions o;
    o.exclude_self = excl;
    LocalStates s = local_states(p, c, r, o);
    for (std::size_t i = 0; i < n; i += 37) {
      for (std::size_t k = 0; k < r.size(); ++k) {
        int tot = 0, cr = 0;
        for (std::size_t j = 0; j < n; ++j) {
          if (excl && j == i) continue;
          if ((p[j] - p[i]).squaredNorm() <= r[k] * r[k]) {
            ++tot;
            cr += c[j];
          }
        }
        ASSERT_EQ(s.total(i, k), tot) << "centre " << i << " radius " << k;
        ASSERT_EQ(s.critical(i, k), cr);
      }
    }
  }
}

TEST(LocalState, EdgeRuleExcludesNeighbourhoodsCrossingTheOutline) {
  // a 21 x 11 lattice of contacts, spacing 1: outline [0,20] x [0,10]
  std::vector<Vec2> p;
  for (int y = 0; y <= 10; ++y)
    for (int x = 0; x <= 20; ++x) p.emplace_back(x, y);
  std::vector<std::uint8_t> c(p.size(), 0);
  PileOutline out(p, 1.0);
  EXPECT_DOUBLE_EQ(out.distance(Vec2(10, 5)), 5.0);
  EXPECT_DOUBLE_EQ(out.distance(Vec2(2, 5)), 2.0);
  EXPECT_DOUBLE_EQ(out.distance(Vec2(10, 9)), 1.0);
  LocalStateOptions o;
  o.edge = EdgeRule::exclude;
  o.outline_bin = 1.0;
  std::vector<double> r = {1.0, 3.0, 6.0};
  LocalStates s = local_states(p, c, r, o);
  const std::size_t centre = 5 * 21 + 10;  // (10, 5): distance 5
  EXPECT_TRUE(s.nu(centre, 1));
  EXPECT_FALSE(s.nu(centre, 2));
  EXPECT_FALSE(s.nu(0, 0));  // a corner
}

TEST(LocalState, FieldOnAGrid) {
  Line l;
  Field f = nu_field(l.p, l.c, 1.0, 2.0);
  ASSERT_EQ(f.nx, 3u);
  ASSERT_EQ(f.ny, 1u);
  EXPECT_DOUBLE_EQ(*f.nu(0, 0), 0.5);        // node (0,0): {0,1}
  EXPECT_DOUBLE_EQ(*f.nu(1, 0), 1.0 / 3.0);  // node (2,0): {1,2,3}
  EXPECT_DOUBLE_EQ(*f.nu(2, 0), 0.5);        // node (4,0): {3,4}
  Field f2 = nu_field(l.p, l.c, 0.4, 0.5);
  EXPECT_FALSE(f2.nu(1, 0));  // node (0.5, 0): nothing within 0.4
}

TEST(LocalState, EmptyFrameAndBadRadii) {
  std::vector<Vec2> none;
  std::vector<std::uint8_t> nc;
  std::vector<double> r = {1.0, 2.0};
  LocalStates s = local_states(none, nc, r);
  EXPECT_EQ(s.centres(), 0u);
  Field f = nu_field(none, nc, 1.0, 1.0);
  EXPECT_EQ(f.nx * f.ny, 0u);
  Line l;
  EXPECT_THROW(local_states(l.p, l.c, std::vector<double>{2.0, 1.0}), Error);
  EXPECT_THROW(local_states(l.p, l.c, std::vector<double>{0.0, 1.0}), Error);
  EXPECT_THROW(local_states(l.p, l.c, std::vector<double>{}), Error);
  EXPECT_THROW(local_states(l.p, std::vector<std::uint8_t>{1}, r), Error);
}
