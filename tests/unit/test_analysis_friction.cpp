// The friction coefficients of an analysis, decided in one place (analysis::choose_friction):
// the value given, else the run's, else an error naming the file and what is missing.
#include "cdpile/analysis/run_record.hpp"
#include "cdpile/error.hpp"

#include <gtest/gtest.h>

#include <string>

using namespace cdpile;
using namespace cdpile::analysis;

namespace {
// The message of the exception E that f throws ("" if none).
template <class E, class F>
std::string message_of(F f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(Friction, TheRunsValuesByDefault) {
  const RecordedRule run{0.001, 0.4, 0.3};
  const Friction mu = choose_friction({}, &run, "run.h5");
  EXPECT_EQ(mu.grain, 0.4);
  EXPECT_EQ(mu.wall, 0.3);
}

TEST(Friction, WithoutTheRunsMuWallTheGrainsServes) {
  const RecordedRule run{{}, 0.4, {}};
  const Friction mu = choose_friction({}, &run, "run.h5");
  EXPECT_EQ(mu.grain, 0.4);
  EXPECT_EQ(mu.wall, 0.4);
}

TEST(Friction, GivenValuesOverTheRuns) {
  const RecordedRule run{0.001, 0.4, 0.3};
  // --mu alone: the wall's too (not the run's mu_wall)
  Friction mu = choose_friction({0.6, {}}, &run, "run.h5");
  EXPECT_EQ(mu.grain, 0.6);
  EXPECT_EQ(mu.wall, 0.6);
  mu = choose_friction({0.6, 0.2}, &run, "run.h5");
  EXPECT_EQ(mu.grain, 0.6);
  EXPECT_EQ(mu.wall, 0.2);
  // --mu-wall alone: the run's mu_grain
  mu = choose_friction({{}, 0.2}, &run, "run.h5");
  EXPECT_EQ(mu.grain, 0.4);
  EXPECT_EQ(mu.wall, 0.2);
  // a contact table (no parameters) with --mu
  mu = choose_friction({0.5, {}}, nullptr, "t.tsv");
  EXPECT_EQ(mu.grain, 0.5);
  EXPECT_EQ(mu.wall, 0.5);
}

TEST(Friction, WhatIsMissingIsNamed) {
  const RecordedRule none{0.001, {}, 0.3};
  EXPECT_EQ(message_of<Error>([&] { choose_friction({}, &none, "run.h5"); }),
            "run.h5: /parameters: no mu_grain; give --mu");
  EXPECT_EQ(message_of<Error>([&] { choose_friction({}, nullptr, "t.tsv"); }),
            "t.tsv: a contact table has no friction coefficient; give --mu");
}

TEST(Friction, MuMustBePositive) {
  const RecordedRule zero{{}, 0.0, 0.3}, zero_wall{{}, 0.4, 0.0};
  EXPECT_EQ(message_of<Error>([&] { choose_friction({}, &zero, "run.h5"); }),
            "run.h5: /parameters: mu_grain must be > 0, got 0");
  EXPECT_EQ(message_of<Error>([&] { choose_friction({}, &zero_wall, "run.h5"); }),
            "run.h5: /parameters: mu_wall must be > 0, got 0");
  const RecordedRule run{{}, 0.4, 0.3};
  EXPECT_EQ(message_of<UsageError>([&] {
              choose_friction({0.0, {}}, &run, "run.h5");
            }),
            "--mu must be > 0 (mu = 0 makes every active contact critical), got 0");
  EXPECT_EQ(message_of<UsageError>([&] {
              choose_friction({0.5, 0.0}, &run, "run.h5");
            }),
            "--mu-wall must be > 0 (mu = 0 makes every active contact critical), got 0");
}

TEST(Friction, AViewFlagsByTheEpsGivenElseTheRunsElseTheDefault) {
  const Friction mu{0.5, 0.5};
  const RecordedRule recorded{0.01, 0.5, 0.5}, silent{{}, 0.5, 0.5};
  EXPECT_EQ(view_rule(0.2, false, recorded, mu).eps, 0.2);
  EXPECT_EQ(view_rule(std::nullopt, false, recorded, mu).eps, 0.01);
  EXPECT_EQ(view_rule(std::nullopt, false, silent, mu).eps, default_eps);
  EXPECT_TRUE(view_rule(std::nullopt, true, silent, mu).include_walls);
  EXPECT_THROW(view_rule(1.0, false, silent, mu), Error);  // eps must be below 1
}
