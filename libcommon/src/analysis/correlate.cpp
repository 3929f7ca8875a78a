// correlate: nu_bar(theta, r), the mean local state around critical contacts (eq 3),
// per frame and pooled in theta windows over frames and runs (Fig 4).
#include "cdpile/analysis/correlate.hpp"

#include "cdpile/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <set>

namespace cdpile::analysis {

namespace {
constexpr double nan = std::numeric_limits<double>::quiet_NaN();

struct FrameInfo {
  std::int64_t run = 0, frame = 0;
  std::optional<double> theta, nu;
  std::optional<std::int64_t> window;
};

// The two tables, each one list of columns (ColumnSpec, table.hpp).
using K = ColumnKind;

// --- frames: nu_bar(r) of each frame
struct FrameStateRow {
  const FrameInfo& f;
  double r;  // [D]
  Sums s;
};
const ColumnSpec<FrameStateRow> frame_columns[] = {
    {"run", "", K::integer, [](const FrameStateRow& x) -> Cell { return x.f.run; }},
    {"frame", "", K::integer, [](const FrameStateRow& x) -> Cell { return x.f.frame; }},
    {"theta", "deg", K::real, [](const FrameStateRow& x) -> Cell { return x.f.theta; }},
    {"r", "D", K::real, [](const FrameStateRow& x) -> Cell { return x.r; }},
    {"n", "", K::integer, [](const FrameStateRow& x) -> Cell { return x.s.n; }},
    {"nu_bar", "", K::real, [](const FrameStateRow& x) -> Cell { return x.s.summary().mean; }},
    {"se", "", K::real, [](const FrameStateRow& x) -> Cell { return x.s.summary().se; }},
    {"nu_pile", "", K::real, [](const FrameStateRow& x) -> Cell { return x.f.nu; }},
};

// --- windows: nu_bar(r) pooled over the frames and runs of a theta window
struct WindowRow {
  std::optional<double> theta, theta_lo, theta_hi;  // none when no frame has a tilt
  double r;                                         // [D]
  std::int64_t runs, frames;
  Pooled pm;     // nu_bar and its se
  Summary pile;  // the pile's nu
};
const ColumnSpec<WindowRow> window_columns[] = {
    {"theta", "deg", K::real, [](const WindowRow& x) -> Cell { return x.theta; }},
    {"theta_lo", "deg", K::real, [](const WindowRow& x) -> Cell { return x.theta_lo; }},
    {"theta_hi", "deg", K::real, [](const WindowRow& x) -> Cell { return x.theta_hi; }},
    {"r", "D", K::real, [](const WindowRow& x) -> Cell { return x.r; }},
    {"runs", "", K::integer, [](const WindowRow& x) -> Cell { return x.runs; }},
    {"frames", "", K::integer, [](const WindowRow& x) -> Cell { return x.frames; }},
    {"n", "", K::integer, [](const WindowRow& x) -> Cell { return x.pm.n; }},
    {"nu_bar", "", K::real, [](const WindowRow& x) -> Cell { return x.pm.mean; }},
    {"se", "", K::real, [](const WindowRow& x) -> Cell { return x.pm.se; }},
    {"se_over", "", K::text,
     [](const WindowRow& x) -> Cell {
       return std::string(x.pm.se ? se_over_name(x.pm.over) : "none");
     }},
    {"nu_pile", "", K::real, [](const WindowRow& x) -> Cell { return x.pile.mean; }},
    {"nu_pile_se", "", K::real, [](const WindowRow& x) -> Cell { return x.pile.se; }},
};

std::int64_t as_int(const Column& c, std::size_t r, const std::string& table,
                    const std::string& src) {
  auto v = c.get(r);
  // within 2^53, as the product readers hold integers (docs/schema.md, "Ranges"): a text
  // product's columns are real, and 1e300 is an integer a cast cannot hold
  if (!v || *v != std::floor(*v) || !(std::fabs(*v) <= 9007199254740992.0))
    throw Error(src, "",
                "table " + table + ", row " + std::to_string(r + 1) + ": column " + c.name +
                    " must be an integer");
  return static_cast<std::int64_t>(*v);
}
}  // namespace

namespace {

// The input's frames, and where each (run, frame) is among them.
struct Frames {
  std::vector<FrameInfo> info;
  std::map<std::pair<std::int64_t, std::int64_t>, std::size_t> index;
};

// Stage 1: localnu's table frames, each (run, frame) once, each theta a tilt.
Frames read_frames(const Table& ft, const std::string& src) {
  Frames out;
  const Column &run = ft.column("run"), &frame = ft.column("frame"), &theta = ft.column("theta"),
               &nu = ft.column("nu");
  const std::size_t n = ft.rows();
  for (std::size_t r = 0; r < n; ++r) {
    FrameInfo f;
    f.run = as_int(run, r, "frames", src);
    f.frame = as_int(frame, r, "frames", src);
    f.theta = theta.get(r);
    // a tilt (docs/schema.md, "Ranges"); its window index is an integer cast of it
    if (f.theta && !(std::fabs(*f.theta) <= 90.0)) {
      char what[160];
      std::snprintf(what, sizeof what,
                    "table frames, row %zu: theta %g deg is outside [-90, 90] deg", r + 1,
                    *f.theta);
      throw Error(src, "", what);
    }
    f.nu = nu.get(r);
    if (!out.index.emplace(std::make_pair(f.run, f.frame), out.info.size()).second)
      throw Error(src, "",
                  "table frames: run " + std::to_string(f.run) + " frame " +
                      std::to_string(f.frame) + " appears twice");
    out.info.push_back(f);
  }
  return out;
}

// Stage 2: each frame's theta window [start + k w, start + (k+1) w), none outside
// opt.theta or without a theta (all frames one window when no frame has one); the results
// that count the frames used and left out.
void assign_windows(std::vector<FrameInfo>& frames, const CorrelateOptions& opt, Product& p) {
  bool any_theta = false;
  for (const FrameInfo& f : frames) any_theta = any_theta || f.theta.has_value();
  std::int64_t skipped_no_theta = 0, skipped_range = 0;
  for (FrameInfo& f : frames) {
    if (f.theta) {
      if (!opt.theta.contains(*f.theta)) {
        ++skipped_range;
        continue;
      }
      f.window =
          static_cast<std::int64_t>(std::floor((*f.theta - opt.window_start) / opt.window + 1e-12));
    } else if (!any_theta && !opt.theta.bounded()) {
      f.window = 0;  // no theta anywhere: one window of every frame
    } else {
      ++skipped_no_theta;
    }
  }
  p.results["frames_used"] = static_cast<std::int64_t>(std::count_if(
      frames.begin(), frames.end(), [](const FrameInfo& f) { return f.window.has_value(); }));
  if (skipped_no_theta) p.results["frames_without_theta"] = skipped_no_theta;
  if (skipped_range) p.results["frames_outside_range"] = skipped_range;
}

// The sums of eq (3) of a (window, r) cell, by run and by frame.
struct Groups {
  std::map<std::int64_t, Sums> by_run;
  std::map<std::size_t, Sums> by_frame;
};
using Cells = std::map<std::pair<std::int64_t, double>, Groups>;  // (window, r)

// Stage 3: localnu's table states, each row's sums into its cell, and into the table
// frames (fr_t, when asked) as a row of its own.
Cells group_states(const Table& st, const Frames& frames, const std::string& src, Table* fr_t) {
  Cells cells;
  const Column &run = st.column("run"), &frame = st.column("frame"), &r = st.column("r"),
               &n = st.column("n"), &sum = st.column("sum"), &sum2 = st.column("sum2");
  const std::size_t rows = st.rows();
  for (std::size_t q = 0; q < rows; ++q) {
    const auto key = std::make_pair(as_int(run, q, "states", src), as_int(frame, q, "states", src));
    auto it = frames.index.find(key);
    if (it == frames.index.end())
      throw Error(src, "",
                  "table states, row " + std::to_string(q + 1) + ": run " +
                      std::to_string(key.first) + " frame " + std::to_string(key.second) +
                      " is not in table frames");
    const FrameInfo& f = frames.info[it->second];
    const auto rr = r.get(q);
    if (!rr || !(*rr > 0))
      throw Error(src, "", "table states, row " + std::to_string(q + 1) + ": bad radius");
    Sums s;
    s.n = as_int(n, q, "states", src);
    s.sum = sum.get(q).value_or(0.0);
    s.sum2 = sum2.get(q).value_or(0.0);
    if (s.n < 0)
      throw Error(src, "", "table states, row " + std::to_string(q + 1) + ": negative count");
    if (fr_t) add_row(*fr_t, frame_columns, FrameStateRow{f, *rr, s});
    if (!f.window) continue;
    Groups& c = cells[{*f.window, *rr}];
    c.by_run[f.run].add(s);
    c.by_frame[it->second].add(s);
  }
  return cells;
}

// Stage 4: a cell pooled: nu_bar with its cluster-robust error over runs (>= 2) or frames,
// the window's mean theta and the pile's nu.
WindowRow pool(std::int64_t win, double r, const Groups& c, const std::vector<FrameInfo>& frames,
               const CorrelateOptions& opt) {
  // frames and runs of the window (also frames whose critical count is 0)
  std::vector<double> thetas, nus;
  std::map<std::int64_t, std::vector<double>> run_nu;
  for (const auto& [fi, s] : c.by_frame) {
    const FrameInfo& f = frames[fi];
    if (f.theta) thetas.push_back(*f.theta);
    if (f.nu) {
      nus.push_back(*f.nu);
      run_nu[f.run].push_back(*f.nu);
    }
  }
  std::vector<Sums> clusters;
  SeOver kind;
  if (c.by_run.size() >= 2) {
    for (const auto& [rn, s] : c.by_run) clusters.push_back(s);
    kind = SeOver::runs;
  } else {
    for (const auto& [fi, s] : c.by_frame) clusters.push_back(s);
    kind = SeOver::frames;
  }
  const Pooled pm = pooled_mean(clusters, kind);
  Summary pile;
  if (run_nu.size() >= 2) {
    std::vector<double> means;
    for (const auto& [rn, v] : run_nu) means.push_back(summarize(v).mean.value_or(nan));
    pile = summarize(means);
    pile.mean = summarize(nus).mean;  // the mean over frames, se over runs
  } else {
    pile = summarize(nus);
  }
  const bool has_theta = !thetas.empty();
  const double lo = opt.window_start + static_cast<double>(win) * opt.window,
               hi = opt.window_start + static_cast<double>(win + 1) * opt.window;
  return WindowRow{has_theta ? summarize(thetas).mean : std::nullopt,
                   has_theta ? std::optional<double>(lo) : std::nullopt,
                   has_theta ? std::optional<double>(hi) : std::nullopt,
                   r,
                   static_cast<std::int64_t>(c.by_run.size()),
                   static_cast<std::int64_t>(c.by_frame.size()),
                   pm,
                   pile};
}

}  // namespace

Product correlate(const Product& in, const CorrelateOptions& opt) {
  if (!(opt.window > 0.0)) throw Error("window must be > 0 deg");
  const Table& ft = in.table("frames");
  const Table& st = in.table("states");
  const std::string& src = in.source;
  Frames frames = read_frames(ft, src);

  Product p;
  p.kind = "correlate";
  p.parameters = {{"window_deg", opt.window}, {"window_start_deg", opt.window_start}};
  record_range(p.parameters, "theta", opt.theta);
  for (const auto& [k, v] : in.parameters) p.parameters["localnu_" + k] = v;
  p.notes = {"nu_bar(theta, r) = mean of nu_i(theta, r) over critical contacts (eq 3), r in D",
             "frames: per frame, se = sd/sqrt(n) over the frame's critical contacts (treated as "
             "independent: an underestimate, contacts are correlated)",
             "windows: [start + k w, start + (k+1) w); nu_bar pools every critical contact of the "
             "window's frames; se is the cluster-robust error of that pooled mean with runs as "
             "clusters when >= 2 runs contribute (se_over = runs), else frames (se_over = frames, "
             "frames of one run are correlated in time), else contacts",
             "theta of a window: the mean theta of its frames; nu_pile: the mean pile nu of its "
             "frames, se over runs (>= 2) or frames",
             "a window has no theta (NA) when the input frames have none: then all frames form one "
             "window"};
  assign_windows(frames.info, opt, p);

  Table* fr_t = opt.frame_table ? &declare_columns(p.add_table("frames", "nu_bar(r) of each frame"),
                                                   frame_columns)
                                : nullptr;
  Table& w_t = declare_columns(
      p.add_table("windows", "nu_bar(r) pooled over the frames and runs of a theta window"),
      window_columns);
  const Cells cells = group_states(st, frames, src, fr_t);
  std::set<std::int64_t> windows;
  for (const auto& [key, c] : cells) {
    add_row(w_t, window_columns, pool(key.first, key.second, c, frames.info, opt));
    windows.insert(key.first);
  }
  p.results["windows"] = static_cast<std::int64_t>(windows.size());
  return p;
}

}  // namespace cdpile::analysis
