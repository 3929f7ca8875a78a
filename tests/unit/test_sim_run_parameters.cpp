// The table of run parameters (sim/tilt_options.hpp) is the one declaration of each
// parameter: every field round-trips through the file's parameters, and a branch or a
// resume inherits every recorded parameter and applies every option given. An option
// left out of the old hand-written table was silently not applied on a branch; these
// tests go over the whole table, so a new row is checked without a new test.
#include "cdpile/cli/avalanche_options.hpp"
#include "cdpile/cli/command.hpp"
#include "cdpile/cli/fields.hpp"
#include "cdpile/error.hpp"
#include "cdpile/fields.hpp"
#include "cdpile/sim/common.hpp"
#include "cdpile/sim/tilt_options.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

using namespace cdpile;

namespace {

// Two valid sets of options that differ in every field of the table.
sim::TiltOptions run_options() {
  sim::TiltOptions o;
  o.rate_deg = 0.002;
  o.from_deg = 0.5;
  o.to_deg = 5.0;
  o.max_deg = 60.0;
  o.margin_deg = 1.5;
  o.avalanche_energy = 2e-3;
  o.avalanche_hold_deg = 0.25;
  o.eps = 2e-3;
  o.frame_every = 20;
  o.checkpoint_every = 300;
  cd::Settings& s = o.settings;
  s.mu_grain = 0.45;
  s.mu_wall = 0.35;
  s.time_step = 2e-5;
  s.theta = 0.55;
  s.tolerance = 1e-5;
  s.max_sweeps = 700;
  s.criterion = cd::Criterion::quad;
  s.check_every = 3;
  s.solver = cd::SolverKind::nncg;
  s.contact_stiffness = 2e5;
  s.contact_damping_ratio = 0.3;
  s.scramble = 7;
  s.max_substeps = 8;
  s.substep_after = 40;
  s.sweep_order = cd::SweepOrder::pair;
  s.strips = 0;
  s.alert_distance = 1.5e-4;
  s.gravity = 9.5;
  s.symmetric_sweeps = true;
  s.threads = 1;
  return o;
}

sim::TiltOptions asked_options() {
  sim::TiltOptions o;
  o.rate_deg = 0.004;
  o.from_deg = 1.0;
  o.to_deg = 10.0;
  o.max_deg = 80.0;
  o.margin_deg = 2.0;
  o.avalanche_energy = 5e-3;
  o.avalanche_hold_deg = 0.3;
  o.eps = 4e-3;
  o.frame_every = 7;
  o.checkpoint_every = 100;
  cd::Settings& s = o.settings;
  s.mu_grain = 0.3;
  s.mu_wall = 0.4;
  s.time_step = 5e-5;
  s.theta = 0.6;
  s.tolerance = 1e-7;
  s.max_sweeps = 500;
  s.criterion = cd::Criterion::qm16;
  s.check_every = 5;
  s.solver = cd::SolverKind::pcg;
  s.contact_stiffness = 1e5;
  s.contact_damping_ratio = 0.8;
  s.scramble = 3;
  s.max_substeps = 4;
  s.substep_after = 50;
  s.substep_start = cd::SubstepStart::h;
  s.finish_after = 700;
  s.sweep_order = cd::SweepOrder::strips;
  s.strips = 6;
  s.alert_distance = 2e-4;
  s.gravity = 3.7;
  s.symmetric_sweeps = false;
  s.threads = 2;
  return o;
}

}  // namespace

TEST(RunParameters, NamesAreUniqueAndRecordedOnesAreInherited) {
  std::set<std::string> fields, keys, options;
  for (const sim::RunParameter& p : sim::run_parameters()) {
    EXPECT_TRUE(fields.insert(p.field).second) << p.field;
    if (!p.key.empty()) {
      EXPECT_TRUE(keys.insert(p.key).second) << p.key;
    }
    for (const std::string& o : {p.option, p.also_option}) {
      if (!o.empty()) {
        EXPECT_TRUE(options.insert(o).second) << o;
      }
    }
    // recorded: the run's value on a branch; not recorded: the command line's
    EXPECT_EQ(p.inherit == sim::Inherit::from_run, !p.key.empty()) << p.field;
    EXPECT_TRUE(p.get && p.set) << p.field;
    if (p.pre_seam) {
      EXPECT_EQ(p.group, sim::ParameterGroup::settings) << p.field;
    }
  }
}

// Every recorded field survives tilt_parameters and tilt_options_from_parameters, and the
// parameters are exactly the table's keys.
TEST(RunParameters, EveryFieldRoundTripsThroughTheFile) {
  const sim::TiltOptions o = asked_options();
  const io::Values v = sim::tilt_parameters(o);
  std::set<std::string> keys;
  for (const sim::RunParameter& p : sim::run_parameters())
    if (!p.key.empty()) keys.insert(p.key);
  std::set<std::string> written;
  for (const auto& [k, value] : v) written.insert(k);
  EXPECT_EQ(written, keys);
  const sim::TiltOptions back = sim::tilt_options_from_parameters(v, "run.h5");
  for (const sim::RunParameter& p : sim::run_parameters()) {
    if (p.key.empty()) continue;
    EXPECT_EQ(p.get(back), p.get(o)) << p.field;
    EXPECT_NE(p.get(back), p.get(sim::TiltOptions{})) << p.field << ": not a default";
  }
  // a run without --to
  sim::TiltOptions open_ended = o;
  open_ended.to_deg.reset();
  EXPECT_FALSE(
      sim::tilt_options_from_parameters(sim::tilt_parameters(open_ended), "run.h5").to_deg);
  // the engine's own: settings_parameters holds the settings group, deposit's record
  io::Values settings = sim::settings_parameters(o.settings);
  for (const sim::RunParameter& p : sim::run_parameters()) {
    if (p.key.empty()) continue;
    EXPECT_EQ(settings.count(p.key), p.group == sim::ParameterGroup::settings ? 1u : 0u) << p.key;
  }
}

// A branch takes each option given, whichever it is, and the run's value of every other
// recorded parameter; what is not recorded (threads, checkpoints) is the command line's.
TEST(RunParameters, ABranchAppliesEveryOptionGivenAndInheritsTheRest) {
  const sim::TiltOptions run = run_options(), asked = asked_options();
  const io::Values stored = sim::tilt_parameters(run);
  for (const sim::RunParameter& given : sim::run_parameters()) {
    if (given.inherit != sim::Inherit::from_run || given.option.empty()) continue;
    for (const std::string& option : {given.option, given.also_option}) {
      if (option.empty()) continue;
      const sim::InheritedOptions b =
          sim::inherit_options(stored, asked, {option}, std::nullopt, "run.h5");
      EXPECT_EQ(given.get(b.options), given.get(asked)) << "--" << option << " not applied";
      ASSERT_FALSE(b.changes.empty()) << option;
      EXPECT_EQ(b.changes.front().option, option);
      EXPECT_EQ(b.changes.front().parameter, given.key);
      for (const sim::RunParameter& p : sim::run_parameters()) {
        if (&p == &given) continue;
        if (p.inherit == sim::Inherit::as_asked) {
          EXPECT_EQ(p.get(b.options), p.get(asked)) << p.field;
        } else if (!(given.key == "tilt_rate_deg_per_step" && p.key == "frame_every_steps")) {
          EXPECT_EQ(p.get(b.options), p.get(run)) << p.field << " with --" << option;
        }
      }
    }
  }
  // nothing given: the run's, every one
  const sim::InheritedOptions same =
      sim::inherit_options(stored, asked, {}, std::nullopt, "run.h5");
  EXPECT_TRUE(same.changes.empty());
  EXPECT_EQ(sim::tilt_parameters(same.options), stored);
}

// The tools spell a field by the option the table declares for it (Usage::declare), and
// the others by their bundle's option or the field's own name: the table's, every one.
TEST(RunParameters, TheToolsSpellFieldsAsTheTableNamesTheirOptions) {
  cli::Usage u;
  const std::vector<OptionDeclaration> declared = sim::declared_options();
  for (const char* group : {"Tilt", "Avalanche", "Recording", "Solver"}) u.declare(group, declared);
  cli::declare_avalanche_rule(u, "", "");
  for (const sim::RunParameter& p : sim::run_parameters()) {
    const std::string spelled = cli::option_of_field(p.field);
    if (p.declaration) {
      EXPECT_EQ(spelled, "--" + p.option) << p.field;
    } else if (spelled != default_field_spelling(p.field)) {
      EXPECT_EQ(spelled, "--" + p.option) << p.field;
    }
  }
  EXPECT_EQ(cli::option_of_field("contact_stiffness"), "--stiffness");
  EXPECT_EQ(cli::option_of_field("avalanche_energy"), "--avalanche-ek");
}

// tilt-cd's options declared in the table: each option's default is its field's, and its
// value sets the field (an optional one not given: none); the engine's, deposit's too,
// default to option_defaults() and set the settings, converted from D and m g / D.
TEST(RunParameters, DeclaredOptionsSetTheirFields) {
  const std::vector<OptionDeclaration> declared = sim::declared_options();
  ASSERT_FALSE(declared.empty());
  const sim::TiltOptions defaults;
  OptionValues values;
  for (const OptionDeclaration& d : declared) {
    if (auto* x = std::get_if<double>(&d.default_value)) values[d.name] = *x;
    if (auto* i = std::get_if<std::int64_t>(&d.default_value)) values[d.name] = *i;
  }
  sim::TiltOptions o = run_options();
  sim::set_declared_options(o, values);
  for (const sim::RunParameter& p : sim::run_parameters())
    if (p.declaration && p.group == sim::ParameterGroup::tilt) {
      EXPECT_EQ(p.get(o), p.get(defaults)) << p.field;
    }
  values["rate"] = 0.25;
  values["checkpoint-every"] = std::int64_t{9};
  sim::set_declared_options(o, values);
  EXPECT_EQ(o.rate_deg, 0.25);
  EXPECT_EQ(o.checkpoint_every, 9);
  EXPECT_FALSE(o.to_deg.has_value());
  values["to"] = -1.0;  // a tilt, not the file's "none"
  sim::set_declared_options(o, values);
  EXPECT_EQ(o.to_deg, std::optional<double>(-1.0));

  for (const OptionDeclaration& d : declared)
    if (auto* name = std::get_if<std::string>(&d.default_value)) values[d.name] = *name;
  const cd::Settings tool = sim::option_defaults();
  cd::Settings s = sim::settings_from_options(values, {2e-3, 0.5, 10.0});
  EXPECT_EQ(s.solver, tool.solver);
  EXPECT_EQ(s.tolerance, tool.tolerance);
  EXPECT_EQ(s.max_substeps, tool.max_substeps);
  EXPECT_EQ(s.criterion, tool.criterion);
  EXPECT_EQ(s.alert_distance, 0.1 * 2e-3);                  // 0.1 D
  EXPECT_EQ(s.contact_stiffness, 1e6 * 0.5 * 10.0 / 2e-3);  // 1e6 m g / D
  values["max-substeps"] = std::int64_t{3};
  try {
    sim::settings_from_options(values, {});
    ADD_FAILURE() << "3 sub-steps accepted";
  } catch (const UsageError& e) {
    EXPECT_EQ(std::string(e.what()),
              "--max-substeps: expected a power of two in [1, 1024], got '3'");
  }
}

// --max-substeps and --max-sweeps have no default of their own: not given, they take the
// compliant defaults (64, 2000), or with --stiffness 0 the rigid ones (no sub-steps, a cap
// of 100 000 at h: docs/method.md, "Sub-steps"); given, they win at any stiffness.
TEST(RunParameters, RigidContactsDefaultToUnsplitStepsWithAHigherCap) {
  for (const OptionDeclaration& d : sim::declared_options()) {
    if (d.name == "max-substeps" || d.name == "max-sweeps") {
      EXPECT_TRUE(std::holds_alternative<std::monostate>(d.default_value)) << d.name;
    }
  }
  const sim::PileScale scale{1e-3, 1e-6, 9.81};
  OptionValues values{{"stiffness", 1e6}};
  cd::Settings s = sim::settings_from_options(values, scale);
  EXPECT_EQ(s.max_substeps, 64);
  EXPECT_EQ(s.max_sweeps, 2000);
  values["stiffness"] = 0.0;
  s = sim::settings_from_options(values, scale);
  EXPECT_EQ(s.contact_stiffness, 0.0);
  EXPECT_EQ(s.max_substeps, 1);
  EXPECT_EQ(s.max_sweeps, 100000);
  EXPECT_EQ(s.max_substeps, sim::rigid_option_defaults().max_substeps);
  EXPECT_EQ(s.max_sweeps, sim::rigid_option_defaults().max_sweeps);
  values["max-substeps"] = std::int64_t{16};
  values["max-sweeps"] = std::int64_t{2000};
  s = sim::settings_from_options(values, scale);
  EXPECT_EQ(s.max_substeps, 16);
  EXPECT_EQ(s.max_sweeps, 2000);
  values["stiffness"] = 1e6;
  values["max-substeps"] = std::int64_t{1};
  values["max-sweeps"] = std::int64_t{100000};
  s = sim::settings_from_options(values, scale);
  EXPECT_EQ(s.max_substeps, 1);
  EXPECT_EQ(s.max_sweeps, 100000);
}

// validate() holds each field to its row's range (RunParameter::accepted), with the
// messages it has always given, naming the field as the front end spells it.
TEST(RunParameters, ValidateRefusesEachFieldOutOfItsRowsRange) {
  set_field_spelling([](const std::string& f) { return "'" + f + "'"; });
  auto refusal = [](auto change) -> std::string {
    sim::TiltOptions o;
    change(o);
    try {
      sim::validate(o);
    } catch (const UsageError& e) {
      return e.what();
    }
    return "accepted";
  };
  using O = sim::TiltOptions;
  EXPECT_EQ(refusal([](O&) {}), "accepted");
  EXPECT_EQ(refusal([](O& o) { o.rate_deg = 0.0; }), "'rate_deg' must be > 0");
  EXPECT_EQ(refusal([](O& o) { o.rate_deg = HUGE_VAL; }), "'rate_deg' must be > 0");
  EXPECT_EQ(refusal([](O& o) { o.from_deg = NAN; }), "'from_deg' must be finite");
  EXPECT_EQ(refusal([](O& o) { o.margin_deg = -1.0; }), "'margin_deg' must be >= 0");
  EXPECT_EQ(refusal([](O& o) { o.avalanche_energy = 0.0; }), "'avalanche_energy' must be > 0");
  EXPECT_EQ(refusal([](O& o) { o.avalanche_hold_deg = -0.5; }),
            "'avalanche_hold_deg' must be >= 0");
  EXPECT_EQ(refusal([](O& o) { o.eps = 1.0; }), "'eps' must be in [0, 1)");
  EXPECT_EQ(refusal([](O& o) { o.checkpoint_every = 0; }), "'checkpoint_every' must be >= 1");
  EXPECT_EQ(refusal([](O& o) { o.frame_every = 0; }), "the frame interval must be >= 1 step");
  EXPECT_EQ(refusal([](O& o) { o.max_deg = -1.0; }), "the maximum angle must be >= 'from_deg'");
  set_field_spelling(nullptr);
}

// The observables are one table: the series has its columns and units, and a step
// appends one value to each.
TEST(Observables, TheSeriesAndEachStepFollowTheTable) {
  const io::Series s0 = sim::observables_series();
  EXPECT_EQ(s0.real.size() + s0.integer.size(), sim::observables().size());
  EXPECT_EQ(s0.unit.size(), sim::observables().size());
  EXPECT_EQ(s0.unit.at("tilt_angle"), "degree");
  EXPECT_EQ(s0.unit.at("max_speed"), "m s-1");
  io::Series s = s0;
  cd::StepReport r;
  r.step = 3;
  r.tilt_angle = M_PI / 180.0;
  r.contacts = 12;
  r.converged = false;
  sim::append_observables(s, r, {5, 2});
  for (const auto& [n, col] : s.real) EXPECT_EQ(col.size(), 1u) << n;
  for (const auto& [n, col] : s.integer) EXPECT_EQ(col.size(), 1u) << n;
  EXPECT_DOUBLE_EQ(s.real.at("tilt_angle")[0], 1.0);
  EXPECT_EQ(s.integer.at("contacts")[0], 12);
  EXPECT_EQ(s.integer.at("converged")[0], 0);
  EXPECT_EQ(s.integer.at("critical")[0], 5);
  EXPECT_EQ(s.integer.at("critical_grain")[0], 2);
}
