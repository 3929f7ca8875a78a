// The progress line fits the terminal: fields dropped in their order, never wrapped, and
// no characters of a longer earlier line left behind.
#include "cdpile/cli/progress.hpp"

#include <gtest/gtest.h>

#include <cstdlib>

#include <unistd.h>

using cdpile::cli::fit_progress;
using cdpile::cli::ProgressField;
using cdpile::cli::ProgressLine;

namespace {
std::vector<ProgressField> tilt_fields() {
  return {{"tilt-cd: 12.345 deg", 0},
          {"step 12345", 2},
          {"678 steps/s", 4},
          {"Ek/(Np m g D) 1.2e-05", 3},
          {"est. 48 s left", 1}};
}
}  // namespace

TEST(Progress, AWideTerminalGetsEveryField) {
  EXPECT_EQ(fit_progress(tilt_fields(), 200),
            "tilt-cd: 12.345 deg  step 12345  678 steps/s  Ek/(Np m g D) 1.2e-05  est. 48 s left");
}

TEST(Progress, FieldsAreDroppedInTheirOrderToFitTheWidth) {
  // 80 columns: at most 79 characters, the last column free
  const std::string s80 = fit_progress(tilt_fields(), 80);
  EXPECT_LE(s80.size(), 79u);
  EXPECT_EQ(s80, "tilt-cd: 12.345 deg  step 12345  Ek/(Np m g D) 1.2e-05  est. 48 s left");
  EXPECT_EQ(fit_progress(tilt_fields(), 40), "tilt-cd: 12.345 deg  est. 48 s left");
  EXPECT_EQ(fit_progress(tilt_fields(), 21), "tilt-cd: 12.345 deg");
  // narrower than the field that is never dropped: cut, never wrapped
  EXPECT_EQ(fit_progress(tilt_fields(), 10), "tilt-cd: ");
  for (std::size_t w = 1; w < 120; ++w)
    EXPECT_LT(fit_progress(tilt_fields(), w).size(), std::max<std::size_t>(w, 2));
}

TEST(Progress, AShorterLineClearsTheLongerOneBefore) {
  EXPECT_EQ(ProgressLine::render("abc", 0), "\rabc");
  EXPECT_EQ(ProgressLine::render("abc", 6), "\rabc   ");
  EXPECT_EQ(ProgressLine::render("abcdef", 3), "\rabcdef");
}

TEST(Progress, ColumnsOverridesTheTerminal) {
  ::setenv("COLUMNS", "57", 1);
  EXPECT_EQ(cdpile::cli::terminal_width(), 57u);
  ::setenv("COLUMNS", "junk", 1);
  EXPECT_GT(cdpile::cli::terminal_width(), 0u);
  ::unsetenv("COLUMNS");
}

// cli::Progress, deposit's and tilt-cd's: a hidden progress (not a terminal, or --quiet) is
// never due and writes nothing; a shown one is due half a second after its start. (That
// it is not due sooner is not asserted: a loaded machine may stall that long.)
TEST(Progress, ALineIsDueOnlyWhenShown) {
  cdpile::cli::Progress hidden(false);
  EXPECT_FALSE(hidden.due());
  testing::internal::CaptureStderr();
  hidden.show({{"never", 0}});
  hidden.finish();
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");

  cdpile::cli::Progress shown(true);
  ::usleep(600000);
  EXPECT_TRUE(shown.due());
  testing::internal::CaptureStderr();
  shown.show({{"line", 0}});
  shown.finish();
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "\rline\n");
  EXPECT_GT(shown.rate(1000.0), 0.0);
  EXPECT_LT(shown.rate(1000.0), 1000.0 / 0.6);  // over the time since the start
}
