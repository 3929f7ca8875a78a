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

Product correlate(const Product& in, const CorrelateOptions& opt) {
  if (!(opt.window > 0.0)) throw Error("window must be > 0 deg");
  const Table& ft = in.table("frames");
  const Table& st = in.table("states");
  const std::string& src = in.source;

  // Frames of the input.
  std::vector<FrameInfo> frames;
  std::map<std::pair<std::int64_t, std::int64_t>, std::size_t> index;
  {
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
      if (!index.emplace(std::make_pair(f.run, f.frame), frames.size()).second)
        throw Error(src, "",
                    "table frames: run " + std::to_string(f.run) + " frame " +
                        std::to_string(f.frame) + " appears twice");
      frames.push_back(f);
    }
  }
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
  p.results["frames_used"] = static_cast<std::int64_t>(std::count_if(
      frames.begin(), frames.end(), [](const FrameInfo& f) { return f.window.has_value(); }));
  if (skipped_no_theta) p.results["frames_without_theta"] = skipped_no_theta;
  if (skipped_range) p.results["frames_outside_range"] = skipped_range;

  Table* fr_t = nullptr;
  if (opt.frame_table) {
    fr_t = &p.add_table("frames", "nu_bar(r) of each frame");
    declare_columns(*fr_t, frame_columns);
  }
  Table& w_t =
      p.add_table("windows", "nu_bar(r) pooled over the frames and runs of a theta window");
  declare_columns(w_t, window_columns);

  // Group the states rows.
  struct Groups {
    std::map<std::int64_t, Sums> by_run;
    std::map<std::size_t, Sums> by_frame;
  };
  std::map<std::pair<std::int64_t, double>, Groups> cells;  // (window, r)
  {
    const Column &run = st.column("run"), &frame = st.column("frame"), &r = st.column("r"),
                 &n = st.column("n"), &sum = st.column("sum"), &sum2 = st.column("sum2");
    const std::size_t rows = st.rows();
    for (std::size_t q = 0; q < rows; ++q) {
      const auto key =
          std::make_pair(as_int(run, q, "states", src), as_int(frame, q, "states", src));
      auto it = index.find(key);
      if (it == index.end())
        throw Error(src, "",
                    "table states, row " + std::to_string(q + 1) + ": run " +
                        std::to_string(key.first) + " frame " + std::to_string(key.second) +
                        " is not in table frames");
      const FrameInfo& f = frames[it->second];
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
  }

  for (const auto& [key, c] : cells) {
    const auto [win, r] = key;
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
    add_row(w_t, window_columns,
            WindowRow{has_theta ? summarize(thetas).mean : std::nullopt,
                      has_theta ? std::optional<double>(lo) : std::nullopt,
                      has_theta ? std::optional<double>(hi) : std::nullopt, r,
                      static_cast<std::int64_t>(c.by_run.size()),
                      static_cast<std::int64_t>(c.by_frame.size()), pm, pile});
  }
  std::set<std::int64_t> windows;
  for (const auto& [k, c] : cells) windows.insert(k.first);
  p.results["windows"] = static_cast<std::int64_t>(windows.size());
  return p;
}

}  // namespace cdpile::analysis
