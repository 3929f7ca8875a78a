// The command-line layer: typed, strict, range-checked values; no prefix guessing;
// defaults and units in --help.
#include "cdpile/cli/command.hpp"

#include <gtest/gtest.h>

using namespace cdpile;

namespace {

cli::Usage demo() {
  cli::Usage u;
  u.name = "demo";
  u.synopsis = "a demo";
  u.argument("input", "input file", true);
  u.output("output file", "-");
  u.integer("grains", 4000, "number of grains", 1);
  u.real("diameter", 1e-3, "mean diameter", "m", 0);
  u.real_opt("to", "final angle", "deg", 0, 90);
  u.real_list("radii", "1:1:20", "radii", "D", 0);
  u.text("criterion", "max", "convergence criterion", {"max", "quad"});
  u.text_list("table", "tables to write", {"runs", "frames"});
  u.flag("exclude-self", "leave contact i out of its own neighbourhood");
  u.flag("force", "replace");
  u.seed();
  return u;
}

cli::Args run(const std::vector<std::string>& words) {
  std::vector<std::string> argv{"demo"};
  argv.insert(argv.end(), words.begin(), words.end());
  return cli::parse(demo(), argv);
}

std::string usage_error(const std::vector<std::string>& words) {
  try {
    run(words);
  } catch (const UsageError& e) {
    return e.what();
  }
  return "accepted";
}

}  // namespace

TEST(Cli, DefaultsAndTypedValues) {
  cli::Args a = run({"in.h5", "--grains", "500", "--diameter=2e-3", "--exclude-self"});
  EXPECT_EQ(a.integer("grains"), 500);
  EXPECT_EQ(a.real("diameter"), 2e-3);
  EXPECT_FALSE(a.real_opt("to").has_value());
  EXPECT_TRUE(a.flag("exclude-self"));
  EXPECT_FALSE(a.force());
  EXPECT_EQ(a.output(), "-");
  EXPECT_EQ(a.seed(), 1u);
  EXPECT_EQ(a.text("criterion"), "max");
  EXPECT_EQ(a.arguments("input"), std::vector<std::string>{"in.h5"});
  EXPECT_TRUE(a.given("grains"));
  EXPECT_FALSE(a.given("seed"));
  auto radii = a.real_list("radii");
  ASSERT_EQ(radii.size(), 20u);
  EXPECT_EQ(radii.front(), 1.0);
  EXPECT_EQ(radii.back(), 20.0);
}

TEST(Cli, RepeatedPositionalAndLists) {
  cli::Args a = run({"a.h5", "b.h5", "-", "--radii", "1,2.5,6", "-o", "x.tsv"});
  EXPECT_EQ(a.arguments("input"), (std::vector<std::string>{"a.h5", "b.h5", "-"}));
  EXPECT_EQ(a.real_list("radii"), (std::vector<double>{1, 2.5, 6}));
  EXPECT_EQ(a.output(), "x.tsv");
}

TEST(Cli, StrictNumbers) {
  EXPECT_EQ(usage_error({"a", "--grains", "1e"}), "--grains: expected an integer >= 1, got '1e'");
  EXPECT_EQ(usage_error({"a", "--grains", "0"}),
            "--grains: expected an integer >= 1, got '0' (out of range)");
  EXPECT_EQ(usage_error({"a", "--grains", "12abc"}),
            "--grains: expected an integer >= 1, got '12abc'");
  EXPECT_EQ(usage_error({"a", "--diameter", "nan"}),
            "--diameter: expected a finite number >= 0, got 'nan'");
  EXPECT_EQ(usage_error({"a", "--diameter", "inf"}),
            "--diameter: expected a finite number >= 0, got 'inf'");
  EXPECT_EQ(usage_error({"a", "--to", "91"}),
            "--to: expected a finite number in [0, 90], got '91' (out of range)");
  EXPECT_EQ(usage_error({"a", "--radii", "1:0:5"}),
            "--radii: expected a list of numbers (A,B,C or FIRST:STEP:LAST) >= 0, got '1:0:5' (the "
            "step must be positive and LAST >= FIRST)");
  EXPECT_EQ(usage_error({"a", "--criterion", "l2"}),
            "--criterion: expected one of max, quad, got 'l2'");
}

TEST(Cli, ListOfChoicesCheckedItemByItem) {
  EXPECT_EQ(run({"a"}).text_list("table"), std::vector<std::string>{});
  EXPECT_EQ(run({"a", "--table", "frames,runs"}).text_list("table"),
            (std::vector<std::string>{"frames", "runs"}));
  EXPECT_EQ(usage_error({"a", "--table", "foo"}),
            "--table: expected one or more of runs, frames (comma-separated), got 'foo'");
  EXPECT_EQ(usage_error({"a", "--table", "runs,foo"}),
            "--table: expected one or more of runs, frames (comma-separated), got 'foo'");
  EXPECT_EQ(usage_error({"a", "--table", "runs,"}),
            "--table: expected one or more of runs, frames (comma-separated), got ''");
}

TEST(Cli, NoPrefixGuessingAndUnknownOptions) {
  // `--grain` must not silently mean `--grains`: a Makefile written today must not
  // change meaning when an option sharing the prefix is added tomorrow.
  EXPECT_NE(usage_error({"a", "--grain", "5"}), "accepted");
  EXPECT_NE(usage_error({"a", "--bogus"}).find("--bogus"), std::string::npos);
}

TEST(Cli, MissingArgument) { EXPECT_EQ(usage_error({}), "missing argument input"); }

TEST(Cli, CommandLineIsShellQuotedForProvenance) {
  cli::Args a = run({"my file.h5", "--grains", "5"});
  EXPECT_EQ(a.command_line(), "demo 'my file.h5' --grains 5");
}

TEST(Cli, HelpShowsEveryOptionWithDefaultAndUnit) {
  const std::string h = cli::help_text(demo());
  EXPECT_NE(h.find("Usage: demo [options] INPUT..."), std::string::npos);
  EXPECT_NE(h.find("mean diameter (unit: m; default: 0.001; >= 0)"), std::string::npos) << h;
  EXPECT_NE(h.find("number of grains (default: 4000; >= 1)"), std::string::npos) << h;
  EXPECT_NE(h.find("Exit status: 0 success; 1 runtime or data error"), std::string::npos);
  const std::string md = cli::help_markdown(demo());
  EXPECT_NE(md.find("| `--diameter X` | mean diameter (>= 0) | m | `0.001` |"), std::string::npos)
      << md;
}

// An old spelling kept for one version: the same option, hidden from --help; both
// spellings together are the option given twice.
TEST(Cli, AliasesStandForTheirOption) {
  cli::Usage u = demo();
  u.alias("grain-count", "grains");
  u.alias("no-self", "exclude-self");
  auto parse = [&](const std::vector<std::string>& words) {
    std::vector<std::string> argv{"demo"};
    argv.insert(argv.end(), words.begin(), words.end());
    return cli::parse(u, argv);
  };
  const cli::Args a = parse({"in.h5", "--grain-count", "7", "--no-self"});
  EXPECT_EQ(a.integer("grains"), 7);
  EXPECT_TRUE(a.given("grains"));
  EXPECT_TRUE(a.flag("exclude-self"));
  EXPECT_FALSE(parse({"in.h5"}).flag("exclude-self"));
  EXPECT_EQ(parse({"in.h5"}).integer("grains"), 4000);
  try {
    parse({"in.h5", "--grains", "5", "--grain-count", "7"});
    ADD_FAILURE() << "both spellings accepted";
  } catch (const UsageError& e) {
    EXPECT_EQ(std::string(e.what()), "--grains given twice (also as --grain-count)");
  }
  EXPECT_EQ(cli::help_text(u).find("grain-count"), std::string::npos);
  EXPECT_EQ(cli::help_markdown(u).find("grain-count"), std::string::npos);
  EXPECT_THROW(u.alias("old", "undeclared"), std::logic_error);
}

// The manual page is the same declaration as --help, in roff: every option, dashes as \-.
TEST(Cli, ManPageFromTheDeclaration) {
  cli::Usage u = demo();
  u.alias("grain-count", "grains");
  const std::string man = cli::help_man(u);
  EXPECT_EQ(man.rfind(".TH DEMO 1 ", 0), 0u);
  EXPECT_NE(man.find(".SH NAME\ndemo \\- a demo\n"), std::string::npos);
  for (const auto& o : u.options) {
    std::string name;  // roff's minus for every dash of the name
    for (char c : o.name) name += c == '-' ? std::string("\\-") : std::string(1, c);
    EXPECT_NE(man.find("\\-\\-" + name), std::string::npos) << o.name;
  }
  EXPECT_EQ(man.find("grain\\-count"), std::string::npos);
}

// An option declared by the library (cdpile/option.hpp) is the option integer() or real()
// would declare, in its group; place_after puts a tool's own option beside one of them.
TEST(Cli, DeclaredOptionsAsTheirDeclarationSays) {
  cli::Usage u;
  u.name = "demo";
  OptionDeclaration rate{"rate", "Tilt", false, 0.001, "tilt per step", "deg", 1e-12, 90.0};
  OptionDeclaration to{"to", "Tilt", false, {}, "final tilt", "deg", -90.0, 90.0};
  OptionDeclaration every{"every", "Recording", true, std::int64_t{20}, "steps", "", 1, 1e12};
  u.declare("Tilt", {rate, every, to});
  u.real_opt("branch-at", "start there", "deg").place_after("rate");
  u.declare("Recording", {rate, every, to});
  cli::Usage by_hand;
  by_hand.name = "demo";
  by_hand.group("Tilt");
  by_hand.real("rate", 0.001, "tilt per step", "deg", 1e-12, 90.0);
  by_hand.real_opt("branch-at", "start there", "deg");
  by_hand.real_opt("to", "final tilt", "deg", -90.0, 90.0);
  by_hand.group("Recording");
  by_hand.integer("every", 20, "steps", 1, 1000000000000);
  EXPECT_EQ(cli::help_text(u), cli::help_text(by_hand));
  const cli::Args a = cli::parse(u, {"demo", "--every", "7"});
  const OptionValues v = cli::option_values(a, {rate, every, to});
  EXPECT_EQ(v.at("rate"), OptionValue(0.001));
  EXPECT_EQ(v.at("every"), OptionValue(std::int64_t{7}));
  EXPECT_FALSE(v.count("to"));  // no default, not given
  EXPECT_THROW(u.real_opt("late", "x").place_after("nothing"), std::logic_error);
}
