// The options shared by the analysis tools: one declaration, one reading.
#include "cdpile/cli/analysis_options.hpp"

#include <gtest/gtest.h>

using namespace cdpile;

namespace {
cli::Args parse(const std::vector<std::string>& words) {
  cli::Usage u;
  u.name = "analysis-demo";
  u.synopsis = "shared analysis options";
  u.argument("runs", "runs", true, true);
  cli::declare_product_output(u, {"a", "b"});
  cli::declare_critical_rule(u, "grain-grain friction coefficient");
  std::vector<std::string> argv{"analysis-demo"};
  argv.insert(argv.end(), words.begin(), words.end());
  return cli::parse(u, argv);
}
}  // namespace

TEST(AnalysisOptions, DefaultsAreTheLibrarys) {
  const cli::Args a = parse({"run.h5"});
  const analysis::CriticalRule r = cli::critical_rule(a);
  EXPECT_EQ(r.eps, analysis::default_eps);
  EXPECT_FALSE(r.include_walls);
  EXPECT_TRUE(r.floor_grains_are_walls);
  const analysis::FrictionChoice mu = cli::friction_choice(a);
  EXPECT_FALSE(mu.grain);
  EXPECT_FALSE(mu.wall);
  EXPECT_EQ(a.text("format"), "auto");
  EXPECT_EQ(a.output(), "");
}

TEST(AnalysisOptions, GivenValuesReachTheRule) {
  const cli::Args a =
      parse({"run.h5", "--eps", "0.01", "--walls", "--floor-grains", "grain", "--mu", "0.3",
             "--mu-wall", "0.2", "--format", "tsv", "--table", "a,b", "-o", "out.tsv"});
  const analysis::CriticalRule r = cli::critical_rule(a);
  EXPECT_EQ(r.eps, 0.01);
  EXPECT_TRUE(r.include_walls);
  EXPECT_FALSE(r.floor_grains_are_walls);
  const analysis::FrictionChoice mu = cli::friction_choice(a);
  EXPECT_EQ(mu.grain, 0.3);
  EXPECT_EQ(mu.wall, 0.2);
  EXPECT_EQ(cli::split_list(a.text("table")), (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(a.output(), "out.tsv");
}

TEST(AnalysisOptions, RangesAreChecked) {
  EXPECT_THROW(parse({"run.h5", "--eps", "1"}), UsageError);
  // --mu's one range is [0, 1000] (a frictionless pile is a simulator's choice); an
  // analysis refuses 0 itself (analysis::choose_friction).
  EXPECT_THROW(parse({"run.h5", "--mu", "-0.5"}), UsageError);
  EXPECT_THROW(parse({"run.h5", "--mu-wall", "1001"}), UsageError);
  EXPECT_EQ(cli::friction_choice(parse({"run.h5", "--mu", "0"})).grain, 0.0);
  EXPECT_THROW(parse({"run.h5", "--floor-grains", "floor"}), UsageError);
  EXPECT_THROW(parse({"run.h5", "--format", "csv"}), UsageError);
  EXPECT_THROW(parse({"run.h5", "--table", "c"}), UsageError);
  EXPECT_THROW(parse({"run.h5", "--table", "a,c"}), UsageError);
}
