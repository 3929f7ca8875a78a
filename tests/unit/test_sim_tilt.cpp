// The tilt protocol: the avalanche rule on a small pile, and checkpoints: a run killed
// at any step and resumed, or stopped by Ctrl-C and resumed, equals an uninterrupted run
// in every dataset, bit for bit.
#include "cdpile/error.hpp"
#include "cdpile/io/checkpoint.hpp"
#include "cdpile/io/files.hpp"
#include "cdpile/sim/common.hpp"
#include "cdpile/sim/deposit.hpp"
#include "cdpile/sim/overlap.hpp"
#include "cdpile/sim/tilt.hpp"

#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <cstring>
#include <filesystem>

namespace sim = cdpile::sim;
namespace io = cdpile::io;
namespace fs = std::filesystem;
using cdpile::ContactStatus;
using cdpile::Contacts;
using cdpile::Frame;
using cdpile::Vec2;

namespace {

/// A pile of 100 grains in a box 12 D wide, written as a file and read back as tilt-cd does.
const sim::PileInput& pile() {
  static const sim::PileInput p = [] {
    sim::DepositOptions o;
    o.grains = 100;
    o.width = 12.0;
    o.seed = 4;
    const sim::Pile pl = sim::deposit(o);
    io::h5::File f = io::h5::create_in_memory("pile");
    sim::write_pile(f, pl, io::provenance_now("test", "", ""));
    return sim::read_pile(f);
  }();
  return p;
}

/// A scratch folder, removed at the end.
struct Scratch {
  fs::path dir;
  Scratch() {
    dir = fs::temp_directory_path() /
          ("cdpile-tilt-" + std::to_string(::getpid()) + "-" + std::to_string(counter()++));
    fs::create_directories(dir);
  }
  ~Scratch() { fs::remove_all(dir); }
  std::string operator/(const std::string& name) const { return (dir / name).string(); }
  static int& counter() {
    static int c = 0;
    return c;
  }
};

/// 0.002 degree per step to 0.3 degree: 150 steps, a frame every 20, a checkpoint every 25.
sim::TiltOptions short_run() {
  sim::TiltOptions o;
  o.rate_deg = 0.002;
  o.to_deg = 0.3;
  o.frame_every = 20;
  o.checkpoint_every = 25;
  return o;
}

struct Crash {};

/// Every dataset and attribute that matters, compared exactly.
void expect_same_run(const std::string& a_path, const std::string& b_path) {
  io::h5::File fa = io::h5::open_read(a_path, "a"), fb = io::h5::open_read(b_path, "b");
  io::RunReader a(fa), b(fb);
  EXPECT_FALSE(io::h5::exists(fb, "/checkpoint"));
  EXPECT_EQ(a.header().parameters, b.header().parameters);
  EXPECT_EQ(a.header().results, b.header().results);
  ASSERT_EQ(a.frame_count(), b.frame_count());
  EXPECT_EQ(a.frame_steps(), b.frame_steps());
  for (std::size_t k = 0; k < a.frame_count(); ++k) {
    const Frame x = a.frame(k), y = b.frame(k);
    const std::size_t n = x.grains.size();
    EXPECT_EQ(0, std::memcmp(x.grains.position.data(), y.grains.position.data(), n * sizeof(Vec2)))
        << k;
    EXPECT_EQ(0, std::memcmp(x.grains.velocity.data(), y.grains.velocity.data(), n * sizeof(Vec2)))
        << k;
    EXPECT_EQ(x.grains.orientation, y.grains.orientation);
    EXPECT_EQ(x.grains.angular_velocity, y.grains.angular_velocity);
    EXPECT_EQ(x.contacts.i, y.contacts.i);
    EXPECT_EQ(x.contacts.j, y.contacts.j);
    EXPECT_EQ(x.contacts.fn, y.contacts.fn);
    EXPECT_EQ(x.contacts.ft, y.contacts.ft);
    EXPECT_EQ(x.contacts.gap, y.contacts.gap);
    EXPECT_EQ(x.contacts.status, y.contacts.status);
  }
  const io::Series sa = a.series(), sb = b.series();
  EXPECT_EQ(sa.step, sb.step);
  EXPECT_EQ(sa.time, sb.time);
  EXPECT_EQ(sa.real, sb.real);
  EXPECT_EQ(sa.integer, sb.integer);
}

}  // namespace

TEST(Tilt, UninterruptedRunHasEveryStepAndFrame) {
  Scratch s;
  const auto out =
      sim::run_tilt(pile(), short_run(), s / "run.h5", false, io::provenance_now("test", "", ""));
  EXPECT_EQ(out.steps, 150);
  EXPECT_EQ(out.stop_reason, "to");
  EXPECT_FALSE(fs::exists(sim::partial_path(s / "run.h5")));
  io::h5::File f = io::h5::open_read(s / "run.h5", "run");
  io::RunReader r(f);
  EXPECT_EQ(r.header().kind, "run");
  EXPECT_EQ(r.frame_steps(), (std::vector<std::int64_t>{0, 20, 40, 60, 80, 100, 120, 140, 150}));
  const io::Series se = r.series();
  ASSERT_EQ(se.size(), 150u);
  for (std::size_t k = 0; k < se.size(); ++k) {
    EXPECT_EQ(se.step[k], static_cast<std::int64_t>(k + 1));
    EXPECT_NEAR(se.real.at("tilt_angle")[k], 0.002 * static_cast<double>(k + 1), 1e-12);
    // Critical contacts are among the active ones; grain-grain among all.
    EXPECT_LE(se.integer.at("critical")[k], se.integer.at("contacts")[k]);
    EXPECT_LE(se.integer.at("critical_grain")[k], se.integer.at("critical")[k]);
  }
  // At 0.3 degree the pile is static: the agitation stays far below the avalanche threshold.
  EXPECT_EQ(io::as_int(r.header().results, "avalanche_detected", "run"), 0);
  EXPECT_EQ(r.header().parameters.at("tilt_rate_deg_per_step"), io::Value(0.002));
}

// kill -9 at any moment: modelled by an exception thrown after step k, which skips every
// write since the last checkpoint, exactly as a killed process would.
TEST(Tilt, ResumeAfterACrashAtAnyStepIsBitForBit) {
  Scratch s;
  const auto prov = io::provenance_now("test", "", "");
  sim::run_tilt(pile(), short_run(), s / "ref.h5", false, prov);
  for (std::int64_t crash : {1, 24, 25, 26, 99, 149}) {
    const std::string out = s / ("run" + std::to_string(crash) + ".h5");
    sim::TiltHooks hooks;
    hooks.progress = [crash](const sim::TiltProgress& p) {
      if (p.step == crash) throw Crash{};
    };
    EXPECT_THROW(sim::run_tilt(pile(), short_run(), out, false, prov, hooks), Crash);
    EXPECT_FALSE(fs::exists(out));
    ASSERT_TRUE(fs::exists(sim::partial_path(out))) << crash;
    // Fresh start refused while the partial exists.
    EXPECT_THROW(sim::run_tilt(pile(), short_run(), out, false, prov), cdpile::Error);
    const auto o = sim::resume_tilt(short_run(), out, false);
    // From the last checkpoint before the crash (step k's checkpoint follows its progress call).
    EXPECT_EQ(o.first_step, ((crash - 1) / 25) * 25) << crash;
    EXPECT_EQ(o.steps, 150);
    EXPECT_FALSE(fs::exists(sim::partial_path(out)));
    expect_same_run(s / "ref.h5", out);
  }
}

// Ctrl-C: the stop hook makes a checkpoint of every completed step; the partial is a
// valid run up to that step; resuming finishes the same run.
TEST(Tilt, InterruptLeavesAValidRunAndResumes) {
  Scratch s;
  const auto prov = io::provenance_now("test", "", "");
  sim::run_tilt(pile(), short_run(), s / "ref.h5", false, prov);
  sim::TiltHooks hooks;
  std::int64_t step = 0;
  hooks.progress = [&](const sim::TiltProgress& p) { step = p.step; };
  hooks.stop = [&] { return step == 63; };
  const auto o = sim::run_tilt(pile(), short_run(), s / "run.h5", false, prov, hooks);
  EXPECT_TRUE(o.interrupted);
  EXPECT_EQ(o.steps, 63);
  {
    io::h5::File f = io::h5::open_read(sim::partial_path(s / "run.h5"), "partial");
    io::RunReader r(f);
    const io::Series se = r.series();
    ASSERT_EQ(se.size(), 63u);
    EXPECT_EQ(se.step.back(), 63);
    EXPECT_EQ(r.frame_steps(), (std::vector<std::int64_t>{0, 20, 40, 60}));
  }
  // Different options are refused, naming the parameter.
  auto other = short_run();
  other.rate_deg = 0.001;
  try {
    sim::resume_tilt(other, s / "run.h5", false);
    ADD_FAILURE() << "resumed with another rate";
  } catch (const cdpile::Error& e) {
    EXPECT_NE(std::string(e.what()).find("tilt_rate_deg_per_step"), std::string::npos) << e.what();
  }
  sim::resume_tilt(short_run(), s / "run.h5", false);
  expect_same_run(s / "ref.h5", s / "run.h5");
}

// The run's CPU is recorded in its provenance (the tilt's entry, last), and a resumed run
// adds the CPU its interrupted processes spent (kept in the checkpoint) to its own.
TEST(Tilt, CpuOfTheRunIsRecordedAndSummedOverResumes) {
  Scratch s;
  sim::run_tilt(pile(), short_run(), s / "ref.h5", false, io::provenance_now("test", "", ""));
  {
    io::h5::File f = io::h5::open_read(s / "ref.h5", "ref");
    const auto h = io::read_header(f);
    ASSERT_FALSE(h.provenance.empty());
    EXPECT_GT(h.provenance.back().cpu_s, 0.0);
    EXPECT_LE(h.provenance.back().cpu_s, io::process_cpu_s());
  }
  sim::TiltHooks hooks;
  std::int64_t step = 0;
  hooks.progress = [&](const sim::TiltProgress& p) { step = p.step; };
  hooks.stop = [&] { return step == 63; };
  sim::run_tilt(pile(), short_run(), s / "run.h5", false, io::provenance_now("test", "", ""),
                hooks);
  // As if the interrupted processes had spent 1000 s: the resumed run's record holds them.
  {
    io::h5::File f = io::h5::open_write(sim::partial_path(s / "run.h5"), "partial");
    ASSERT_TRUE(io::h5::has_attr(f, io::kCheckpointGroup, "cpu_s"));
    EXPECT_GT(io::h5::attr_double(f, io::kCheckpointGroup, "cpu_s"), 0.0);
    io::h5::set_attr(f, io::kCheckpointGroup, "cpu_s", 1000.0);
  }
  sim::resume_tilt(short_run(), s / "run.h5", false);
  io::h5::File f = io::h5::open_read(s / "run.h5", "run");
  const double cpu = io::read_header(f).provenance.back().cpu_s;
  EXPECT_GT(cpu, 1000.0);
  EXPECT_LE(cpu, 1000.0 + io::process_cpu_s());
  expect_same_run(s / "ref.h5", s / "run.h5");  // the record is provenance, not the run
}

// A signal while a step is being solved (a large pile at the sweep cap can take longer
// than a second): the solver polls stop() before every sweep, abandons the step, and the
// checkpoint is the last completed step's; resuming finishes the same run.
TEST(Tilt, StopInsideAStepCheckpointsTheLastCompletedStep) {
  Scratch s;
  const auto prov = io::provenance_now("test", "", "");
  sim::run_tilt(pile(), short_run(), s / "ref.h5", false, prov);
  sim::TiltHooks hooks;
  std::int64_t step = 0;
  int polls = 0;
  hooks.progress = [&](const sim::TiltProgress& p) { step = p.step; };
  hooks.stop = [&] {
    return step == 41 && ++polls == 2;
  };  // after step 41, then before a sweep of 42
  const auto o = sim::run_tilt(pile(), short_run(), s / "run.h5", false, prov, hooks);
  EXPECT_TRUE(o.interrupted);
  EXPECT_EQ(o.steps, 41);
  {
    io::h5::File f = io::h5::open_read(sim::partial_path(s / "run.h5"), "partial");
    io::RunReader r(f);
    EXPECT_EQ(r.series().step.back(), 41);
    EXPECT_EQ(io::h5::attr_int(f, "/checkpoint", "step"), 41);
  }
  sim::resume_tilt(short_run(), s / "run.h5", false);
  expect_same_run(s / "ref.h5", s / "run.h5");
}

// Signals are deferred while the run steps and saves, and no longer once OUTPUT.partial
// holds the whole run: then a stop leaves that partial, and a resume only writes the file.
TEST(Tilt, DeferralEndsWhenThePartialHoldsTheWholeRun) {
  Scratch s;
  const auto prov = io::provenance_now("test", "", "");
  sim::run_tilt(pile(), short_run(), s / "ref.h5", false, prov);
  sim::TiltHooks hooks;
  std::vector<bool> calls;
  std::int64_t checkpoint_at_end = -1;
  bool stopping = false;
  hooks.deferring = [&](bool on) {
    calls.push_back(on);
    if (on) return;
    io::h5::File f = io::h5::open_read(sim::partial_path(s / "run.h5"), "partial");
    checkpoint_at_end = io::h5::attr_int(f, "/checkpoint", "step");
    stopping = true;  // a signal that comes now
  };
  hooks.stop = [&] { return stopping; };
  const auto o = sim::run_tilt(pile(), short_run(), s / "run.h5", false, prov, hooks);
  EXPECT_EQ(calls, (std::vector<bool>{true, false}));
  EXPECT_EQ(checkpoint_at_end, 150);
  EXPECT_TRUE(o.interrupted);
  EXPECT_EQ(o.steps, 150);
  EXPECT_FALSE(fs::exists(s / "run.h5"));
  const auto r = sim::resume_tilt(short_run(), s / "run.h5", false);
  EXPECT_EQ(r.first_step, 150);
  expect_same_run(s / "ref.h5", s / "run.h5");
}

// The avalanche rule on a small pile tilted at 0.01 degree per step: the pile is static
// at small tilt, the avalanche is detected at a finite angle, and the agitation obeys
// the rule there: below the threshold just before, above it for the whole hold.
TEST(Tilt, AvalancheOfASmallPileIsDetected) {
  Scratch s;
  sim::DepositOptions d;
  d.grains = 150;
  d.width = 15.0;
  d.seed = 2;
  const sim::Pile pl = sim::deposit(d);
  io::h5::File mem = io::h5::create_in_memory("pile");
  sim::write_pile(mem, pl, io::provenance_now("test", "", ""));
  sim::TiltOptions o;
  o.rate_deg = 0.01;
  o.margin_deg = 0.5;
  o.frame_every = 1000;
  const auto out = sim::run_tilt(sim::read_pile(mem), o, s / "run.h5", false,
                                 io::provenance_now("test", "", ""));
  ASSERT_TRUE(out.avalanche);
  EXPECT_EQ(out.stop_reason, "avalanche");
  EXPECT_GT(out.avalanche_deg, 2.0);
  EXPECT_LT(out.avalanche_deg, 60.0);
  std::printf("avalanche of 150 grains at %.3f deg\n", out.avalanche_deg);
  io::h5::File f = io::h5::open_read(s / "run.h5", "run");
  io::RunReader r(f);
  const auto& res = r.header().results;
  EXPECT_EQ(res.at("avalanche_angle_deg"), io::Value(out.avalanche_deg));
  const std::int64_t start = io::as_int(res, "avalanche_step", "run");
  const std::int64_t confirmed = io::as_int(res, "avalanche_confirmed_step", "run");
  EXPECT_EQ(confirmed - start + 1, sim::hold_steps(o));
  EXPECT_EQ(out.steps, confirmed + 50);  // margin 0.5 degree = 50 steps
  const io::Series se = r.series();
  const sim::Agitation agit(sim::read_pile(mem).grains, o.settings.gravity);
  const auto& ek = se.real.at("kinetic_energy");
  for (std::int64_t k = start; k <= confirmed; ++k)
    EXPECT_GE(agit(ek[static_cast<std::size_t>(k - 1)]), o.avalanche_energy);
  EXPECT_LT(agit(ek[static_cast<std::size_t>(start - 2)]), o.avalanche_energy);
  // Static at small tilt: over the first 2 degrees the agitation stays 100 times below it.
  for (std::size_t k = 0; k < 200; ++k) EXPECT_LT(agit(ek[k]), 1e-2 * o.avalanche_energy) << k;
}

TEST(Tilt, NotAPileAndBadOptionsAreRefused) {
  Scratch s;
  sim::run_tilt(pile(), short_run(), s / "run.h5", false, io::provenance_now("test", "", ""));
  io::h5::File f = io::h5::open_read(s / "run.h5", "run.h5");
  try {
    sim::read_pile(f);
    ADD_FAILURE() << "a run was accepted as a pile";
  } catch (const cdpile::Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "run.h5: /: is a 'run' file, expected a pile (made by deposit)");
  }
  // An existing output is kept.
  EXPECT_THROW(
      sim::run_tilt(pile(), short_run(), s / "run.h5", false, io::provenance_now("test", "", "")),
      cdpile::Error);
  auto bad = [](auto change) {
    auto o = short_run();
    change(o);
    EXPECT_THROW(sim::validate(o), cdpile::UsageError);
  };
  bad([](sim::TiltOptions& o) { o.rate_deg = -0.001; });
  bad([](sim::TiltOptions& o) { o.to_deg = -1.0; });
  bad([](sim::TiltOptions& o) { o.frame_every = 0; });
  bad([](sim::TiltOptions& o) { o.settings.tolerance = 0.0; });
  EXPECT_FALSE(fs::exists(s / "other.h5"));
}

// A branch from a frame of a run, with the run's own options, repeats the run's next
// steps: the same contacts, critical counts and sweeps, and kinetic energies equal up to
// the rounding of impulse = force x h in the warm start.
TEST(Tilt, BranchFromAFrameRepeatsTheRun) {
  Scratch s;
  const auto prov = io::provenance_now("test", "", "");
  sim::run_tilt(pile(), short_run(), s / "run.h5", false, prov);
  io::h5::File f = io::h5::open_read(s / "run.h5", "run.h5");
  // 0.1 degree lies between the frames of steps 40 (0.08 deg) and 60 (0.12 deg).
  const sim::PileInput b = sim::read_branch(f, 0.1);
  ASSERT_TRUE(b.branch);
  EXPECT_EQ(b.branch->step, 40);
  EXPECT_NEAR(b.branch->tilt_deg, 0.08, 1e-12);
  EXPECT_EQ(sim::read_branch(f, 0.12).branch->step, 60);  // a frame exactly at the angle
  auto o = short_run();
  o.from_deg = b.branch->tilt_deg;
  sim::run_tilt(b, o, s / "branch.h5", false, prov);

  io::h5::File fa = io::h5::open_read(s / "run.h5", "run"),
               fb = io::h5::open_read(s / "branch.h5", "branch");
  io::RunReader ra(fa), rb(fb);
  EXPECT_EQ(io::as_int(rb.header().parameters, "branch_step", "branch"), 40);
  const io::Series sa = ra.series(), sb = rb.series();
  ASSERT_EQ(sb.size(), 110u);  // 0.08 to 0.3 degree at 0.002 per step
  for (std::size_t k = 0; k < sb.size(); ++k) {
    const std::size_t ka = k + 40;
    EXPECT_NEAR(sb.real.at("tilt_angle")[k], sa.real.at("tilt_angle")[ka], 1e-12);
    for (const char* key :
         {"contacts", "contacts_grain", "critical", "critical_grain", "sliding", "sweeps"})
      EXPECT_EQ(sb.integer.at(key)[k], sa.integer.at(key)[ka]) << key << " at branch step " << k;
    const double ea = sa.real.at("kinetic_energy")[ka], eb = sb.real.at("kinetic_energy")[k];
    EXPECT_NEAR(eb, ea, 1e-6 * ea + 1e-300) << k;
  }
  // A pile is not a run to branch from, and a branch needs a frame at or below the angle.
  io::h5::File pf = io::h5::create_in_memory("pile.h5");
  sim::write_pile(
      pf,
      [] {
        sim::DepositOptions d;
        d.grains = 20;
        d.width = 6.0;
        return sim::deposit(d);
      }(),
      prov);
  try {
    sim::read_branch(pf, 1.0);
    ADD_FAILURE() << "branched from a pile";
  } catch (const cdpile::Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "pile.h5: /: is a 'pile' file; a branch starts from a run (made by tilt-cd)");
  }
  try {
    sim::read_branch(f, -1.0);
    ADD_FAILURE() << "branched below the first frame";
  } catch (const cdpile::Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "run.h5: /particles/grains/position: has no frame at or below -1 deg (the first is "
              "at 0 deg)");
  }
}

// Steps that hit the sweep cap are flagged step by step (observable converged = 0) and
// counted in the run's results (unconverged_steps) and outcome.
TEST(Tilt, UnconvergedStepsAreFlaggedAndCounted) {
  Scratch s;
  auto o = short_run();
  o.settings.max_sweeps = 2;
  o.settings.tolerance = 1e-9;
  const auto out =
      sim::run_tilt(pile(), o, s / "run.h5", false, io::provenance_now("test", "", ""));
  io::h5::File f = io::h5::open_read(s / "run.h5", "run");
  io::RunReader r(f);
  const io::Series se = r.series();
  std::int64_t flagged = 0;
  for (std::size_t k = 0; k < se.size(); ++k) {
    const bool converged = se.integer.at("converged")[k] != 0;
    if (!converged) {
      ++flagged;
      EXPECT_EQ(se.integer.at("sweeps")[k], 2);
      EXPECT_GT(se.real.at("residual")[k], 1e-9);
    }
  }
  EXPECT_GT(flagged, 100);  // 150 steps of a 100-grain pile cannot converge to 1e-9 in 2 sweeps
  EXPECT_EQ(out.unconverged_steps, flagged);
  EXPECT_EQ(io::as_int(r.header().results, "unconverged_steps", "run"), flagged);
  // ... and warned of, in the outcome and in the file.
  ASSERT_EQ(out.warnings.size(), 1u);
  EXPECT_EQ(out.warnings[0].rfind(std::to_string(flagged) + " of 150 steps (", 0), 0u)
      << out.warnings[0];
  EXPECT_EQ(io::as_int(r.header().results, "warnings", "run"), 1);
  EXPECT_EQ(r.header().results.at("warning_messages"), io::Value(out.warnings[0]));
}

// The settings' warnings and their thresholds, from the stability map: h sqrt(g/D) above
// 0.02, a tolerance of 1e-2 or looser. The defaults earn none.
TEST(Tilt, SettingsWarningsAtTheirThresholds) {
  const double D = 1e-3;
  cdpile::cd::Settings s;  // h = 1e-4 s, tolerance 1e-4
  EXPECT_TRUE(sim::settings_warnings(s, D).empty());
  s.time_step = 0.02 / std::sqrt(s.gravity / D) * (1 - 1e-9);  // just below 0.02
  EXPECT_TRUE(sim::settings_warnings(s, D).empty());
  s.time_step = 2.1e-4;
  const auto step = sim::settings_warnings(s, D);
  ASSERT_EQ(step.size(), 1u);
  EXPECT_EQ(
      step[0],
      "h sqrt(g/D) = 0.0208 is above 0.02; runs of the stability map overlapped beyond 1e-3 D "
      "from 0.04 on (lower --time-step; docs/performance.md)");
  s.time_step = 1e-4;
  s.tolerance = 9.99e-3;
  EXPECT_TRUE(sim::settings_warnings(s, D).empty());
  s.tolerance = 1e-2;
  const auto tol = sim::settings_warnings(s, D);
  ASSERT_EQ(tol.size(), 1u);
  EXPECT_EQ(
      tol[0],
      "the tolerance 0.01 is 1e-2 or looser; runs of the stability map overlapped or moved the "
      "avalanche there (lower --tolerance; docs/performance.md)");
  s.time_step = 1e-3;
  EXPECT_EQ(sim::settings_warnings(s, D).size(), 2u);
}

// The run-time warnings and their thresholds: 1 % of the steps at the cap, overlaps of
// 1e-3 D. A sound run has none (and the short run above, converged, says so in its file).
TEST(Tilt, RunWarningsAtTheirThresholds) {
  EXPECT_TRUE(sim::run_warnings(1000, 10, 0.0, 1e-3).empty());  // exactly 1 %
  const auto cap = sim::run_warnings(1000, 11, 0.0, 1e-3);
  ASSERT_EQ(cap.size(), 1u);
  EXPECT_EQ(cap[0],
            "11 of 1000 steps (1.1 %) hit the sweep cap; their forces are not converged "
            "(raise --max-sweeps; docs/performance.md)");
  EXPECT_TRUE(sim::run_warnings(1000, 0, 1e-6, 1e-3).empty());  // exactly 1e-3 D
  const auto overlap = sim::run_warnings(1000, 0, 2.5e-6, 1e-3);
  ASSERT_EQ(overlap.size(), 1u);
  EXPECT_EQ(overlap[0],
            "the run's overlaps grew by up to 0.0025 D, beyond 1e-3 D; the time step is too large "
            "for these speeds (lower --time-step)");
  EXPECT_EQ(sim::run_warnings(1000, 500, 1e-5, 1e-3).size(), 2u);
  // With a contact stiffness the capped steps converge with sub-steps, and more of them.
  EXPECT_EQ(sim::run_warnings(1000, 11, 0.0, 1e-3, 2e7)[0],
            "11 of 1000 steps (1.1 %) hit the sweep cap; their forces are not converged "
            "(allow sub-steps, --max-substeps 64; docs/method.md, Sub-steps)");
  EXPECT_EQ(sim::run_warnings(1000, 11, 0.0, 1e-3, 2e7, 16)[0],
            "11 of 1000 steps (1.1 %) hit the sweep cap; their forces are not converged "
            "(raise --max-substeps; docs/method.md, Sub-steps)");
  // With a contact stiffness the overlap is the compliance, not a time-step error.
  const auto soft = sim::run_warnings(1000, 0, 2.5e-6, 1e-3, 2e7);
  ASSERT_EQ(soft.size(), 1u);
  EXPECT_EQ(soft[0],
            "the run's overlaps grew by up to 0.0025 D, beyond 1e-3 D: the compliance of the "
            "contact stiffness (an impact at speed v compresses a contact by about v sqrt(m/k); "
            "a stiffer k makes it smaller)");
  Scratch s;
  const auto out =
      sim::run_tilt(pile(), short_run(), s / "run.h5", false, io::provenance_now("test", "", ""));
  EXPECT_TRUE(out.warnings.empty());
  io::h5::File f = io::h5::open_read(s / "run.h5", "run");
  EXPECT_EQ(io::as_int(io::RunReader(f).header().results, "warnings", "run"), 0);
  EXPECT_EQ(io::RunReader(f).header().results.count("warning_messages"), 0u);
}

// The overlap warning measures what the run adds to the pile's own overlaps, contact by
// contact: an overlap the pile came with counts only by what it grows; a pair that had
// none, or a contact with another wall, counts whole; an overlap that shrank counts 0.
TEST(Tilt, OverlapGrowthIsBeyondEachPairsOwnAtTheStart) {
  const Vec2 p{0.0, 0.0}, n{0.0, 1.0};
  Contacts start;
  start.push_back(1, 2, p, n, 1.0, 0.0, -5e-6, ContactStatus::stick);
  start.push_back(3, -1, p, n, 1.0, 0.0, -4e-6, ContactStatus::stick);
  start.push_back(4, 5, p, n, 0.0, 0.0, 1e-7, ContactStatus::open);
  const sim::OverlapGrowth growth(start);
  EXPECT_EQ(growth.grown(start), 0.0);
  Contacts now;
  now.push_back(1, 2, p, n, 1.0, 0.0, -5.5e-6, ContactStatus::stick);  // grew by 0.5e-6
  now.push_back(3, -1, p, n, 1.0, 0.0, -1e-6, ContactStatus::stick);   // shrank
  EXPECT_NEAR(growth.grown(now), 0.5e-6, 1e-18);
  now.push_back(4, 5, p, n, 1.0, 0.0, -0.7e-6, ContactStatus::stick);  // new overlap
  EXPECT_NEAR(growth.grown(now), 0.7e-6, 1e-18);
  now.push_back(3, -2, p, n, 1.0, 0.0, -2e-6, ContactStatus::stick);  // another wall
  EXPECT_NEAR(growth.grown(now), 2e-6, 1e-18);
  // A pile without overlaps: the growth is the largest overlap.
  EXPECT_NEAR(sim::OverlapGrowth(Contacts{}).grown(now), 5.5e-6, 1e-18);
}

// The settings a run records are the settings it is rebuilt with: every field survives
// settings_parameters and settings_from_parameters, and a missing or bad one names the
// file and what is wrong.
TEST(Settings, ParametersRoundTripAndErrorsNameTheFile) {
  namespace cd = cdpile::cd;
  cd::Settings s;
  s.time_step = 2.5e-5;
  s.theta = 0.75;
  s.gravity = 3.7;
  s.mu_grain = 0.3;
  s.mu_wall = 0.2;
  s.alert_distance = 3e-5;
  s.tolerance = 1e-6;
  s.max_sweeps = 123;
  s.symmetric_sweeps = false;
  s.criterion = cd::Criterion::qm16;
  const cd::Settings back = sim::settings_from_parameters(sim::settings_parameters(s), "run.h5");
  EXPECT_EQ(back.time_step, s.time_step);
  EXPECT_EQ(back.theta, s.theta);
  EXPECT_EQ(back.gravity, s.gravity);
  EXPECT_EQ(back.mu_grain, s.mu_grain);
  EXPECT_EQ(back.mu_wall, s.mu_wall);
  EXPECT_EQ(back.alert_distance, s.alert_distance);
  EXPECT_EQ(back.tolerance, s.tolerance);
  EXPECT_EQ(back.max_sweeps, s.max_sweeps);
  EXPECT_EQ(back.symmetric_sweeps, s.symmetric_sweeps);
  EXPECT_EQ(back.criterion, s.criterion);

  auto message = [](const io::Values& v) {
    try {
      sim::settings_from_parameters(v, "run.h5");
    } catch (const cdpile::Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  io::Values v = sim::settings_parameters(s);
  v.erase("tolerance");
  EXPECT_EQ(message(v), "run.h5: /parameters: missing parameter 'tolerance'");
  v = sim::settings_parameters(s);
  v["criterion"] = std::string("fast");
  EXPECT_EQ(message(v),
            "run.h5: /parameters: unknown convergence criterion 'fast' (maxm, quad, qm16, law or "
            "err)");
  v = sim::settings_parameters(s);
  v["theta"] = 0.2;
  EXPECT_EQ(message(v), "run.h5: /parameters: engine settings: theta must be in [0.5, 1]");
}

// Files written before the solver seam have no solver, check_every or contact stiffness:
// they are read as NSGS, checked every sweep, rigid, so their resumes and branches go on
// as the run began; today's files round-trip all three.
TEST(Settings, PreSeamFilesReadAsRigidNsgsCheckedEverySweep) {
  namespace cd = cdpile::cd;
  cd::Settings s;
  s.contact_stiffness = 1.5e6;
  s.check_every = 50;
  s.criterion = cd::Criterion::law;
  const cd::Settings back = sim::settings_from_parameters(sim::settings_parameters(s), "run.h5");
  EXPECT_EQ(back.contact_stiffness, 1.5e6);
  EXPECT_EQ(back.check_every, 50);
  EXPECT_EQ(back.criterion, cd::Criterion::law);
  EXPECT_EQ(back.solver, cd::SolverKind::nsgs);

  io::Values old = sim::settings_parameters(cd::Settings{});
  for (const char* k : {"solver", "check_every", "contact_stiffness_N_m2"}) old.erase(k);
  const cd::Settings legacy = sim::settings_from_parameters(old, "old.h5");
  EXPECT_EQ(legacy.solver, cd::SolverKind::nsgs);
  EXPECT_EQ(legacy.check_every, 1);
  EXPECT_EQ(legacy.contact_stiffness, 0.0);
  EXPECT_EQ(sim::with_pre_seam_settings(old), sim::settings_parameters(cd::Settings{}));

  // Files made before the strips were counted cut the box into as many as fit (0).
  io::Values before_strips = sim::settings_parameters(cd::Settings{});
  before_strips.erase("strips");
  EXPECT_EQ(sim::settings_from_parameters(before_strips, "old.h5").strips, 0);
  EXPECT_EQ(cd::Settings{}.strips, 16);
}

// A branch that makes a compliant run's contacts rigid takes the rigid defaults of the
// sub-steps and the cap where not given (docs/method.md, "Sub-steps"), and back; a branch
// at another compliant stiffness keeps the run's.
TEST(Tilt, ABranchToRigidContactsTakesTheirSubstepsAndCap) {
  sim::TiltOptions run = short_run();
  run.settings.contact_stiffness = 1e6;
  run.settings.max_substeps = 64;
  run.settings.max_sweeps = 2000;
  const io::Values compliant = sim::tilt_parameters(run);
  sim::TiltOptions asked;
  asked.settings.contact_stiffness = 0.0;
  sim::InheritedOptions b = sim::inherit_options(compliant, asked, {"stiffness"}, 0.1, "run.h5");
  EXPECT_EQ(b.options.settings.max_substeps, 1);
  EXPECT_EQ(b.options.settings.max_sweeps, 100000);
  ASSERT_EQ(b.changes.size(), 3u);  // in the table's order: the cap, k, the sub-steps
  EXPECT_EQ(b.changes[0].parameter, "max_sweeps");
  EXPECT_EQ(b.changes[0].option, "");
  EXPECT_EQ(b.changes[0].run_value + " " + b.changes[0].value, "2000 100000");
  EXPECT_EQ(b.changes[0].reason, "the default with rigid contacts");
  EXPECT_EQ(b.changes[1].option, "stiffness");
  EXPECT_EQ(b.changes[2].parameter, "max_substeps");
  // given, they win
  asked.settings.max_substeps = 4;
  b = sim::inherit_options(compliant, asked, {"stiffness", "max-substeps"}, 0.1, "run.h5");
  EXPECT_EQ(b.options.settings.max_substeps, 4);
  EXPECT_EQ(b.options.settings.max_sweeps, 100000);
  // and back: a rigid run branched compliant
  run.settings.contact_stiffness = 0.0;
  run.settings.max_substeps = 1;
  run.settings.max_sweeps = 100000;
  asked = sim::TiltOptions{};
  asked.settings.contact_stiffness = 2e7;
  b = sim::inherit_options(sim::tilt_parameters(run), asked, {"stiffness"}, 0.1, "run.h5");
  EXPECT_EQ(b.options.settings.max_substeps, 64);
  EXPECT_EQ(b.options.settings.max_sweeps, 2000);
  // another compliant stiffness keeps the run's
  run.settings.contact_stiffness = 1e6;
  run.settings.max_substeps = 16;
  b = sim::inherit_options(sim::tilt_parameters(run), asked, {"stiffness"}, 0.1, "run.h5");
  EXPECT_EQ(b.options.settings.max_substeps, 16);
  EXPECT_EQ(b.options.settings.max_sweeps, 100000);
}

// A branch or a resume takes the run's options; those given override them and are listed
// as changes; a frame interval not given keeps its degrees at another rate.
TEST(Tilt, BranchAndResumeInheritTheRunsOptions) {
  sim::TiltOptions run = short_run();  // 0.002 deg per step, a frame every 20 steps, to 0.3
  run.settings.tolerance = 1e-5;
  run.eps = 2e-3;
  const io::Values stored = sim::tilt_parameters(run);
  const sim::TiltOptions defaults;  // what the command line holds for options not given
  // nothing given: the run's options
  sim::InheritedOptions same = sim::inherit_options(stored, defaults, {}, std::nullopt, "run.h5");
  EXPECT_TRUE(same.changes.empty());
  EXPECT_EQ(sim::tilt_parameters(same.options), stored);
  // a branch at 0.08 deg with another tolerance and rate
  sim::TiltOptions asked = defaults;
  asked.settings.tolerance = 1e-7;
  asked.rate_deg = 0.004;
  const sim::InheritedOptions b =
      sim::inherit_options(stored, asked, {"tolerance", "rate"}, 0.08, "run.h5");
  EXPECT_EQ(b.options.rate_deg, 0.004);
  EXPECT_EQ(b.options.settings.tolerance, 1e-7);
  EXPECT_EQ(b.options.frame_every, 10);  // 20 steps at 0.002 deg: 0.04 deg
  EXPECT_EQ(b.options.from_deg, 0.08);
  EXPECT_EQ(b.options.to_deg, run.to_deg);
  EXPECT_EQ(b.options.eps, 2e-3);
  ASSERT_EQ(b.changes.size(), 3u);  // the rate, the tolerance, the frame interval (derived)
  EXPECT_EQ(b.changes[0].option, "rate");
  EXPECT_EQ(b.changes[0].parameter, "tilt_rate_deg_per_step");
  EXPECT_EQ(b.changes[0].run_value, "0.002");
  EXPECT_EQ(b.changes[0].value, "0.004");
  EXPECT_EQ(b.changes[1].option, "");
  EXPECT_EQ(b.changes[1].parameter, "frame_every_steps");
  EXPECT_EQ(b.changes[1].reason, "the same interval in degrees at this --rate");
  EXPECT_EQ(b.changes[2].option, "tolerance");
  // a run without --to: "none"
  io::Values open_ended = stored;
  open_ended["tilt_to_deg"] = -1.0;
  asked = defaults;
  asked.to_deg = 0.2;
  const sim::InheritedOptions to = sim::inherit_options(open_ended, asked, {"to"}, 0.08, "run.h5");
  ASSERT_EQ(to.changes.size(), 1u);
  EXPECT_EQ(to.changes[0].run_value + " " + to.changes[0].value, "none 0.2");
  // a frame interval given is kept as given
  asked.frame_every = 7;
  EXPECT_EQ(sim::inherit_options(stored, asked, {"rate", "frame-every"}, 0.08, "run.h5")
                .options.frame_every,
            7);
  // an option given with the run's own value is no change
  asked = defaults;
  asked.rate_deg = 0.002;
  EXPECT_TRUE(
      sim::inherit_options(stored, asked, {"rate"}, std::nullopt, "run.h5").changes.empty());
  // a run without a tilt parameter: an Error naming the file
  io::Values broken = stored;
  broken.erase("tilt_rate_deg_per_step");
  EXPECT_THROW(sim::inherit_options(broken, defaults, {}, std::nullopt, "run.h5"), cdpile::Error);
}
