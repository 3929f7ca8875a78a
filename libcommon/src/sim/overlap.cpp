// The overlaps a run makes beyond its pile's (overlap.hpp; docs/method.md, "Warnings").
#include "cdpile/sim/overlap.hpp"

#include "cdpile/cd/contact_system.hpp"

#include <algorithm>

namespace cdpile::sim {

OverlapGrowth::OverlapGrowth(const Contacts& start) {
  for (std::size_t a = 0; a < start.size(); ++a)
    if (start.gap[a] < 0.0)
      start_.emplace_back(cd::pair_key(start.i[a], start.j[a]), -start.gap[a]);
  std::sort(start_.begin(), start_.end());
}

double OverlapGrowth::grown(const Contacts& now) const {
  // The engine's contacts come in pair order (cd::pair_key, as start_): one merge walk.
  // Contacts in any other order are still right, found by a binary search.
  double most = 0.0;
  auto it = start_.begin();
  std::uint64_t last = 0;
  for (std::size_t a = 0; a < now.size(); ++a) {
    const double overlap = -now.gap[a];
    if (overlap <= most) continue;  // most contacts: no overlap, or less than found so far
    const std::uint64_t key = cd::pair_key(now.i[a], now.j[a]);
    if (key < last) it = start_.begin();
    last = key;
    while (it != start_.end() && it->first < key) ++it;
    const double before = (it != start_.end() && it->first == key) ? it->second : 0.0;
    most = std::max(most, overlap - before);
  }
  return most;
}

}  // namespace cdpile::sim
