// A run's summary (analysis/run_summary.hpp): the RunRecord it holds is the one it was
// made from, field by field, missing values included; a localnu study fed summaries makes
// the product it makes from the frames; a reading with other settings is refused.
#include "cdpile/analysis/run_summary.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace cdpile;
using namespace cdpile::analysis;

namespace {

RunRecord sample_run() {
  RunRecord r;
  r.name = "run-7.h5";
  r.free_grains = 40;
  r.diameter = 1e-3;
  r.mean_mass = 2.04e-3;
  r.gravity = 9.81;
  r.recorded_avalanche = 17.25;
  r.recorded_rule = {1e-3, 0.5, std::nullopt};
  r.mu = {0.5, 0.4};
  for (int k = 0; k < 5; ++k) {
    r.steps.step.push_back(k + 1);
    r.steps.theta.push_back(0.1 * (k + 1));
    r.steps.contacts.push_back(70 + k);
    r.steps.critical.push_back(3 + (k % 2));
    r.steps.kinetic_energy.push_back(1e-9 * (k + 1) / 3.0);
    r.steps.converged.push_back(k != 2);
    r.steps.sweeps.push_back(k == 2 ? 200000 : 40 + k);
    r.steps.substeps.push_back(k == 3 ? 4 : 1);
  }
  // sliding, rotational_energy, max_speed, grains_without_contact: not recorded
  FrameRecord a;
  a.frame = 0;
  a.step = 0;
  a.theta = 0.0;
  a.state = {70, 3, 1, 40, 38, 3.0 / 70.0, 1.0 / 70.0, 3.6842105263157894, 3.5, 0.4};
  a.kinetic_energy = 1.5e-10;
  a.bound = StaticBound{70, 38, 3};
  a.agitation = 2e-10;
  a.max_speed = 1e-4;
  a.grains_without_contact = 2;
  a.z_paper = 3.55;
  a.slipping = 4;
  a.critical_slipping = 1;
  a.contacts_at_rest = 60;
  a.critical_at_rest = 2;
  a.mobilisation.assign(mobilisation_bins, 0);
  a.mobilisation[19] = 3;
  a.mobilisation[4] = 67;
  FrameRecord b;  // a frame without velocities and without contacts: every optional empty
  b.frame = 1;
  b.step = 5;
  b.theta = 0.5;
  b.state.grains = 40;
  r.frames = {a, b};
  return r;
}

Product localnu_part() {
  LocalNuStudy s(default_localnu_options());
  ContactSet set;
  for (int k = 0; k < 30; ++k) {
    set.point.emplace_back(1e-3 * (k % 6), 1e-3 * (k / 6));
    set.critical.push_back(k % 4 == 0);
    set.i.push_back(k);
    set.j.push_back(k + 1);
    set.mobilisation.push_back(k % 4 == 0 ? 1.0 : 0.3);
    set.sliding.push_back(0);
    set.row.push_back(static_cast<std::size_t>(k));
  }
  s.add_frame(0, "run-7.h5", 0, 0, 0.0, 1e-3, set, true, false);
  s.add_frame(0, "run-7.h5", 1, 5, 0.5, 1e-3, set, true, true);
  return s.product();
}

}  // namespace

TEST(RunSummary, RunRecordRoundTrip) {
  const RunRecord r = sample_run();
  Product s = make_summary(r, critical_reading({}, r.mu, RattlerRule::exclude, 1e-4, 1e-2),
                           localnu_part(),
                           localnu_reading(default_localnu_options(), {}, r.mu, {}, {}, {}), {},
                           {}, {{"seed", std::int64_t{7}}, {"solver", std::string("pcg")}});
  s.source = "s.h5";
  const RunRecord q = summary_run_record(s);
  EXPECT_EQ(q.name, "run-7.h5");
  EXPECT_EQ(q.free_grains, 40);
  EXPECT_EQ(q.diameter, r.diameter);
  EXPECT_EQ(q.mean_mass, r.mean_mass);
  EXPECT_EQ(q.gravity, r.gravity);
  EXPECT_EQ(q.recorded_avalanche, r.recorded_avalanche);
  EXPECT_EQ(q.recorded_rule.eps, r.recorded_rule.eps);
  EXPECT_EQ(q.recorded_rule.mu_wall, std::nullopt);
  EXPECT_EQ(q.mu.grain, 0.5);
  EXPECT_EQ(q.mu.wall, 0.4);
  EXPECT_EQ(q.steps.step, r.steps.step);
  EXPECT_EQ(q.steps.theta, r.steps.theta);
  EXPECT_EQ(q.steps.contacts, r.steps.contacts);
  EXPECT_EQ(q.steps.critical, r.steps.critical);
  EXPECT_EQ(q.steps.kinetic_energy, r.steps.kinetic_energy);  // every bit
  EXPECT_EQ(q.steps.converged, r.steps.converged);
  EXPECT_EQ(q.steps.sweeps, (std::vector<std::int64_t>{40, 41, 200000, 43, 44}));
  EXPECT_EQ(q.steps.substeps, (std::vector<std::int64_t>{1, 1, 1, 4, 1}));
  EXPECT_TRUE(q.steps.sliding.empty());
  EXPECT_TRUE(q.steps.max_speed.empty());
  ASSERT_EQ(q.frames.size(), 2u);
  const FrameRecord &a = q.frames[0], &b = q.frames[1];
  EXPECT_EQ(a.state.contacts, 70);
  EXPECT_EQ(a.state.loaded_grains, 38);
  EXPECT_EQ(a.state.nu, 3.0 / 70.0);
  EXPECT_EQ(a.state.z, 3.6842105263157894);
  EXPECT_EQ(a.state.lambda, 0.4);
  ASSERT_TRUE(a.bound);
  EXPECT_EQ(a.bound->bound(), 2 * 70 - 3 * 38);
  EXPECT_EQ(a.bound->critical, 3);
  EXPECT_EQ(a.agitation, 2e-10);
  EXPECT_EQ(a.grains_without_contact, 2);
  EXPECT_EQ(a.critical_at_rest, 2);
  EXPECT_EQ(a.mobilisation, r.frames[0].mobilisation);
  EXPECT_EQ(b.step, 5);
  EXPECT_EQ(b.theta, 0.5);
  EXPECT_FALSE(b.state.nu);
  EXPECT_FALSE(b.bound);
  EXPECT_FALSE(b.kinetic_energy);
  EXPECT_FALSE(b.slipping);
  EXPECT_TRUE(b.mobilisation.empty());
  // the engine: the run's parameters, the stiffness apart from them
  EXPECT_EQ(std::get<std::string>(s.parameters.at("run_solver")), "pcg");
}

TEST(RunSummary, LocalNuFromSummaryIsLocalNuFromFrames) {
  const Product part = localnu_part();
  Product s = make_summary(sample_run(), critical_reading({}, {}, RattlerRule::exclude, 1e-4, 1e-2),
                           part, {}, {}, {}, {});
  s.source = "s.h5";
  // the study's product from the summary, as input 3, against the same frames added as input 3
  LocalNuStudy from_summary(default_localnu_options());
  from_summary.add_summary(3, s);
  const Product p = from_summary.product();
  const Table &frames = p.table("frames"), &states = p.table("states"), &pdf = p.table("pdf");
  EXPECT_EQ(frames.rows(), 2u);
  EXPECT_EQ(frames.column("run").num, std::vector<double>(2, 3.0));
  EXPECT_EQ(states.column("sum").num, part.table("states").column("sum").num);
  EXPECT_EQ(pdf.column("count_c").num, part.table("pdf").column("count_c").num);
  EXPECT_EQ(p.result("pdf_frames"), part.result("pdf_frames"));
  EXPECT_EQ(p.result("pdf_critical"), part.result("pdf_critical"));
  // the map is not added by add_summary: the caller chooses it (summary_map, set_map)
  EXPECT_FALSE(p.find("map"));
}

TEST(RunSummary, MapsKeptAndThresholdedAgain) {
  const Product part = localnu_part();
  Product s = make_summary(sample_run(), {}, part, {}, {0.5}, {part}, {});
  s.source = "s.h5";
  const auto none = summary_map(s, 3.0);
  EXPECT_FALSE(none);
  auto found = summary_map(s, 0.5);
  ASSERT_TRUE(found);
  EXPECT_EQ(found->first.column("nu").num, part.table("map").column("nu").num);
  LocalNuOptions o = default_localnu_options();
  o.nu_c = 0.3;
  LocalNuStudy st(o);
  st.set_map(2, found->first, found->second);
  const Product p = st.product();
  const Column &nu = p.table("map").column("nu"), &above = p.table("map").column("above");
  std::size_t checked = 0;
  for (std::size_t k = 0; k < nu.num.size(); ++k)
    if (nu.defined(k)) {
      EXPECT_EQ(above.num[k], nu.num[k] >= 0.3 ? 1.0 : 0.0);
      ++checked;
    }
  EXPECT_GT(checked, 0u);
  EXPECT_EQ(p.result("map_run"), 2.0);
  EXPECT_EQ(p.result("map_nu_c"), 0.3);
  EXPECT_EQ(p.result("map_frame"), 1.0);
}

TEST(RunSummary, ReadingAndEngineRefusedWithTheDifferenceNamed) {
  const RunRecord r = sample_run();
  Product s = make_summary(r, critical_reading({}, r.mu, RattlerRule::exclude, 1e-4, 1e-2),
                           localnu_part(), {}, {}, {},
                           {{"seed", std::int64_t{7}}, {"tolerance", 1e-6}});
  s.source = "s.h5";
  CriticalRule other;
  other.eps = 1e-2;
  EXPECT_NO_THROW(require_reading(s, critical_reading({}, r.mu, RattlerRule::exclude, 1e-4, 1e-2)));
  try {
    require_reading(s, critical_reading(other, r.mu, RattlerRule::exclude, 1e-4, 1e-2));
    FAIL() << "another eps was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "s.h5: /parameters: made with --eps 0.001, asked 0.01: summarise the run again with "
              "these settings, or ask for the summary's");
  }
  Product t = make_summary(r, {}, localnu_part(), {}, {}, {},
                           {{"seed", std::int64_t{8}}, {"tolerance", 1e-6}});
  t.source = "t.h5";
  EXPECT_EQ(engine_difference(s, t), std::nullopt);  // the seed may differ
  Product u = make_summary(r, {}, localnu_part(), {}, {}, {},
                           {{"seed", std::int64_t{8}}, {"tolerance", 1e-4}});
  u.source = "u.h5";
  EXPECT_EQ(engine_difference(s, u), "run_tolerance 1e-06 in s.h5, 1e-04 in u.h5");
}
