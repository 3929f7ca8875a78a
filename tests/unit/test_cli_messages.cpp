// Messages on hostile input: control bytes escaped, an output that is an input refused.
#include "cdpile/cli/avalanche_options.hpp"
#include "cdpile/cli/command.hpp"
#include "cdpile/cli/fields.hpp"
#include "cdpile/error.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

using namespace cdpile;

TEST(Printable, EscapesControlBytesAndBrokenUtf8) {
  EXPECT_EQ(printable("run.h5: plain text, tabs\tkept"), "run.h5: plain text, tabs\tkept");
  EXPECT_EQ(printable("a\x1b[2Jb\x07\n\r\x7f"), "a\\x1b[2Jb\\x07\\x0a\\x0d\\x7f");
  EXPECT_EQ(printable("caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80"),
            "caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80");
  EXPECT_EQ(printable("\xff\xc3"), "\\xff\\xc3");  // not UTF-8, a sequence cut short
  EXPECT_EQ(printable("\xc2\x9b"
                      "31m"),
            "\\xc2\\x9b31m");  // U+009B, the C1 control CSI
  EXPECT_EQ(printable("\xc0\xaf \xed\xa0\x80"),
            "\\xc0\\xaf \\xed\\xa0\\x80");  // overlong, surrogate
  EXPECT_EQ(printable(std::string("a\0b", 3)), "a\\x00b");
}

namespace {
cli::Usage two_inputs() {
  cli::Usage u;
  u.name = "demo";
  u.synopsis = "a demo";
  u.argument("inputs", "input files", true);
  u.output("output file");
  u.text_opt("nu", "another input");
  u.flag("force", "replace");
  return u;
}
std::string refusal(const std::vector<std::string>& words) {
  std::vector<std::string> argv{"demo"};
  argv.insert(argv.end(), words.begin(), words.end());
  try {
    cli::check_output_is_not_an_input(cli::parse(two_inputs(), argv));
  } catch (const UsageError& e) {
    return e.what();
  }
  return "accepted";
}
}  // namespace

TEST(OutputIsNotAnInput, SameFileByAnyNameIsRefused) {
  namespace fs = std::filesystem;
  const fs::path dir =
      fs::temp_directory_path() / ("cdpile-test-" + std::to_string(std::random_device{}()));
  fs::create_directories(dir);
  const std::string a = (dir / "a.h5").string(), b = (dir / "b.h5").string(),
                    link = (dir / "l.h5").string();
  std::ofstream(a) << "a";
  std::ofstream(b) << "b";
  fs::create_symlink(a, link);
  EXPECT_EQ(refusal({a, b, "-o", b, "--force"}),
            "-o " + b + ": is also an input (" + b + "); write to another file");
  EXPECT_EQ(refusal({a, "-o", link}),
            "-o " + link + ": is also an input (" + a + "); write to another file");
  EXPECT_EQ(refusal({a, "--nu", b, "-o", b}),
            "-o " + b + ": is also an input (" + b + "); write to another file");
  EXPECT_EQ(refusal({a, "-o", (dir / "new.h5").string()}), "accepted");  // does not exist yet
  EXPECT_EQ(refusal({"-", "-o", "-"}), "accepted");                      // stdin and stdout
  EXPECT_EQ(refusal({a, "--nu", "0.5", "-o", b}), "accepted");
  fs::remove_all(dir);
}

// The tools' spelling of the library's fields: the option that sets each one, as declared
// (the library's declaration of the option names the field).
TEST(Fields, TheToolsSpellAFieldAsItsOption) {
  OptionDeclaration rate;
  rate.name = "rate";
  rate.field = "rate_deg";
  rate.group = "Tilt";
  cli::Usage u;
  u.declare(rate);
  cli::declare_avalanche_rule(u, "", "");
  EXPECT_EQ(cli::option_of_field("rate_deg"), "--rate");
  EXPECT_EQ(cli::option_of_field("avalanche_energy"), "--avalanche-ek");
  EXPECT_EQ(cli::option_of_field("output"), "-o");
  EXPECT_EQ(cli::option_of_field("max_sweeps"), "--max-sweeps");  // an option of the field's name
}
