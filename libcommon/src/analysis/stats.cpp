#include "cdpile/analysis/stats.hpp"

#include <algorithm>
#include <cmath>

namespace cdpile::analysis {

Summary summarize(std::span<const double> samples) {
  Summary s;
  s.n = static_cast<std::int64_t>(samples.size());
  if (samples.empty()) return s;
  double mean = 0.0;
  for (double x : samples) mean += x;
  mean /= static_cast<double>(samples.size());
  s.mean = mean;
  if (samples.size() >= 2) {
    double ss = 0.0;
    for (double x : samples) ss += (x - mean) * (x - mean);
    const double sd = std::sqrt(ss / static_cast<double>(samples.size() - 1));
    s.sd = sd;
    s.se = sd / std::sqrt(static_cast<double>(samples.size()));
  }
  return s;
}

Summary Sums::summary() const {
  Summary s;
  s.n = n;
  if (n == 0) return s;
  const double dn = static_cast<double>(n);
  const double mean = sum / dn;
  s.mean = mean;
  if (n >= 2) {
    const double var = std::max(0.0, (sum2 - dn * mean * mean) / (dn - 1.0));
    s.sd = std::sqrt(var);
    s.se = std::sqrt(var / dn);
  }
  return s;
}

const char* se_over_name(SeOver s) {
  switch (s) {
    case SeOver::contacts: return "contacts";
    case SeOver::frames: return "frames";
    case SeOver::runs: return "runs";
    default: return "none";
  }
}

Pooled pooled_mean(std::span<const Sums> clusters, SeOver cluster_kind) {
  Pooled p;
  Sums all;
  for (const Sums& c : clusters) {
    if (c.n == 0) continue;
    all.add(c);
    ++p.clusters;
  }
  p.n = all.n;
  if (all.n == 0) return p;
  const double mean = all.sum / static_cast<double>(all.n);
  p.mean = mean;
  if (p.clusters >= 2) {
    double ss = 0.0;
    for (const Sums& c : clusters) {
      if (c.n == 0) continue;
      const double d = c.sum - mean * static_cast<double>(c.n);
      ss += d * d;
    }
    const double nc = static_cast<double>(p.clusters);
    const double total = static_cast<double>(all.n);
    p.se = std::sqrt(nc / (nc - 1.0) * ss) / total;
    p.over = cluster_kind;
  } else {
    const Summary s = all.summary();
    p.se = s.se;
    p.over = s.se ? SeOver::contacts : SeOver::none;
  }
  return p;
}

}  // namespace cdpile::analysis
