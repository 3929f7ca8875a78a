#include "cdpile/analysis/series.hpp"

#include "cdpile/error.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace cdpile::analysis {

std::vector<Event> rearrangements(std::span<const std::int64_t> n, const EventRule& rule) {
  if (rule.hysteresis < 1) throw Error("event hysteresis must be >= 1 contact");
  if (rule.min_drop < 1) throw Error("event minimum drop must be >= 1 contact");
  std::vector<Event> events;
  if (n.empty()) return events;
  const std::int64_t h = rule.hysteresis;
  bool falling = false;
  std::size_t peak = 0, trough = 0;
  auto record = [&](bool open) {
    Event e;
    e.peak = peak;
    e.trough = trough;
    e.n_peak = n[peak];
    e.n_trough = n[trough];
    e.open = open;
    const std::int64_t drop = e.n_peak - e.n_trough;
    if (drop >= rule.min_drop && e.n_peak > 0) {
      e.loss = static_cast<double>(drop) / static_cast<double>(e.n_peak);
      events.push_back(e);
    }
  };
  for (std::size_t k = 1; k < n.size(); ++k) {
    if (!falling) {
      if (n[k] >= n[peak]) {
        peak = k;  // latest sample at the maximum: the state just before the drop
      } else if (n[peak] - n[k] >= h) {
        falling = true;
        trough = k;
      }
    } else {
      if (n[k] < n[trough]) {
        trough = k;  // first sample at the minimum
      } else if (n[k] - n[trough] >= h) {
        record(false);
        falling = false;
        peak = k;
      }
    }
  }
  if (falling) record(true);
  return events;
}

std::optional<std::size_t> Grid::bin(double x) const {
  if (count == 0 || !std::isfinite(x)) return std::nullopt;
  const double u = (x - start) / step;
  if (u < 0.0) {
    // the lower end allows round-off too: a grid started at a rounded first angle
    // (5.5 deg) must hold that angle read back from radians (5.499999999999999)
    if (x >= start - 1e-12 * std::max(1.0, std::abs(x))) return 0;
    return std::nullopt;
  }
  auto k = static_cast<std::size_t>(std::floor(u));
  if (k >= count) {
    // the upper end belongs to the last bin (allow round-off)
    if (x <= upper(count - 1) + 1e-12 * std::max(1.0, std::abs(x))) return count - 1;
    return std::nullopt;
  }
  return k;
}

Grid make_grid(double start, double stop, double step) {
  if (!(step > 0.0) || !std::isfinite(step)) throw Error("grid step must be > 0");
  if (!std::isfinite(start) || !std::isfinite(stop)) throw Error("grid bounds must be finite");
  Grid g;
  g.start = start;
  g.step = step;
  if (stop < start) return g;
  const double u = (stop - start) / step;
  g.count = static_cast<std::size_t>(std::ceil(u - 1e-9));
  if (g.count == 0) g.count = 1;
  return g;
}

namespace {
void check_lengths(std::span<const double> a, std::span<const double> b) {
  if (a.size() != b.size()) throw Error("theta and value series differ in length");
}
}  // namespace

std::vector<std::optional<double>> bin_mean(std::span<const double> theta,
                                            std::span<const double> value, const Grid& grid) {
  check_lengths(theta, value);
  std::vector<double> sum(grid.count, 0.0);
  std::vector<std::int64_t> cnt(grid.count, 0);
  for (std::size_t k = 0; k < theta.size(); ++k) {
    if (!std::isfinite(value[k])) continue;
    if (auto b = grid.bin(theta[k])) {
      sum[*b] += value[k];
      ++cnt[*b];
    }
  }
  std::vector<std::optional<double>> out(grid.count);
  for (std::size_t b = 0; b < grid.count; ++b)
    if (cnt[b]) out[b] = sum[b] / static_cast<double>(cnt[b]);
  return out;
}

std::vector<std::optional<double>> bin_max(std::span<const double> theta,
                                           std::span<const double> value, const Grid& grid,
                                           std::vector<std::optional<double>>* at) {
  check_lengths(theta, value);
  std::vector<std::optional<double>> out(grid.count);
  if (at) at->assign(grid.count, std::nullopt);
  for (std::size_t k = 0; k < theta.size(); ++k) {
    if (!std::isfinite(value[k])) continue;
    if (auto b = grid.bin(theta[k])) {
      if (!out[*b] || value[k] > *out[*b]) {
        out[*b] = value[k];
        if (at) (*at)[*b] = theta[k];
      }
    }
  }
  return out;
}

std::vector<Summary> across_runs(const std::vector<std::vector<std::optional<double>>>& per_run,
                                 std::size_t bins) {
  std::vector<Summary> out(bins);
  std::vector<double> v;
  for (std::size_t b = 0; b < bins; ++b) {
    v.clear();
    for (const auto& run : per_run)
      if (b < run.size() && run[b]) v.push_back(*run[b]);
    out[b] = summarize(v);
  }
  return out;
}

std::optional<std::size_t> avalanche_index(std::span<const double> theta,
                                           std::span<const double> energy,
                                           const AvalancheRule& rule) {
  check_lengths(theta, energy);
  if (!(rule.threshold > 0.0)) throw Error("avalanche threshold must be > 0");
  if (!(rule.hold >= 0.0)) throw Error("avalanche hold must be >= 0 deg");
  const std::size_t n = theta.size();
  // Scan from the end: `above_until[k]` is whether every sample from k to the end of the
  // hold window is above the threshold. A single forward pass with the index of the next
  // sample below the threshold does it in O(n).
  std::vector<std::size_t> next_below(n + 1, n);
  for (std::size_t k = n; k-- > 0;)
    next_below[k] = avalanche_agitated(energy[k], rule.threshold) ? next_below[k + 1] : k;
  for (std::size_t k = 0; k < n; ++k) {
    if (!avalanche_agitated(energy[k], rule.threshold)) continue;
    const std::size_t b = next_below[k];
    if (b == n || theta[b] > theta[k] + rule.hold) return k;
  }
  return std::nullopt;
}

}  // namespace cdpile::analysis
