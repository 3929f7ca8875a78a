#include "cdpile/cli/progress.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>

namespace cdpile::cli {

namespace {
std::string join(const std::vector<ProgressField>& fields, const std::vector<bool>& keep) {
  std::string s;
  for (std::size_t k = 0; k < fields.size(); ++k) {
    if (!keep[k] || fields[k].text.empty()) continue;
    if (!s.empty()) s += "  ";
    s += fields[k].text;
  }
  return s;
}
}  // namespace

std::string fit_progress(const std::vector<ProgressField>& fields, std::size_t width) {
  const std::size_t room = width > 1 ? width - 1 : 1;
  std::vector<bool> keep(fields.size(), true);
  std::string line = join(fields, keep);
  while (line.size() > room) {
    // the kept field dropped first: the highest drop_order, the last one among equals
    std::size_t worst = fields.size();
    for (std::size_t k = 0; k < fields.size(); ++k)
      if (keep[k] && fields[k].drop_order > 0 &&
          (worst == fields.size() || fields[k].drop_order >= fields[worst].drop_order))
        worst = k;
    if (worst == fields.size()) return line.substr(0, room);
    keep[worst] = false;
    line = join(fields, keep);
  }
  return line;
}

std::size_t terminal_width() {
  if (const char* c = std::getenv("COLUMNS")) {
    char* end = nullptr;
    const long n = std::strtol(c, &end, 10);
    if (end != c && *end == '\0' && n > 0) return static_cast<std::size_t>(n);
  }
  winsize ws{};
  if (::ioctl(STDERR_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 0) return ws.ws_col;
  return 80;
}

std::string ProgressLine::render(const std::string& line, std::size_t previous) {
  return "\r" + line + std::string(previous > line.size() ? previous - line.size() : 0, ' ');
}

void ProgressLine::show(const std::vector<ProgressField>& fields) {
  const std::size_t width = terminal_width();
  const std::string line = fit_progress(fields, width);
  // spaces over the rest of the previous line, but never into the last column
  const std::string out = render(line, std::min(previous_, width > 1 ? width - 1 : 1));
  std::fwrite(out.data(), 1, out.size(), stderr);
  std::fflush(stderr);
  previous_ = line.size();
  shown_ = true;
}

void ProgressLine::finish() {
  if (shown_) std::fputc('\n', stderr);
  shown_ = false;
  previous_ = 0;
}

bool progress_wanted(const Args& a) { return !a.quiet() && isatty(STDERR_FILENO) != 0; }

Progress::Progress(bool shown) : shown_(shown), start_(Clock::now()), last_(start_) {}

double Progress::seconds() const {
  return std::chrono::duration<double>(Clock::now() - start_).count();
}

double Progress::rate(double count) const { return count / std::max(seconds(), 1e-9); }

bool Progress::due() const {
  return shown_ && std::chrono::duration<double>(Clock::now() - last_).count() >= 0.5;
}

void Progress::show(const std::vector<ProgressField>& fields) {
  if (!shown_) return;
  last_ = Clock::now();
  line_.show(fields);
}

}  // namespace cdpile::cli
