// correlate: nu_bar(theta, r), the mean local state around critical contacts (eq 3),
// per frame and pooled in theta windows over frames and runs (Fig 4).
#include "cdpile/analysis/studies.hpp"

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
    for (auto [n, u, k] : std::initializer_list<std::tuple<const char*, const char*, ColumnKind>>{
             {"run", "", ColumnKind::integer},
             {"frame", "", ColumnKind::integer},
             {"theta", "deg", ColumnKind::real},
             {"r", "D", ColumnKind::real},
             {"n", "", ColumnKind::integer},
             {"nu_bar", "", ColumnKind::real},
             {"se", "", ColumnKind::real},
             {"nu_pile", "", ColumnKind::real}})
      fr_t->add_column(n, u, k);
  }
  Table& w_t =
      p.add_table("windows", "nu_bar(r) pooled over the frames and runs of a theta window");
  for (auto [n, u, k] : std::initializer_list<std::tuple<const char*, const char*, ColumnKind>>{
           {"theta", "deg", ColumnKind::real},
           {"theta_lo", "deg", ColumnKind::real},
           {"theta_hi", "deg", ColumnKind::real},
           {"r", "D", ColumnKind::real},
           {"runs", "", ColumnKind::integer},
           {"frames", "", ColumnKind::integer},
           {"n", "", ColumnKind::integer},
           {"nu_bar", "", ColumnKind::real},
           {"se", "", ColumnKind::real},
           {"se_over", "", ColumnKind::text},
           {"nu_pile", "", ColumnKind::real},
           {"nu_pile_se", "", ColumnKind::real}})
    w_t.add_column(n, u, k);

  // Group the states rows.
  struct Cell {
    std::map<std::int64_t, Sums> by_run;
    std::map<std::size_t, Sums> by_frame;
  };
  std::map<std::pair<std::int64_t, double>, Cell> cells;  // (window, r)
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
      if (fr_t) {
        const Summary sm = s.summary();
        fr_t->column("run").add_int(f.run);
        fr_t->column("frame").add_int(f.frame);
        fr_t->column("theta").add(f.theta);
        fr_t->column("r").add(*rr);
        fr_t->column("n").add_int(s.n);
        fr_t->column("nu_bar").add(sm.mean);
        fr_t->column("se").add(sm.se);
        fr_t->column("nu_pile").add(f.nu);
      }
      if (!f.window) continue;
      Cell& c = cells[{*f.window, *rr}];
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
    w_t.column("theta").add(has_theta ? summarize(thetas).mean : std::nullopt);
    w_t.column("theta_lo")
        .add(has_theta
                 ? std::optional<double>(opt.window_start + static_cast<double>(win) * opt.window)
                 : std::nullopt);
    w_t.column("theta_hi")
        .add(has_theta ? std::optional<double>(opt.window_start +
                                               static_cast<double>(win + 1) * opt.window)
                       : std::nullopt);
    w_t.column("r").add(r);
    w_t.column("runs").add_int(static_cast<std::int64_t>(c.by_run.size()));
    w_t.column("frames").add_int(static_cast<std::int64_t>(c.by_frame.size()));
    w_t.column("n").add_int(pm.n);
    w_t.column("nu_bar").add(pm.mean);
    w_t.column("se").add(pm.se);
    w_t.column("se_over").add_text(pm.se ? se_over_name(pm.over) : "none");
    w_t.column("nu_pile").add(pile.mean);
    w_t.column("nu_pile_se").add(pile.se);
  }
  std::set<std::int64_t> windows;
  for (const auto& [k, c] : cells) windows.insert(k.first);
  p.results["windows"] = static_cast<std::int64_t>(windows.size());
  return p;
}

}  // namespace cdpile::analysis
