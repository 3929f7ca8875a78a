// The /checkpoint group of a partial run (io/checkpoint.hpp): what is written is read back
// to the bit, a rewrite replaces the group, and a file without one is refused by name.
#include "cdpile/error.hpp"
#include "cdpile/io/checkpoint.hpp"

#include <gtest/gtest.h>

#include <limits>

using namespace cdpile;

namespace {

io::Checkpoint sample() {
  io::Checkpoint c;
  c.grains.add_disk(0.5e-3, 2600.0, Vec2(1e-3, 2e-3));
  c.grains.add_disk(0.6e-3, 2600.0, Vec2(3e-3, 2e-3));
  c.grains.velocity = {Vec2(0.1, -0.2), Vec2(1.0 / 3.0, 0.0)};
  c.grains.orientation = {0.25, -1.0 / 7.0};
  c.grains.angular_velocity = {2.0, 0.0};
  c.impulses = {{0, 1, 1.0 / 3.0, -1e-9}, {-1, 1, 2.5e-7, 0.0}};
  c.step = 41;
  c.time = 41 * 1e-4;
  c.counters = {{"since", std::int64_t{-1}}, {"since_deg", 0.1 + 0.2}, {"label", std::string("x")}};
  c.description = "test";
  return c;
}

}  // namespace

TEST(Checkpoint, RoundTripsToTheBit) {
  io::h5::File f = io::h5::create_in_memory("mem.h5");
  const io::Checkpoint c = sample();
  io::write_checkpoint(f, c);
  Grains properties = c.grains;  // the run's grains: their state is the checkpoint's
  for (auto& x : properties.position) x = Vec2(0, 0);
  const io::Checkpoint r = io::read_checkpoint(f, properties);
  ASSERT_EQ(r.grains.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(r.grains.position[k], c.grains.position[k]);
    EXPECT_EQ(r.grains.velocity[k], c.grains.velocity[k]);
    EXPECT_EQ(r.grains.orientation[k], c.grains.orientation[k]);
    EXPECT_EQ(r.grains.angular_velocity[k], c.grains.angular_velocity[k]);
    EXPECT_EQ(r.grains.radius[k], c.grains.radius[k]);
  }
  ASSERT_EQ(r.impulses.size(), 2u);
  EXPECT_EQ(r.impulses[0].rn, 1.0 / 3.0);
  EXPECT_EQ(r.impulses[1].i, -1);
  EXPECT_EQ(r.step, 41);
  EXPECT_EQ(r.time, 41 * 1e-4);
  EXPECT_EQ(r.counter_int("since", "mem.h5"), -1);
  EXPECT_EQ(r.counter_real("since_deg", "mem.h5"), 0.1 + 0.2);
  EXPECT_THROW(r.counter_int("since_deg", "mem.h5"), Error);  // a real is not an integer
  EXPECT_THROW(r.counter_real("absent", "mem.h5"), Error);
}

TEST(Checkpoint, ARewriteReplacesTheGroup) {
  io::h5::File f = io::h5::create_in_memory("mem.h5");
  io::Checkpoint c = sample();
  io::write_checkpoint(f, c);
  c.step = 42;
  c.impulses.pop_back();
  io::write_checkpoint(f, c);
  const io::Checkpoint r = io::read_checkpoint(f, c.grains);
  EXPECT_EQ(r.step, 42);
  EXPECT_EQ(r.impulses.size(), 1u);
}

TEST(Checkpoint, AFileWithoutOneIsNotAPartialRun) {
  io::h5::File f = io::h5::create_in_memory("mem.h5");
  try {
    io::read_checkpoint(f, sample().grains);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "mem.h5: /checkpoint: missing: not a partial run");
  }
}

// docs/schema.md, "Ranges": the step and time as a frame's, the counters within 2^53, the
// sub-step level (a shift count) within [0, 30].
TEST(Checkpoint, ValuesOutsideTheirRangeAreRefused) {
  auto message = [](io::Checkpoint c) {
    io::h5::File f = io::h5::create_in_memory("mem.h5");
    io::write_checkpoint(f, c);
    try {
      io::read_checkpoint(f, c.grains);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  io::Checkpoint c = sample();
  c.step = -1;
  EXPECT_EQ(message(c), "mem.h5: /checkpoint: attribute 'step': -1 is outside [0, 2^53]");
  c = sample();
  c.time = -1e-300;
  EXPECT_EQ(message(c), "mem.h5: /checkpoint: attribute 'time': -1e-300 s is outside [0, inf) s");
  c = sample();
  c.counters.emplace_back("substep_level", std::int64_t{1} << 32);
  EXPECT_EQ(message(c),
            "mem.h5: /checkpoint: attribute 'substep_level': 4294967296 is outside [0, 30]");
  c = sample();
  c.counters.emplace_back("unconverged_steps", std::numeric_limits<std::int64_t>::min());
  EXPECT_EQ(message(c),
            "mem.h5: /checkpoint: attribute 'unconverged_steps': -9223372036854775808 is outside "
            "[-2^53, 2^53]");
}
