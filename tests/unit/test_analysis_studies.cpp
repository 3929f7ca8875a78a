// The four analyses end to end on data built by hand: critical (events, ensemble,
// envelope, theta_c), localnu (nu_bar and pdfs), correlate (pooling) and clusterfit
// (recovery of A, alpha, r_c, beta and theta_c from synthetic nu_bar).
#include "cdpile/analysis/fit.hpp"
#include "cdpile/analysis/studies.hpp"
#include "cdpile/error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <span>
#include <stdexcept>

using namespace cdpile;
using namespace cdpile::analysis;

namespace {
PileState state(std::int64_t n, std::int64_t nc) {
  PileState s;
  s.contacts = n;
  s.critical = nc;
  s.grains = 10;
  if (n > 0) s.nu = double(nc) / double(n);
  s.z = s.z_all = 2.0 * double(n) / 10.0;
  return s;
}

RunRecord small_run(const std::string& name, std::vector<std::int64_t> n,
                    std::vector<std::int64_t> nc) {
  RunRecord r;
  r.name = name;
  r.free_grains = 10;
  r.diameter = 1.0;
  r.mean_mass = 1.0;
  r.gravity = 1.0;
  r.recorded_rule = {default_eps, 0.5, 0.5};  // the counts follow the default rule
  for (std::size_t k = 0; k < n.size(); ++k) {
    r.steps.step.push_back(std::int64_t(k));
    r.steps.theta.push_back(0.1 * double(k));
    r.steps.contacts.push_back(n[k]);
    r.steps.critical.push_back(nc[k]);
    r.steps.kinetic_energy.push_back(0.0);
  }
  return r;
}
}  // namespace

TEST(CriticalStudy, StepsEventsEnsembleByHand) {
  // run a: N drops 10 -> 8 at step 2; run b: flat N
  RunRecord a = small_run("a", {10, 10, 8, 8}, {1, 2, 0, 1});
  RunRecord b = small_run("b", {10, 10, 10, 10}, {3, 4, 5, 6});
  CriticalOptions o;
  o.grid_step = 0.2;
  o.envelope_window = 0.2;
  Product p = critical_study({a, b}, o);
  EXPECT_EQ(std::get<std::string>(p.parameters.at("series")), "steps");
  const Table& ev = p.table("events");
  ASSERT_EQ(ev.rows(), 1u);
  EXPECT_EQ(*ev.column("peak_step").get(0), 1);
  EXPECT_DOUBLE_EQ(*ev.column("loss").get(0), 0.2);
  EXPECT_DOUBLE_EQ(*ev.column("nu_before").get(0), 0.2);  // step 1 of run a: 2/10
  // ensemble bins [0, 0.2): steps 0, 1; [0.2, 0.4]: steps 2, 3 (0.3 in the last bin)
  const Table& en = p.table("ensemble");
  ASSERT_EQ(en.rows(), 2u);
  // run a: (0.1 + 0.2)/2 = 0.15, run b: (0.3 + 0.4)/2 = 0.35 -> mean 0.25, se 0.1
  EXPECT_NEAR(*en.column("nu").get(0), 0.25, 1e-12);
  EXPECT_NEAR(*en.column("nu_se").get(0), 0.1, 1e-12);
  // envelope: maxima 0.2 and 0.4 -> 0.3
  EXPECT_NEAR(*p.table("envelope").column("envelope").get(0), 0.3, 1e-12);
  EXPECT_FALSE(p.result("nu_c"));  // too few windows to fit: a note, not a NaN
  const Table& st = p.table("steps");
  EXPECT_EQ(st.rows(), 8u);
  EXPECT_DOUBLE_EQ(*st.column("z_all").get(0), 2.0);
  // lambda = sqrt(2/(z nu)) with z = 2, nu = 0.1 -> sqrt(10) D
  EXPECT_NEAR(*st.column("lambda").get(0), std::sqrt(10.0), 1e-12);
  EXPECT_FALSE(st.column("lambda").get(2));  // nu = 0: infinite, missing
}

TEST(CriticalStudy, FramesSourceAndAvalancheCut) {
  RunRecord a = small_run("a", {10, 10, 10, 10, 10, 10}, {1, 1, 1, 1, 1, 1});
  a.steps.critical.clear();  // no per-step critical count: frames are the source
  a.steps.kinetic_energy = {0, 0, 0, 5e-3, 6e-3, 7e-3};  // per grain: /10 -> 5e-4.. with m g D = 1
  for (auto& e : a.steps.kinetic_energy) e *= 10;        // -> 5e-3 per grain
  // frame 1 carries its Ek per grain (m g D = 1); the others have no grain velocities
  a.frames = {{0, 0, 0.0, state(10, 1), std::nullopt},
              {1, 2, 0.2, state(10, 2), 3e-3},
              {2, 4, 0.4, state(10, 9), std::nullopt}};
  CriticalOptions o;
  o.avalanche = {1e-3, 0.1};
  Product p = critical_study({a}, o);
  EXPECT_EQ(std::get<std::string>(p.parameters.at("series")), "frames");
  EXPECT_FALSE(p.table("frames").column("Ek").get(0));
  EXPECT_DOUBLE_EQ(*p.table("frames").column("Ek").get(1), 3e-3);
  EXPECT_DOUBLE_EQ(*p.table("frames").column("ek_norm").get(1), 3e-3);
  EXPECT_EQ(p.table("frames").column("Ek").unit, "J m-1");
  EXPECT_NEAR(*p.table("runs").column("theta_c").get(0), 0.3, 1e-12);
  EXPECT_NEAR(*p.result("theta_c_deg"), 0.3, 1e-12);
  const Table& fr = p.table("frames");
  EXPECT_EQ(*fr.column("loading").get(2), 0);                       // theta 0.4 > theta_c
  EXPECT_DOUBLE_EQ(*p.table("runs").column("nu_max").get(0), 0.2);  // the cut frame is left out
  EXPECT_THROW(critical_study({a},
                              [] {
                                CriticalOptions x;
                                x.source = SeriesSource::steps;
                                return x;
                              }()),
               Error);
}

TEST(CriticalStudy, StepRuleMismatch) {
  const RecordedRule rec{1e-3, 0.5, 0.4};
  const Friction mu{0.5, 0.4};
  EXPECT_FALSE(step_rule_mismatch(rec, CriticalRule{}, mu));
  CriticalRule eps;
  eps.eps = 0.2;
  ASSERT_TRUE(step_rule_mismatch(rec, eps, mu));
  EXPECT_FALSE(step_rule_mismatch(rec, eps, mu)->unknown);
  EXPECT_EQ(step_rule_mismatch(rec, eps, mu)->why, "eps 0.2 asked, 0.001 recorded");
  EXPECT_EQ(step_rule_mismatch(rec, eps, {0.3, 0.4})->why,
            "eps 0.2 asked, 0.001 recorded; mu 0.3 asked, 0.5 recorded");
  // mu_wall matters only when wall contacts count (the recorded 'critical' then)
  EXPECT_FALSE(step_rule_mismatch(rec, CriticalRule{}, {0.5, 0.9}));
  CriticalRule walls;
  walls.include_walls = true;
  EXPECT_EQ(step_rule_mismatch(rec, walls, {0.5, 0.9})->why, "mu_wall 0.9 asked, 0.4 recorded");
  EXPECT_FALSE(step_rule_mismatch(rec, walls, mu));
  // critical_grain leaves contacts with glued floor grains out; with walls they all count
  CriticalRule floor;
  floor.floor_grains_are_walls = false;
  EXPECT_EQ(step_rule_mismatch(rec, floor, mu)->why,
            "floor grains counted as grains, not in critical_grain");
  floor.include_walls = true;
  EXPECT_FALSE(step_rule_mismatch(rec, floor, mu));
  // a run that does not record its rule (a pile of deposit has no critical_eps)
  ASSERT_TRUE(step_rule_mismatch({std::nullopt, 0.5, 0.4}, CriticalRule{}, mu));
  EXPECT_TRUE(step_rule_mismatch({std::nullopt, 0.5, 0.4}, CriticalRule{}, mu)->unknown);
  EXPECT_EQ(step_rule_mismatch({std::nullopt, 0.5, 0.4}, CriticalRule{}, mu)->why,
            "no critical_eps in /parameters");
  // the same values written as text and read back are the same
  EXPECT_FALSE(step_rule_mismatch({0.001, 0.5, 0.4}, CriticalRule{}, mu));
}

TEST(CriticalStudy, AnotherRuleThanTheRecordedTakesTheFrames) {
  // The per-step count follows eps = 1e-3 (nu 0.1, 0.2, 0.1, 0.1); the frames, classified
  // with the eps asked for, say nu = 0.5, 0.6. With eps = 0.2 the per-step counts are not
  // the asked rule's: auto takes the frames for nu_max, the ensemble and the events, and the
  // steps table has no Nc, nu or lambda.
  RunRecord a = small_run("a.h5", {10, 10, 8, 8}, {1, 2, 0, 1});
  a.frames = {{0, 0, 0.0, state(10, 5), std::nullopt}, {1, 1, 0.1, state(10, 6), std::nullopt}};
  CriticalOptions o;
  o.grid_step = 0.2;
  o.envelope_window = 0.2;
  o.rule.eps = 0.2;
  Product p = critical_study({a}, o);
  EXPECT_EQ(std::get<std::string>(p.parameters.at("series")), "frames");
  EXPECT_DOUBLE_EQ(*p.table("runs").column("nu_max").get(0), 0.6);
  EXPECT_DOUBLE_EQ(*p.table("events").column("nu_before").get(0), 0.6);  // frame 1, the peak's step
  EXPECT_DOUBLE_EQ(*p.table("ensemble").column("nu").get(0), 0.55);
  const Table& st = p.table("steps");
  for (std::size_t k = 0; k < st.rows(); ++k) {
    EXPECT_FALSE(st.column("Nc").get(k));
    EXPECT_FALSE(st.column("nu").get(k));
    EXPECT_FALSE(st.column("lambda").get(k));
  }
  EXPECT_EQ(*st.column("N").get(2), 8);
  const std::string note =
      "a.h5 recorded its per-step critical count with another rule (eps 0.2 asked, 0.001 "
      "recorded): its "
      "per-step Nc, nu and lambda are NA and nu(theta) comes from its frames unless --series "
      "sliding";
  EXPECT_NE(std::find(p.notes.begin(), p.notes.end(), note), p.notes.end());
  // the same eps as recorded: the per-step series
  o.rule.eps = default_eps;
  EXPECT_EQ(std::get<std::string>(critical_study({a}, o).parameters.at("series")), "steps");
  // asked for explicitly with another rule: a usage error; with an unrecorded rule: a data error
  o.rule.eps = 0.2;
  o.source = SeriesSource::steps;
  try {
    critical_study({a}, o);
    FAIL();
  } catch (const UsageError& e) {
    EXPECT_EQ(std::string(e.what()),
              "--series steps: a.h5 recorded its per-step critical count with another rule (eps "
              "0.2 asked, "
              "0.001 recorded); use --series frames or auto");
  }
  o.rule.eps = default_eps;
  a.recorded_rule.eps.reset();
  EXPECT_THROW(critical_study({a}, o), Error);
  o.source = SeriesSource::automatic;
  EXPECT_EQ(std::get<std::string>(critical_study({a}, o).parameters.at("series")), "frames");
}

TEST(CriticalStudy, EnvelopeFitRecoversNuC) {
  // 15 runs whose nu fluctuates below an envelope nu_c - B exp(-theta/tau)
  const double nu_c = 0.08, B = 0.07, tau = 4.0;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<RunRecord> runs;
  for (int r = 0; r < 15; ++r) {
    RunRecord run;
    run.name = "r" + std::to_string(r);
    run.free_grains = 4000;
    run.diameter = 1;
    run.recorded_rule = {default_eps, 0.5, 0.5};
    for (int k = 0; k <= 20000; ++k) {
      const double th = 0.001 * k;
      run.steps.step.push_back(k);
      run.steps.theta.push_back(th);
      run.steps.contacts.push_back(7200);
      const double env = nu_c - B * std::exp(-th / tau);
      // nu = env * (1 - small random depth); maxima over a window approach env
      const double nu = env * (1.0 - 0.2 * u(rng));
      run.steps.critical.push_back(std::llround(nu * 7200));
    }
    runs.push_back(std::move(run));
  }
  CriticalOptions o;
  o.step_table = false;
  Product p = critical_study(runs, o);
  ASSERT_TRUE(p.result("nu_c")) << (p.notes.empty() ? "" : p.notes.back());
  ASSERT_TRUE(p.result("nu_c_se"));
  // the maxima of ~500 steps per window sit within 0.1 % of the envelope
  EXPECT_NEAR(*p.result("nu_c"), nu_c, 0.01 * nu_c);
  EXPECT_LT(std::abs(*p.result("nu_c") - nu_c), 3 * *p.result("nu_c_se") + 0.002 * nu_c);
  EXPECT_GT(*p.result("envelope_tau_deg"), 2.0);
  EXPECT_LT(*p.result("envelope_tau_deg"), 6.0);
  EXPECT_EQ(*p.result("envelope_saturates"), 1.0);
}

TEST(CriticalStudy, EnvelopeThatDoesNotSaturateGivesNoNuC) {
  // nu rising linearly to the end (a small pile tilted fast): an exponential fits it with
  // tau far beyond the data, so the "limit" would be an extrapolation, not nu_c.
  std::vector<RunRecord> runs;
  for (int r = 0; r < 3; ++r) {
    RunRecord run;
    run.name = "r" + std::to_string(r);
    run.free_grains = 300;
    run.diameter = 1;
    run.recorded_rule = {default_eps, 0.5, 0.5};
    for (int k = 0; k <= 1500; ++k) {
      const double th = 0.01 * k;
      run.steps.step.push_back(k);
      run.steps.theta.push_back(th);
      run.steps.contacts.push_back(1000);
      run.steps.critical.push_back(
          std::llround(1000 * 0.012 * th * (1.0 - 0.05 * ((k + r) % 7) / 7.0)));
    }
    runs.push_back(std::move(run));
  }
  CriticalOptions o;
  o.step_table = false;
  Product p = critical_study(runs, o);
  EXPECT_FALSE(p.result("nu_c"));
  EXPECT_FALSE(p.result("lambda_c_D"));
  ASSERT_TRUE(p.result("envelope_saturates"));
  EXPECT_EQ(*p.result("envelope_saturates"), 0.0);
  ASSERT_FALSE(p.notes.empty());
  EXPECT_NE(p.notes.back().find("envelope does not saturate in the fitted range"),
            std::string::npos)
      << p.notes.back();
  // the reading is named, and critical's closing line agrees with the product: no nu_c
  EXPECT_EQ(p.notes.back().rfind("nu_c (every state) not determined: the envelope", 0), 0u)
      << p.notes.back();
  EXPECT_EQ(critical_readings(p).find("nu_c = "), std::string::npos) << critical_readings(p);
  EXPECT_NE(critical_readings(p).find("nu_c, nu_c_static, nu_c_rest not determined"),
            std::string::npos)
      << critical_readings(p);
}

TEST(CriticalStudy, ReadingsLineSaysWhatTheProductHolds) {
  // the line critical ends with: determined exactly when the result is there, 6 digits
  Product p;
  p.kind = "critical";
  p.results["theta_c_deg"] = 17.400000000000002;
  p.results["nu_c"] = 0.20639228641070728;
  p.results["nu_c_se"] = 0.007718361517636802;
  p.results["nu_c_static"] = 0.14611254075191227;
  EXPECT_EQ(critical_readings(p),
            "theta_c = 17.4 deg; nu_c = 0.206392 +- 0.00771836 (every state), nu_c_static = "
            "0.146113 (static states); nu_c_rest not determined");
  p.results["nu_c_rest"] = 0.1;
  p.results["nu_c_rest_se"] = 0.02;
  EXPECT_EQ(critical_readings(p),
            "theta_c = 17.4 deg; nu_c = 0.206392 +- 0.00771836 (every state), nu_c_static = "
            "0.146113 (static states), nu_c_rest = 0.1 +- 0.02 (contacts at rest)");
}

TEST(CriticalStudy, TableNamesKnownBeforehand) {
  // critical refuses an unknown --table before reading its runs from this list
  for (bool steps : {true, false}) {
    CriticalOptions o;
    o.step_table = steps;
    const Product p = critical_study({small_run("a", {10, 10}, {1, 2})}, o);
    std::vector<std::string> made;
    for (const Table& t : p.tables) made.push_back(t.name);
    EXPECT_EQ(made, critical_table_names(o));
  }
}

TEST(CriticalStudy, EmptyInputsGiveEmptyTables) {
  Product p = critical_study({}, {});
  EXPECT_EQ(p.table("ensemble").rows(), 0u);
  RunRecord r;
  r.name = "empty";
  Product q = critical_study({r}, {});
  EXPECT_EQ(q.table("frames").rows(), 0u);
  EXPECT_EQ(q.table("runs").rows(), 1u);
  EXPECT_FALSE(q.table("runs").column("theta_c").get(0));
}

namespace {
// Five contacts on a line 1 apart, contacts 0 and 3 critical (as in test_analysis_local_state).
ContactSet line_set() {
  ContactSet s;
  for (int k = 0; k < 5; ++k) {
    s.row.push_back(k);
    s.i.push_back(k);
    s.j.push_back(k + 1);
    s.point.emplace_back(k, 0);
    s.critical.push_back(k == 0 || k == 3);
    s.sliding.push_back(0);
    s.mobilisation.push_back(k == 0 || k == 3 ? 1.0 : 0.5);
  }
  return s;
}
}  // namespace

TEST(LocalNuStudy, StatesAndPdfsByHand) {
  LocalNuOptions o;
  o.radii = {1.0, 2.5};
  o.pdf_radius = 1.0;
  o.pdf_bins = 4;
  o.map_spacing = 2.0;
  o.map_radius = 1.0;
  o.per_contact = true;
  LocalNuStudy s(o);
  s.add_frame(0, "line", 7, 70, 1.5, 1.0, line_set(), true, true);
  Product p = s.product();
  const Table& st = p.table("states");
  ASSERT_EQ(st.rows(), 2u);
  EXPECT_EQ(*st.column("n").get(0), 2);
  EXPECT_DOUBLE_EQ(*st.column("nu_bar").get(0), (0.5 + 1.0 / 3.0) / 2.0);
  EXPECT_DOUBLE_EQ(*st.column("nu_bar").get(1), (1.0 / 3.0 + 0.25) / 2.0);
  EXPECT_DOUBLE_EQ(*st.column("sum2").get(0), 0.25 + 1.0 / 9.0);
  const Table& pdf = p.table("pdf");
  EXPECT_EQ(*pdf.column("count_c").get(1), 1);
  EXPECT_EQ(*pdf.column("count_c").get(2), 1);
  EXPECT_EQ(*pdf.column("count_nc").get(1), 2);
  EXPECT_DOUBLE_EQ(*pdf.column("P_c").get(1), 2.0);
  const Table& map = p.table("map");
  ASSERT_EQ(map.rows(), 3u);
  EXPECT_DOUBLE_EQ(*map.column("nu").get(1), 1.0 / 3.0);
  EXPECT_EQ(*map.column("above").get(1), 1);  // 1/3 >= 0.08
  const Table& c = p.table("contacts");
  EXPECT_DOUBLE_EQ(*c.column("nu_r2.5").get(2), 0.4);
  EXPECT_EQ(*p.table("frames").column("Nc").get(0), 2);
}

TEST(LocalNuStudy, FrameWithoutCriticalContactsHasNoNuBar) {
  LocalNuStudy s(default_localnu_options());
  ContactSet set = line_set();
  set.critical.assign(5, 0);
  s.add_frame(0, "x", 0, 0, std::nullopt, 1.0, set, true, false);
  s.add_frame(0, "x", 1, 1, std::nullopt, 1.0, ContactSet{}, true, false);  // empty frame
  Product p = s.product();
  const Table& st = p.table("states");
  EXPECT_EQ(st.rows(), 40u);
  for (std::size_t r = 0; r < st.rows(); ++r) EXPECT_FALSE(st.column("nu_bar").get(r));
  EXPECT_FALSE(p.table("pdf").column("P_c").get(0));  // empty pdf: missing, not NaN
  EXPECT_FALSE(p.table("frames").column("nu").get(1));
}

TEST(Correlate, PoolsFramesAndRunsByHand) {
  LocalNuOptions o;
  o.radii = {1.0};
  LocalNuStudy s(o);
  ContactSet a = line_set();  // nu_i(1) of critical contacts: 1/2, 1/3
  ContactSet b = line_set();
  b.critical = {1, 0, 0, 0, 0};  // nu_0(1) = 1/2 only
  s.add_frame(0, "r0", 0, 0, 0.2, 1.0, a, true, false);
  s.add_frame(0, "r0", 1, 1, 0.7, 1.0, b, true, false);
  s.add_frame(1, "r1", 0, 0, 0.4, 1.0, b, true, false);
  s.add_frame(1, "r1", 1, 1, 1.5, 1.0, a, true, false);
  Product lp = s.product();
  CorrelateOptions co;
  co.window = 1.0;
  Product c = correlate(lp, co);
  const Table& w = c.table("windows");
  ASSERT_EQ(w.rows(), 2u);
  // window [0, 1): run 0 frames 0, 1 -> sums 5/6 (n 2) + 1/2 (n 1); run 1 frame 0 -> 1/2
  // pooled mean = (5/6 + 1/2 + 1/2) / 4 = 11/24
  EXPECT_NEAR(*w.column("nu_bar").get(0), 11.0 / 24.0, 1e-15);
  EXPECT_EQ(*w.column("runs").get(0), 2);
  EXPECT_EQ(*w.column("frames").get(0), 3);
  EXPECT_EQ(*w.column("n").get(0), 4);
  EXPECT_EQ(w.column("se_over").text[0], "runs");
  // clusters: run 0: S = 4/3, N = 3; run 1: S = 1/2, N = 1; mean m = 11/24
  const double m = 11.0 / 24.0;
  const double d0 = 4.0 / 3.0 - 3 * m, d1 = 0.5 - m;
  EXPECT_NEAR(*w.column("se").get(0), std::sqrt(2.0 * (d0 * d0 + d1 * d1)) / 4.0, 1e-15);
  EXPECT_NEAR(*w.column("theta").get(0), (0.2 + 0.7 + 0.4) / 3.0, 1e-15);
  // window [1, 2): one frame of one run -> se over contacts
  EXPECT_NEAR(*w.column("nu_bar").get(1), 5.0 / 12.0, 1e-15);
  EXPECT_EQ(w.column("se_over").text[1], "contacts");
  EXPECT_EQ(c.table("frames").rows(), 4u);
}

namespace {
// A correlate product whose nu_bar follows eq (4) exactly, with A(theta) and alpha(theta)
// affine and nu_inf(theta) chosen so that r_c = C (theta_c - theta)^-beta (eq 5).
Product synthetic_correlate_rc(double nu_c, const std::function<double(double)>& rc_of,
                               double noise, unsigned seed);
Product synthetic_correlate(double nu_c, double theta_c, double beta, double c, double noise,
                            unsigned seed) {
  return synthetic_correlate_rc(
      nu_c, [=](double th) { return c * std::pow(theta_c - th, -beta); }, noise, seed);
}
Product synthetic_correlate_rc(double nu_c, const std::function<double(double)>& rc_of,
                               double noise, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  Product p;
  p.kind = "correlate";
  Table& w = p.add_table("windows", "");
  for (const char* n :
       {"theta", "theta_lo", "theta_hi", "r", "nu_bar", "se", "nu_pile", "nu_pile_se"})
    w.add_column(n, "");
  for (double th = 2.0; th <= 19.0 + 1e-9; th += 1.0) {
    const double a = 1.0 + 0.05 * th, alpha = -1.8 + 0.02 * th;
    const double rc = rc_of(th);
    const double q = a * std::pow(rc, alpha);  // nu_c/nu_inf - 1
    const double nu_inf = nu_c / (1.0 + q);
    for (double r = 1.0; r <= 20.0; r += 1.0) {
      const double nb = r <= 10.0 ? nu_inf * (1.0 + a * std::pow(r, alpha)) : nu_inf;
      const double se = noise * nb;
      w.column("theta").add(th);
      w.column("theta_lo").add(th - 0.5);
      w.column("theta_hi").add(th + 0.5);
      w.column("r").add(r);
      w.column("nu_bar").add(nb + se * g(rng));
      w.column("se").add(se);
      w.column("nu_pile").add(nu_inf);
      w.column("nu_pile_se").add(std::optional<double>());
    }
  }
  return p;
}
}  // namespace

TEST(ClusterFit, RecoversAAlphaAndTheDivergence) {
  const double nu_c = 0.08, theta_c = 19.96, beta = 0.5, c = 6.0;
  Product cor = synthetic_correlate(nu_c, theta_c, beta, c, 0.002, 3);
  ClusterFitOptions o;
  o.nu_c = nu_c;
  o.power = {12.0, 100.0};
  Product p = clusterfit(cor, nullptr, o);
  const Table& f = p.table("fits");
  ASSERT_EQ(f.rows(), 18u);
  for (std::size_t k = 0; k < f.rows(); ++k) {
    ASSERT_EQ(*f.column("converged").get(k), 1) << k;
    const double th = *f.column("theta").get(k);
    EXPECT_LT(std::abs(*f.column("A").get(k) - (1.0 + 0.05 * th)), 4 * *f.column("A_se").get(k))
        << th;
    EXPECT_LT(std::abs(*f.column("alpha").get(k) - (-1.8 + 0.02 * th)),
              4 * *f.column("alpha_se").get(k))
        << th;
    const double rc = c * std::pow(theta_c - th, -beta);
    ASSERT_TRUE(f.column("r_c").get(k));
    EXPECT_LT(std::abs(*f.column("r_c").get(k) - rc), 4 * *f.column("r_c_se").get(k)) << th;
  }
  const Table& a = p.table("affine");
  ASSERT_EQ(a.rows(), 2u);
  EXPECT_LT(std::abs(*a.column("c1").get(0) - 0.05), 4 * *a.column("c1_se").get(0));
  EXPECT_LT(std::abs(*a.column("c1").get(1) - 0.02), 4 * *a.column("c1_se").get(1));
  ASSERT_TRUE(p.result("beta") && p.result("beta_se"));
  EXPECT_LT(std::abs(*p.result("beta") - beta), 3 * *p.result("beta_se"));
  EXPECT_LT(std::abs(*p.result("theta_c_deg") - theta_c), 3 * *p.result("theta_c_se_deg"));

  // theta_c given: beta alone
  o.theta_c = theta_c;
  Product q = clusterfit(cor, nullptr, o);
  EXPECT_LT(std::abs(*q.result("beta") - beta), 3 * *q.result("beta_se"));
  EXPECT_EQ(std::get<std::int64_t>(q.results.at("theta_c_fitted")), 0);
}

TEST(ClusterFit, ThetaCOnTheLastAngleIsDegenerateNotABeta) {
  // r_c that fluctuates without growing over the power range (as in one noisy run): the
  // fit drives theta_c onto the last window, where any beta "fits"; no beta is reported.
  const double rcs[] = {3.377, 2.345, 4.243, 2.385};
  // Windows run to 19 deg, outside the power range: its r_c repeats the last (it read
  // past the array before, found by the asan preset's UBSan).
  auto rc_of = [&](double th) {
    return th < 15.0 ? 2.0 : rcs[std::min(static_cast<int>(th) - 15, 3)];
  };
  Product cor = synthetic_correlate_rc(0.08, rc_of, 0.0, 1);
  ClusterFitOptions o;
  o.nu_c = 0.08;
  o.power = {15.0, 18.5};
  Product p = clusterfit(cor, nullptr, o);
  EXPECT_FALSE(p.result("beta"));
  ASSERT_TRUE(p.result("power_degenerate"));
  EXPECT_EQ(*p.result("power_degenerate"), 1.0);
  // the same windows with theta_c given: an ordinary fit of beta
  o.theta_c = 20.0;
  Product q = clusterfit(cor, nullptr, o);
  EXPECT_TRUE(q.result("beta"));
  EXPECT_FALSE(q.result("power_degenerate"));
}

TEST(ClusterFit, NuInfFromTheCriticalEnsemble) {
  Product cor = synthetic_correlate(0.08, 19.96, 0.5, 6.0, 0.001, 4);
  Product crit;
  crit.kind = "critical";
  crit.results["nu_c"] = 0.08;
  Table& e = crit.add_table("ensemble", "");
  for (const char* n : {"theta", "nu", "nu_se"}) e.add_column(n, "");
  const Table& w = cor.table("windows");
  for (std::size_t k = 0; k < w.rows(); k += 20) {  // one bin per window, at its centre
    e.column("theta").add(*w.column("theta").get(k));
    e.column("nu").add(*w.column("nu_pile").get(k));
    e.column("nu_se").add(1e-4);
  }
  Product p = clusterfit(cor, &crit, {});
  EXPECT_EQ(std::get<std::string>(p.parameters.at("nu_inf")), "ensemble");
  const Table& f = p.table("fits");
  EXPECT_NEAR(*f.column("nu_inf").get(0), *w.column("nu_pile").get(0), 1e-15);
  EXPECT_NEAR(*f.column("nu_inf_se").get(0), 1e-4, 1e-15);
  EXPECT_TRUE(p.result("beta"));
}

TEST(ClusterFit, NothingToFitIsADocumentedEmptyResult) {
  Product cor;
  cor.kind = "correlate";
  Table& w = cor.add_table("windows", "");
  for (const char* n : {"theta", "theta_lo", "theta_hi", "r", "nu_bar", "se"}) w.add_column(n, "");
  Product p = clusterfit(cor, nullptr, {});
  EXPECT_EQ(p.table("fits").rows(), 0u);
  EXPECT_FALSE(p.result("beta"));
  // a window whose pile has no critical contact (nu_inf = 0) is not fitted, not NaN
  Product c2 = synthetic_correlate(0.08, 19.96, 0.5, 6.0, 0.001, 1);
  for (auto& v : c2.tables[0].column("nu_pile").num) v = 0.0;
  Product q = clusterfit(c2, nullptr, {});
  EXPECT_EQ(*q.table("fits").column("converged").get(0), 0);
  EXPECT_FALSE(q.table("fits").column("A").get(0));
  EXPECT_THROW(clusterfit(c2, nullptr,
                          [] {
                            ClusterFitOptions x;
                            x.nu_inf = NuInfSource::ensemble;
                            return x;
                          }()),
               Error);
}

namespace {
// One run whose per-step nu has, in each 0.5 deg envelope window (50 steps), its maximum at
// step 50 b + 25 on a saturating envelope; frames every 10 steps (steps 0 to 1999, theta 0 to 19.99
// deg). `above(step)` says which frames are above their static bound.
RunRecord bound_run(const std::function<bool(std::int64_t)>& above) {
  RunRecord run;
  run.name = "r";
  run.free_grains = 4000;
  run.diameter = 1;
  run.recorded_rule = {default_eps, 0.5, 0.5};
  for (std::int64_t k = 0; k < 2000; ++k) {
    const double th = 0.01 * static_cast<double>(k);
    const double env = 0.08 - 0.07 * std::exp(-th / 4.0);
    run.steps.step.push_back(k);
    run.steps.theta.push_back(th);
    run.steps.contacts.push_back(7200);
    run.steps.critical.push_back(std::llround((k % 50 == 25 ? 1.0 : 0.5) * env * 7200));
    if (k % 10 == 0) {
      FrameRecord f{k / 10, k, th, state(7200, 0), std::nullopt, StaticBound{}};
      f.bound->contacts = 7200;
      f.bound->grains = 4000;                      // B = 14400 - 12000 = 2400
      f.bound->critical = above(k) ? 2401 : 2400;  // at the bound is static
      run.frames.push_back(f);
    }
  }
  return run;
}
}  // namespace

TEST(CriticalStudy, StaticBoundColumnsAndNuCWarning) {
  CriticalOptions o;
  o.step_table = false;
  // The maxima are at steps 50 b + 25; the frame judged is the last at or before: 50 b + 20.
  Product p = critical_study({bound_run([](std::int64_t k) { return k % 50 == 20; })}, o);
  ASSERT_TRUE(p.result("nu_c")) << (p.notes.empty() ? "" : p.notes.back());
  const Table& fr = p.table("frames");
  ASSERT_EQ(fr.rows(), 200u);
  EXPECT_EQ(*fr.column("contacts_load_bearing").get(2), 7200);
  EXPECT_EQ(*fr.column("grains_load_bearing").get(2), 4000);
  EXPECT_EQ(*fr.column("critical_load_bearing").get(2), 2401);  // step 20
  EXPECT_EQ(*fr.column("static_bound").get(2), 2400);
  EXPECT_EQ(*fr.column("above_static_bound").get(2), 1);
  EXPECT_EQ(*fr.column("above_static_bound").get(3), 0);
  EXPECT_EQ(*p.result("static_bound_frames"), 200);
  EXPECT_EQ(*p.result("static_bound_frames_above"), 40);  // steps 20, 70, ..., 1970
  // 40 windows [0.5 b, 0.5 (b + 1)), every one in the fit, each judged above
  EXPECT_EQ(*p.result("nu_c_maxima_judged"), 40);
  EXPECT_EQ(*p.result("nu_c_maxima_above_static_bound"), 40);
  const auto w = product_warnings(p);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("nu_c comes from frames above the static bound: 40 of the 40"),
            std::string::npos)
      << w[0];
  EXPECT_NE(w[0].find("40 of 200 frames"), std::string::npos) << w[0];

  // Frames just after the maxima above their bound do not make nu_c's maxima suspect.
  Product q = critical_study({bound_run([](std::int64_t k) { return k % 50 == 30; })}, o);
  ASSERT_TRUE(q.result("nu_c"));
  EXPECT_EQ(*q.result("static_bound_frames_above"), 40);
  EXPECT_EQ(*q.result("nu_c_maxima_above_static_bound"), 0);
  EXPECT_TRUE(product_warnings(q).empty());

  // Frames without a bound (e.g. built by hand): NA columns, nothing judged, no warning.
  RunRecord r = bound_run([](std::int64_t) { return true; });
  for (FrameRecord& f : r.frames) f.bound.reset();
  Product u = critical_study({r}, o);
  EXPECT_FALSE(u.table("frames").column("static_bound").get(0));
  EXPECT_FALSE(u.result("static_bound_frames"));
  EXPECT_EQ(*u.result("nu_c_maxima_judged"), 0);
  EXPECT_TRUE(product_warnings(u).empty());
}

// Static and moving states (docs/analysis.md): nu read over every state and over static
// ones. A pile whose envelope is env(theta) = 0.08 - 0.07 exp(-theta/4): at rest at
// 0.5 env, and once every 50 steps a moving step (grains at 0.5 sqrt(g D)) at env, the
// maxima today's reading takes. From theta = 19.5 deg the pile flows (theta_c).
TEST(CriticalStudy, StaticStatesAreReadApartFromMovingOnes) {
  RunRecord run;
  run.name = "r";
  run.free_grains = 4000;
  run.diameter = 1.0;
  run.mean_mass = 1.0;
  run.gravity = 1.0;
  run.recorded_rule = {default_eps, 0.5, 0.5};
  auto env = [](double th) { return 0.08 - 0.07 * std::exp(-th / 4.0); };
  for (std::int64_t k = 0; k < 2100; ++k) {
    const double th = 0.01 * static_cast<double>(k);
    const bool moving = k % 50 == 25;
    const bool flowing = th >= 19.5;
    run.steps.step.push_back(k + 1);
    run.steps.theta.push_back(th);
    run.steps.contacts.push_back(7200);
    run.steps.critical.push_back(std::llround((moving ? 1.0 : 0.5) * env(th) * 7200));
    run.steps.kinetic_energy.push_back(flowing ? 4000.0 * 1.0 : 0.0);  // Ek/(m g D) = 1 per grain
    run.steps.rotational_energy.push_back(0.0);
    run.steps.converged.push_back(1);
    run.steps.max_speed.push_back(moving ? 0.5 : 0.0);
    run.steps.grains_without_contact.push_back(0);
    if (k % 10 == 0) {
      FrameRecord f{k / 10, k + 1,        th, state(7200, std::llround(0.5 * env(th) * 7200)),
                    0.0,    StaticBound{}};
      f.agitation = flowing ? 1.0 : 0.0;
      f.max_speed = 0.0;
      // the contacts at rest hold a fourth of the critical ones of the pile at rest
      f.contacts_at_rest = 3600;
      f.critical_at_rest = std::llround(0.25 * 0.5 * env(th) * 3600);
      run.frames.push_back(f);
    }
  }
  // One step of the static part misses its criterion, another has a grain in flight.
  run.steps.converged[100] = 0;
  run.steps.grains_without_contact[101] = 3;
  CriticalOptions o;
  o.avalanche.threshold = 0.5;
  Product p = critical_study({run}, o);
  ASSERT_TRUE(p.result("theta_c_deg"));
  EXPECT_NEAR(*p.result("theta_c_deg"), 19.5, 1e-9);
  const Table& st = p.table("steps");
  EXPECT_EQ(*st.column("static").get(0), 1);
  EXPECT_EQ(*st.column("static").get(25), 0);    // moving
  EXPECT_EQ(*st.column("static").get(100), 0);   // unconverged
  EXPECT_EQ(*st.column("static").get(101), 0);   // a grain in flight
  EXPECT_EQ(*st.column("static").get(2000), 0);  // flowing
  // 1951 loading steps (theta <= 19.5): 39 moving (k = 25, 75, ..., 1925), 2 others and
  // the step at theta_c, which flows
  EXPECT_EQ(*p.result("static_steps"), 1951 - 39 - 2 - 1);
  const Table& fr = p.table("frames");
  EXPECT_EQ(*fr.column("static").get(10), 0);  // its step (101, k = 100) did not converge
  EXPECT_EQ(*fr.column("static").get(11), 1);
  EXPECT_EQ(*fr.column("static").get(10 * 0 + 200), 0);  // frame 200 at theta 20: flowing
  // Today's reading follows the moving maxima to 0.08, the static one the pile at rest to 0.04.
  ASSERT_TRUE(p.result("nu_c") && p.result("nu_c_static")) << p.notes.back();
  EXPECT_NEAR(*p.result("nu_c"), 0.08, 2e-3);
  EXPECT_NEAR(*p.result("nu_c_static"), 0.04, 2e-3);
  // The paper's reading: the mean static nu over [19.0, 19.5] deg.
  double sum = 0.0;
  int m = 0;
  const double theta_c = *p.result("theta_c_deg");
  for (std::int64_t k = 0; k < 1950; ++k) {
    const double th = 0.01 * static_cast<double>(k);
    if (k % 50 != 25 && th >= theta_c - 0.5) {
      sum += static_cast<double>(std::llround(0.5 * env(th) * 7200)) / 7200.0;
      ++m;
    }
  }
  EXPECT_EQ(m, 49);
  ASSERT_TRUE(p.result("nu_theta_c"));
  EXPECT_NEAR(*p.result("nu_theta_c"), sum / m, 1e-12);
  const Table& en = p.table("ensemble");
  EXPECT_EQ(*en.column("runs_static").get(0), 1);
  // The reading over contacts at rest, from the frames: 0.25 of the static one.
  ASSERT_TRUE(p.result("nu_c_rest")) << p.notes.back();
  EXPECT_NEAR(*p.result("nu_c_rest"), 0.01, 1e-3);
  EXPECT_NEAR(*fr.column("nu_rest").get(11),
              static_cast<double>(std::llround(0.125 * env(1.1) * 3600)) / 3600.0,
              1e-12);  // frame 11: theta 1.1
}

namespace {
struct PairRow {
  std::string name;
  std::int64_t count;
  std::optional<double> share;
};
const ColumnSpec<PairRow> pair_columns[] = {
    {"name", "", ColumnKind::text, [](const PairRow& x) -> Cell { return x.name; }},
    {"count", "", ColumnKind::integer, [](const PairRow& x) -> Cell { return x.count; }},
    {"share", "", ColumnKind::real, [](const PairRow& x) -> Cell { return x.share; }},
};
const ColumnSpec<PairRow> wrong_kind[] = {
    {"count", "", ColumnKind::text, [](const PairRow& x) -> Cell { return x.count; }},
};
}  // namespace

TEST(Table, DeclaredOnceLaidOutAndWrittenFromOneList) {
  Table t;
  t.name = "pairs";
  declare_columns(t, std::span<const ColumnSpec<PairRow>>(pair_columns));
  ASSERT_EQ(t.columns.size(), 3u);
  EXPECT_EQ(t.columns[1].name, "count");
  EXPECT_EQ(t.columns[1].kind, ColumnKind::integer);
  add_row(t, std::span<const ColumnSpec<PairRow>>(pair_columns), PairRow{"a", 3, 0.25});
  add_row(t, std::span<const ColumnSpec<PairRow>>(pair_columns), PairRow{"b", 1, std::nullopt});
  add_row(t, std::span<const ColumnSpec<PairRow>>(pair_columns),
          PairRow{"c", 0, std::numeric_limits<double>::infinity()});
  EXPECT_EQ(t.rows(), 3u);
  EXPECT_EQ(t.column("name").text[1], "b");
  EXPECT_EQ(t.column("count").num[0], 3.0);
  EXPECT_EQ(*t.column("share").get(0), 0.25);
  EXPECT_FALSE(t.column("share").defined(1));  // missing
  EXPECT_FALSE(t.column("share").defined(2));  // not finite: missing, never inf in a file
  // a list given to a table that has other columns, a cell of another kind: refused
  EXPECT_THROW(declare_columns(t, std::span<const ColumnSpec<PairRow>>(pair_columns)),
               std::logic_error);
  Table u;
  u.name = "wrong";
  declare_columns(u, std::span<const ColumnSpec<PairRow>>(wrong_kind));
  EXPECT_THROW(add_row(u, std::span<const ColumnSpec<PairRow>>(wrong_kind), PairRow{"a", 1, 0.0}),
               std::logic_error);
  EXPECT_THROW(add_row(u, std::span<const ColumnSpec<PairRow>>(pair_columns), PairRow{"a", 1, 0.0}),
               std::logic_error);
}
