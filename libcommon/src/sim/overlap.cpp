// The overlaps a run makes beyond its pile's (overlap.hpp; docs/method.md, "Warnings").
#include "cdpile/sim/overlap.hpp"

#include <algorithm>

namespace cdpile::sim {

std::uint64_t OverlapGrowth::pair(std::int32_t i, std::int32_t j) {
  // j may be a wall (< 0): its bits as an unsigned 32-bit number keep pairs distinct.
  return (std::uint64_t{static_cast<std::uint32_t>(i)} << 32) | static_cast<std::uint32_t>(j);
}

OverlapGrowth::OverlapGrowth(const Contacts& start) {
  for (std::size_t a = 0; a < start.size(); ++a)
    if (start.gap[a] < 0.0) start_.emplace_back(pair(start.i[a], start.j[a]), -start.gap[a]);
  std::sort(start_.begin(), start_.end());
}

double OverlapGrowth::grown(const Contacts& now) const {
  double most = 0.0;
  for (std::size_t a = 0; a < now.size(); ++a) {
    const double overlap = -now.gap[a];
    if (overlap <= most) continue;  // most contacts: no overlap, or less than found so far
    const std::uint64_t key = pair(now.i[a], now.j[a]);
    auto it = std::lower_bound(start_.begin(), start_.end(), std::make_pair(key, 0.0));
    const double before = (it != start_.end() && it->first == key) ? it->second : 0.0;
    most = std::max(most, overlap - before);
  }
  return most;
}

}  // namespace cdpile::sim
