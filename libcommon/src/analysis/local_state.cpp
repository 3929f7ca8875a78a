#include "cdpile/analysis/local_state.hpp"

#include "cdpile/error.hpp"

#include <CGAL/Fuzzy_sphere.h>
#include <CGAL/Kd_tree.h>
#include <CGAL/Search_traits_2.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/property_map.h>
#include <boost/iterator/counting_iterator.hpp>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <string>

namespace cdpile::analysis {

// ---------------------------------------------------------------------------------
// CGAL spatial searching: a Kd_tree of contact indices, keyed to their points through a
// property map, queried with a Fuzzy_sphere of radius r and epsilon 0 (exact range).

namespace {
using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_2;
using PointMap = CGAL::Pointer_property_map<Point>::const_type;
using BaseTraits = CGAL::Search_traits_2<Kernel>;
using Traits = CGAL::Search_traits_adapter<std::size_t, PointMap, BaseTraits>;
using Tree = CGAL::Kd_tree<Traits>;
using Sphere = CGAL::Fuzzy_sphere<Traits>;

// The tree reports through an output iterator that it copies and assigns, so the callback
// must be assignable: a pointer to the caller's callable, not a capturing lambda.
template <class F>
struct CallbackIterator {
  using iterator_category = std::output_iterator_tag;
  using value_type = void;
  using difference_type = std::ptrdiff_t;
  using pointer = void;
  using reference = void;
  F* f;
  CallbackIterator& operator*() { return *this; }
  CallbackIterator& operator++() { return *this; }
  CallbackIterator operator++(int) { return *this; }
  CallbackIterator& operator=(std::size_t k) {
    (*f)(k);
    return *this;
  }
};
template <class F>
CallbackIterator<F> reporter(F& f) {
  return CallbackIterator<F>{&f};
}
}  // namespace

struct NeighbourIndex::Impl {
  std::vector<Point> points;
  Traits traits;
  Tree tree;
  explicit Impl(std::span<const Vec2> p)
      : points(make(p)),
        traits(PointMap(points.data())),
        tree(boost::counting_iterator<std::size_t>(0),
             boost::counting_iterator<std::size_t>(points.size()), Tree::Splitter(), traits) {
    if (!points.empty()) tree.build();
  }
  static std::vector<Point> make(std::span<const Vec2> p) {
    std::vector<Point> out;
    out.reserve(p.size());
    for (const Vec2& v : p) {
      if (!std::isfinite(v.x()) || !std::isfinite(v.y()))
        throw Error("a contact point is not finite");
      out.emplace_back(v.x(), v.y());
    }
    return out;
  }
};

NeighbourIndex::NeighbourIndex(std::span<const Vec2> points)
    : impl_(std::make_unique<Impl>(points)) {
  if (points.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    throw Error("too many contacts in one frame for the neighbour index");
}
NeighbourIndex::~NeighbourIndex() = default;
NeighbourIndex::NeighbourIndex(NeighbourIndex&&) noexcept = default;
NeighbourIndex& NeighbourIndex::operator=(NeighbourIndex&&) noexcept = default;
std::size_t NeighbourIndex::size() const { return impl_->points.size(); }

void NeighbourIndex::within(const Vec2& centre, double r,
                            const std::function<void(std::uint32_t, double)>& f) const {
  if (impl_->points.empty()) return;
  const Point c(centre.x(), centre.y());
  const double r2 = r * r;
  const auto& pts = impl_->points;
  auto visit = [&](std::size_t k) {
    const double dx = pts[k].x() - c.x(), dy = pts[k].y() - c.y();
    const double d2 = dx * dx + dy * dy;
    if (d2 <= r2) f(static_cast<std::uint32_t>(k), d2);
  };
  impl_->tree.search(reporter(visit), Sphere(c, r, 0.0, impl_->traits));
}

void NeighbourIndex::count(const Vec2& centre, std::span<const double> radii_sq,
                           std::span<const std::uint8_t> critical, std::int64_t skip,
                           std::int32_t* total, std::int32_t* crit) const {
  const std::size_t nk = radii_sq.size();
  std::fill(total, total + nk, 0);
  std::fill(crit, crit + nk, 0);
  if (impl_->points.empty() || nk == 0) return;
  const double rmax2 = radii_sq.back();
  const Point c(centre.x(), centre.y());
  const auto& pts = impl_->points;
  const double* r2 = radii_sq.data();
  // Per-radius bin counts first (the smallest k with d^2 <= r_k^2), then a prefix sum:
  // one query of the largest radius gives every radius.
  auto visit = [&](std::size_t k) {
    if (static_cast<std::int64_t>(k) == skip) return;
    const double dx = pts[k].x() - c.x(), dy = pts[k].y() - c.y();
    const double d2 = dx * dx + dy * dy;
    if (d2 > rmax2) return;
    const auto b = static_cast<std::size_t>(std::lower_bound(r2, r2 + nk, d2) - r2);
    ++total[b];
    crit[b] += critical[k];
  };
  impl_->tree.search(reporter(visit), Sphere(c, std::sqrt(rmax2), 0.0, impl_->traits));
  for (std::size_t b = 1; b < nk; ++b) {
    total[b] += total[b - 1];
    crit[b] += crit[b - 1];
  }
}

// ---------------------------------------------------------------------------------

PileOutline::PileOutline(std::span<const Vec2> points, double bin) : bin_(bin) {
  if (!(bin > 0.0) || !std::isfinite(bin)) throw Error("pile outline column width must be > 0");
  if (points.empty()) return;
  xmin_ = xmax_ = points[0].x();
  ymin_ = ymax_ = points[0].y();
  for (const Vec2& p : points) {
    xmin_ = std::min(xmin_, p.x());
    xmax_ = std::max(xmax_, p.x());
    ymin_ = std::min(ymin_, p.y());
    ymax_ = std::max(ymax_, p.y());
  }
  const auto cols = static_cast<std::size_t>(std::floor((xmax_ - xmin_) / bin_)) + 1;
  std::vector<double> raw(cols, -std::numeric_limits<double>::infinity());
  for (const Vec2& p : points) {
    const auto c = std::min(cols - 1, static_cast<std::size_t>((p.x() - xmin_) / bin_));
    raw[c] = std::max(raw[c], p.y());
  }
  top_.assign(cols, ymin_);
  for (std::size_t c = 0; c < cols; ++c) {
    double t = raw[c];
    if (c > 0) t = std::max(t, raw[c - 1]);
    if (c + 1 < cols) t = std::max(t, raw[c + 1]);
    top_[c] = std::isfinite(t) ? t : ymin_;
  }
}

double PileOutline::surface(double x) const {
  if (top_.empty()) return ymin_;
  const double u = std::clamp((x - xmin_) / bin_, 0.0, static_cast<double>(top_.size() - 1));
  return top_[static_cast<std::size_t>(u)];
}

double PileOutline::distance(const Vec2& p) const {
  const double d = std::min({p.x() - xmin_, xmax_ - p.x(), p.y() - ymin_, surface(p.x()) - p.y()});
  return std::max(0.0, d);
}

// ---------------------------------------------------------------------------------

void validate_radii(std::span<const double> radii) {
  if (radii.empty()) throw Error("no radius given");
  for (std::size_t k = 0; k < radii.size(); ++k) {
    if (!std::isfinite(radii[k]) || !(radii[k] > 0.0)) throw Error("radii must be finite and > 0");
    if (k > 0 && !(radii[k] > radii[k - 1])) throw Error("radii must be strictly increasing");
  }
}

namespace {
std::vector<double> squares(std::span<const double> radii) {
  std::vector<double> r2(radii.size());
  for (std::size_t k = 0; k < radii.size(); ++k) r2[k] = radii[k] * radii[k];
  return r2;
}
void check_sizes(std::span<const Vec2> points, std::span<const std::uint8_t> critical) {
  if (points.size() != critical.size())
    throw Error("contact points and critical flags differ in number");
}
}  // namespace

LocalStates local_states(std::span<const Vec2> points, std::span<const std::uint8_t> critical,
                         std::span<const double> radii, const LocalStateOptions& opt) {
  check_sizes(points, critical);
  NeighbourIndex index(points);
  std::vector<std::uint32_t> all(points.size());
  for (std::size_t k = 0; k < all.size(); ++k) all[k] = static_cast<std::uint32_t>(k);
  return local_states(index, points, critical, radii, all, opt);
}

LocalStates local_states(const NeighbourIndex& index, std::span<const Vec2> points,
                         std::span<const std::uint8_t> critical, std::span<const double> radii,
                         std::span<const std::uint32_t> centres, const LocalStateOptions& opt) {
  check_sizes(points, critical);
  validate_radii(radii);
  if (index.size() != points.size()) throw Error("neighbour index built on other points");
  const std::vector<double> r2 = squares(radii);
  LocalStates out(centres.size(), radii.size());
  std::optional<PileOutline> outline;
  if (opt.edge == EdgeRule::exclude) outline.emplace(points, opt.outline_bin);
  for (std::size_t c = 0; c < centres.size(); ++c) {
    const std::uint32_t i = centres[c];
    if (i >= points.size()) throw Error("centre index out of range");
    std::int32_t* tot = out.total_row(c);
    std::int32_t* cr = out.critical_row(c);
    index.count(points[i], r2, critical, opt.exclude_self ? static_cast<std::int64_t>(i) : -1, tot,
                cr);
    if (outline) {
      const double d = outline->distance(points[i]);
      for (std::size_t k = 0; k < radii.size(); ++k)
        if (radii[k] > d) {
          tot[k] = 0;
          cr[k] = 0;
        }
    }
  }
  return out;
}

LocalStates local_states_at(const NeighbourIndex& index, std::span<const std::uint8_t> critical,
                            std::span<const Vec2> at, std::span<const double> radii) {
  validate_radii(radii);
  if (index.size() != critical.size()) throw Error("critical flags and index differ in size");
  const std::vector<double> r2 = squares(radii);
  LocalStates out(at.size(), radii.size());
  for (std::size_t c = 0; c < at.size(); ++c)
    index.count(at[c], r2, critical, -1, out.total_row(c), out.critical_row(c));
  return out;
}

std::vector<Sums> state_sums(const LocalStates& s, std::span<const std::uint8_t> flag,
                             std::uint8_t which) {
  if (flag.size() != s.centres()) throw Error("flags and local states differ in number");
  std::vector<Sums> out(s.radii());
  for (std::size_t c = 0; c < s.centres(); ++c) {
    if (flag[c] != which) continue;
    for (std::size_t k = 0; k < s.radii(); ++k)
      if (auto v = s.nu(c, k)) out[k].add(*v);
  }
  return out;
}

void Histogram::add(double x) {
  if (count.empty() || !(x >= lo && x <= hi)) {
    ++outside;
    return;
  }
  auto b = static_cast<std::size_t>((x - lo) / width());
  if (b >= count.size()) b = count.size() - 1;
  ++count[b];
}

void Histogram::add(const Histogram& o) {
  if (o.count.size() != count.size() || o.lo != lo || o.hi != hi)
    throw Error("cannot add histograms with different bins");
  for (std::size_t b = 0; b < count.size(); ++b) count[b] += o.count[b];
  outside += o.outside;
}

std::int64_t Histogram::total() const {
  std::int64_t t = 0;
  for (auto c : count) t += c;
  return t;
}

double Histogram::density(std::size_t b) const {
  const std::int64_t t = total();
  if (t == 0) return 0.0;
  return static_cast<double>(count[b]) / (static_cast<double>(t) * width());
}

void add_to_pdfs(const LocalStates& s, std::span<const std::uint8_t> critical, std::size_t k,
                 Histogram& pc, Histogram& pnc) {
  if (critical.size() != s.centres()) throw Error("flags and local states differ in number");
  if (k >= s.radii()) throw Error("pdf radius index out of range");
  for (std::size_t c = 0; c < s.centres(); ++c)
    if (auto v = s.nu(c, k)) (critical[c] ? pc : pnc).add(*v);
}

Field nu_field(std::span<const Vec2> points, std::span<const std::uint8_t> critical, double radius,
               double dx) {
  check_sizes(points, critical);
  if (!(dx > 0.0) || !std::isfinite(dx)) throw Error("field grid spacing must be > 0");
  if (!(radius > 0.0) || !std::isfinite(radius)) throw Error("field radius must be > 0");
  Field f;
  f.dx = dx;
  f.radius = radius;
  if (points.empty()) return f;
  double xmin = points[0].x(), xmax = xmin, ymin = points[0].y(), ymax = ymin;
  for (const Vec2& p : points) {
    xmin = std::min(xmin, p.x());
    xmax = std::max(xmax, p.x());
    ymin = std::min(ymin, p.y());
    ymax = std::max(ymax, p.y());
  }
  f.x0 = xmin;
  f.y0 = ymin;
  // Counted in doubles: points far apart (a damaged file) would overflow size_t.
  const double nodes_x = std::floor((xmax - xmin) / dx) + 1,
               nodes_y = std::floor((ymax - ymin) / dx) + 1;
  if (!(nodes_x * nodes_y <= max_field_nodes)) throw FieldTooLarge(nodes_x * nodes_y);
  f.nx = static_cast<std::size_t>(nodes_x);
  f.ny = static_cast<std::size_t>(nodes_y);
  std::vector<Vec2> nodes;
  nodes.reserve(f.nx * f.ny);
  for (std::size_t b = 0; b < f.ny; ++b)
    for (std::size_t a = 0; a < f.nx; ++a)
      nodes.emplace_back(f.x0 + static_cast<double>(a) * dx, f.y0 + static_cast<double>(b) * dx);
  NeighbourIndex index(points);
  const double r[1] = {radius};
  LocalStates s = local_states_at(index, critical, nodes, r);
  f.total.resize(nodes.size());
  f.critical.resize(nodes.size());
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    f.total[n] = s.total(n, 0);
    f.critical[n] = s.critical(n, 0);
  }
  return f;
}

}  // namespace cdpile::analysis
