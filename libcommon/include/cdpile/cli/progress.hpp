/// The progress line of the long-running tools (deposit, tilt-cd) on a terminal's stderr:
/// one line rewritten in place with '\r', which must never wrap (a wrapped line scrolls a
/// new line at every update) and never leave characters of a longer earlier line behind.
#pragma once

#include "cdpile/cli/command.hpp"

#include <chrono>
#include <cstddef>
#include <string>
#include <vector>

namespace cdpile::cli {

/// One field of a progress line; fields with a higher `drop_order` are dropped first when
/// the line does not fit (0: never dropped, cut to the width as a last resort).
struct ProgressField {
  std::string text;
  int drop_order = 0;
};

/// The fields, in their order, joined by two spaces, dropping fields by drop_order until
/// the line has at most `width` - 1 characters (the last column is left free: some
/// terminals wrap when it is written).
std::string fit_progress(const std::vector<ProgressField>& fields, std::size_t width);

/// The width of the terminal on stderr: $COLUMNS when it is a positive number (a user's
/// override), else the terminal's (TIOCGWINSZ), else 80.
std::size_t terminal_width();

/// Prints progress lines on stderr, each over the previous one: '\r', the fitted line,
/// then spaces over what a longer previous line left. finish() ends the line.
class ProgressLine {
 public:
  void show(const std::vector<ProgressField>& fields);
  void finish();
  /// What show() writes after the previous line of `previous` characters (for the tests).
  static std::string render(const std::string& line, std::size_t previous);

 private:
  std::size_t previous_ = 0;
  bool shown_ = false;
};

/// Whether progress lines go to stderr: a terminal, and no --quiet.
bool progress_wanted(const Args& a);

/// The progress of a long loop (deposit's settling, tilt-cd's steps): a ProgressLine
/// rewritten at most twice a second, so that printing never slows the loop, and only when
/// progress_wanted. The clock starts at construction.
class Progress {
 public:
  explicit Progress(bool shown);
  explicit Progress(const Args& a) : Progress(progress_wanted(a)) {}
  bool shown() const { return shown_; }
  /// Seconds since the start.
  double seconds() const;
  /// `count` per second since the start (steps/s).
  double rate(double count) const;
  /// Whether a line is due: shown, and half a second since the last line (or the start).
  bool due() const;
  /// Writes the line now, if shown.
  void show(const std::vector<ProgressField>& fields);
  /// Ends the line (a newline if any was shown).
  void finish() { line_.finish(); }

 private:
  using Clock = std::chrono::steady_clock;
  bool shown_;
  Clock::time_point start_, last_;
  ProgressLine line_;
};

}  // namespace cdpile::cli
