// Contact detection (cd/detection.hpp; docs/method.md, "The scheme", stage 2).
#include "cdpile/cd/detection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cdpile::cd {

void ContactDetection::build_grid(const DetectionInput& in, double r_max, double m_max) {
  const std::size_t n = in.position.size();
  lo_ = Vec2(std::numeric_limits<double>::max(), std::numeric_limits<double>::max());
  Vec2 hi = -lo_;
  for (const Vec2& p : in.position) {
    lo_ = lo_.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  // A cell is at least as wide as the largest interaction range, so pairs are in
  // neighbouring cells; it is widened if scattered grains would need too many.
  cell_ = 2.0 * r_max + in.alert + 2.0 * m_max;
  const Vec2 extent = hi - lo_;
  const double max_cells = 4.0 * static_cast<double>(n) + 16.0;
  if ((extent.x() / cell_ + 1.0) * (extent.y() / cell_ + 1.0) > max_cells)
    cell_ =
        std::max(cell_, std::sqrt((extent.x() + cell_) * (extent.y() + cell_) / max_cells) * 1.01);
  nx_ = static_cast<std::int32_t>(extent.x() / cell_) + 1;
  ny_ = static_cast<std::int32_t>(extent.y() / cell_) + 1;
  // Counting sort of the grains into cells (row-major, cy then cx): deterministic.
  cell_start_.assign(static_cast<std::size_t>(nx_) * ny_ + 1, 0);
  cell_items_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::int32_t cx, cy;
    cell_of(in.position[i], cx, cy);
    ++cell_start_[static_cast<std::size_t>(cy) * nx_ + cx + 1];
  }
  for (std::size_t c = 1; c < cell_start_.size(); ++c) cell_start_[c] += cell_start_[c - 1];
  std::vector<std::int32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) {
    std::int32_t cx, cy;
    cell_of(in.position[i], cx, cy);
    cell_items_[fill[static_cast<std::size_t>(cy) * nx_ + cx]++] = static_cast<std::int32_t>(i);
  }
}

void ContactDetection::cell_of(const Vec2& p, std::int32_t& cx, std::int32_t& cy) const {
  cx = std::min(nx_ - 1, static_cast<std::int32_t>((p.x() - lo_.x()) / cell_));
  cy = std::min(ny_ - 1, static_cast<std::int32_t>((p.y() - lo_.y()) / cell_));
}

// The candidates of grain i (with j > i, and its walls), in the order of j: a grain's rows
// depend on nothing but the grains, so ranges of grains are detected apart and their rows
// put one after the other give the same list on any number of threads.
void ContactDetection::detect_grain(const DetectionInput& in, std::size_t ui,
                                    std::vector<ContactRow>& out,
                                    std::vector<std::int32_t>& neighbours) const {
  const std::size_t n = in.position.size();
  const auto i = static_cast<std::int32_t>(ui);
  auto add_row = [&](std::int32_t j, double gap, const Vec2& normal) {
    ContactRow r{};
    r.i = i;
    r.j = j;
    r.bi = i;
    r.bj = j < 0 ? static_cast<std::int32_t>(n) : j;
    r.nx = normal.x();
    r.ny = normal.y();
    r.gap = gap;
    out.push_back(r);
  };
  const Vec2& xi = in.position[ui];
  const double ri = in.radius[ui];
  const double reach = in.alert + in.margin[ui];
  if (in.inv_mass[ui] != 0.0) {  // walls, in the order of their ids: right, left, floor
    const double g_right = in.width - xi.x() - ri;
    if (g_right < reach) add_row(wall_right, g_right, Vec2(-1.0, 0.0));
    const double g_left = xi.x() - ri;
    if (g_left < reach) add_row(wall_left, g_left, Vec2(1.0, 0.0));
    const double g_floor = xi.y() - ri;
    if (g_floor < reach) add_row(wall_floor, g_floor, Vec2(0.0, 1.0));
  }
  std::int32_t cx, cy;
  cell_of(xi, cx, cy);
  neighbours.clear();
  for (std::int32_t y = std::max(0, cy - 1); y <= std::min(ny_ - 1, cy + 1); ++y)
    for (std::int32_t x = std::max(0, cx - 1); x <= std::min(nx_ - 1, cx + 1); ++x) {
      const std::size_t c = static_cast<std::size_t>(y) * nx_ + x;
      for (std::int32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
        const std::int32_t j = cell_items_[k];
        if (j <= i) continue;
        const auto uj = static_cast<std::size_t>(j);
        if (in.inv_mass[ui] == 0.0 && in.inv_mass[uj] == 0.0) continue;  // two glued grains
        const double d = (xi - in.position[uj]).norm();
        if (d - ri - in.radius[uj] < reach + in.margin[uj]) neighbours.push_back(j);
      }
    }
  std::sort(neighbours.begin(), neighbours.end());
  for (const std::int32_t j : neighbours) {
    const Vec2 dx = xi - in.position[static_cast<std::size_t>(j)];
    const double d = dx.norm();
    // Coincident centres cannot happen without a huge overlap; keep a valid normal.
    const Vec2 normal = d > 0.0 ? Vec2(dx / d) : Vec2(0.0, 1.0);
    add_row(j, d - ri - in.radius[static_cast<std::size_t>(j)], normal);
  }
}

void ContactDetection::detect(const DetectionInput& in, std::vector<ContactRow>& rows, Team* team) {
  const std::size_t n = in.position.size();
  rows.clear();
  if (n == 0) return;
  double r_max = 0.0, m_max = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    r_max = std::max(r_max, in.radius[i]);
    m_max = std::max(m_max, in.margin[i]);
  }
  build_grid(in, r_max, m_max);
  const auto threads = team ? static_cast<std::size_t>(team->size()) : std::size_t{1};
  parts_.resize(threads);
  if (threads == 1 || n < team->smallest_shared()) {
    for (std::size_t i = 0; i < n; ++i) detect_grain(in, i, rows, parts_[0].neighbours);
    return;
  }
  // Each thread detects its range of grains into its own part (the first thread's part is
  // the rows themselves), then copies the part to its place in the rows (the parts' sizes
  // summed in thread order).
  std::vector<std::size_t> offset(threads + 1, 0);
  team->run([&](int t) {
    const auto u = static_cast<std::size_t>(t);
    Part& part = parts_[u];
    std::vector<ContactRow>& mine = u == 0 ? rows : part.rows;
    mine.clear();
    for (std::size_t i = n * u / threads; i < n * (u + 1) / threads; ++i)
      detect_grain(in, i, mine, part.neighbours);
    offset[u + 1] = mine.size();
    team->barrier();
    if (u == 0) {
      for (std::size_t k = 0; k < threads; ++k) offset[k + 1] += offset[k];
      rows.resize(offset[threads]);
    }
    team->barrier();
    if (u > 0)
      std::copy(part.rows.begin(), part.rows.end(),
                rows.begin() + static_cast<std::ptrdiff_t>(offset[u]));
  });
}

}  // namespace cdpile::cd
