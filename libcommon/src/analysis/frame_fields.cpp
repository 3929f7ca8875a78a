#include "cdpile/analysis/frame_fields.hpp"

#include "cdpile/analysis/local_state.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cdpile::analysis {

FrameFields frame_fields(const Contacts& c, const Grains& g, const Friction& mu,
                         const CriticalRule& rule, double nu_radius) {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  const std::size_t N = g.size(), nc = c.size();
  FrameFields f;
  // nu of every grain: the local state at its centre.
  f.nu.assign(N, nan);
  const ContactSet set = select_contacts(c, g.species, mu, rule);
  if (set.size() > 0) {
    const std::vector<double> radii{nu_radius};
    const NeighbourIndex index(set.point);
    const LocalStates st = local_states_at(index, set.critical, g.position, radii);
    for (std::size_t k = 0; k < N; ++k)
      if (auto v = st.nu(k, 0)) f.nu[k] = *v;
  }
  f.critical.resize(nc);
  f.mobilisation.resize(nc);
  f.fn_rel.resize(nc);
  double fn_sum = 0;
  std::size_t active = 0;
  for (std::size_t q = 0; q < nc; ++q)
    if (c.fn[q] > 0) fn_sum += c.fn[q], ++active;
  const double fn_mean = active ? fn_sum / static_cast<double>(active) : 0.0;
  for (std::size_t q = 0; q < nc; ++q) {
    const double m = c.j[q] < 0 ? mu.wall : mu.grain;
    f.critical[q] = is_critical(c.fn[q], c.ft[q], m, rule.eps) ? 1 : 0;
    f.mobilisation[q] = c.fn[q] > 0 ? std::abs(c.ft[q]) / (m * c.fn[q]) : nan;
    f.fn_rel[q] = fn_mean > 0 ? c.fn[q] / fn_mean : 0.0;
  }
  return f;
}

void ColourRanges::add(const FrameFields& f) {
  for (double v : f.nu)
    if (!std::isnan(v)) nu_max_ = std::max(nu_max_, v);
  fn_rel_.insert(fn_rel_.end(), f.fn_rel.begin(), f.fn_rel.end());
}

double ColourRanges::fn_rel_high() const {
  if (fn_rel_.empty()) return 0;
  std::vector<double> v = fn_rel_;
  const auto at = v.begin() + static_cast<std::ptrdiff_t>(0.99 * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), at, v.end());
  return *at;
}

}  // namespace cdpile::analysis
