/// Local states of contacts (Staron, Vilotte & Radjai 2002, eqs 1 and 3, Figs 3-5).
///
/// The local state of contact i at radius r is eq (1) on the disk V of radius r centred
/// on i's contact point:
///
///     nu_i(r) = (critical contacts whose contact point is within r of i's point)
///             / (contacts whose contact point is within r of i's point),
///
/// "within" meaning distance <= r, contact i itself included unless `exclude_self`.
/// nu_bar(r) is the mean of nu_i(r) over the critical contacts (eq 3).
///
/// Neighbours come from a CGAL Kd_tree (spatial searching) over the contact points: one
/// fuzzy-sphere query of the largest radius per centre gives every radius at once.
/// Undefined local states (no contact in the neighbourhood, or a centre excluded by the
/// edge rule) are empty, never NaN.
#pragma once

#include "cdpile/error.hpp"

#include "cdpile/analysis/stats.hpp"
#include "cdpile/model.hpp"

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace cdpile::analysis {

/// How neighbourhoods that cross the edge of the pile are treated.
enum class EdgeRule {
  keep,     ///< default: the neighbourhood is the part of the disk inside the pile
  exclude,  ///< nu_i(r) is empty when r exceeds the centre's distance to the pile outline
};

struct LocalStateOptions {
  bool exclude_self = false;  ///< leave contact i out of its own neighbourhood
  EdgeRule edge = EdgeRule::keep;
  double outline_bin =
      0.0;  ///< [m] column width of the pile outline; > 0 with EdgeRule::exclude (tools use 1 D)
};

/// The outline of a pile seen from its contact points: the bounding box's left, right
/// and bottom sides, and a free surface made of the highest contact point in columns of
/// width `bin` (each column takes the maximum over itself and its two neighbours).
/// `distance(p)` is the smallest distance from p to the left, right, bottom sides or to
/// the surface measured vertically, >= 0. It approximates the distance to the pile's
/// edge; state it when using EdgeRule::exclude.
class PileOutline {
 public:
  PileOutline(std::span<const Vec2> points, double bin);
  double distance(const Vec2& p) const;
  double surface(double x) const;
  double xmin() const { return xmin_; }
  double xmax() const { return xmax_; }
  double ymin() const { return ymin_; }
  double ymax() const { return ymax_; }

 private:
  double xmin_ = 0, xmax_ = 0, ymin_ = 0, ymax_ = 0, bin_ = 1;
  std::vector<double> top_;
};

/// A spatial index over contact points (a CGAL Kd_tree); built once per frame.
class NeighbourIndex {
 public:
  explicit NeighbourIndex(std::span<const Vec2> points);
  ~NeighbourIndex();
  NeighbourIndex(NeighbourIndex&&) noexcept;
  NeighbourIndex& operator=(NeighbourIndex&&) noexcept;
  std::size_t size() const;
  /// Calls f(index, squared distance) for every point within r of `centre` (d <= r).
  void within(const Vec2& centre, double r,
              const std::function<void(std::uint32_t, double)>& f) const;
  /// The counts (all, critical) of points within each radius (ascending) of `centre`,
  /// cumulative: total[k] counts the points at distance <= radii[k]. `skip` is an index
  /// not to count (the centre itself), or -1.
  void count(const Vec2& centre, std::span<const double> radii_sq,
             std::span<const std::uint8_t> critical, std::int64_t skip, std::int32_t* total,
             std::int32_t* crit) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// nu_i(r) for a set of centres and a list of radii. Counts are cumulative in r.
class LocalStates {
 public:
  LocalStates() = default;
  LocalStates(std::size_t centres, std::size_t radii)
      : n_(centres), k_(radii), total_(centres * radii, 0), critical_(centres * radii, 0) {}
  std::size_t centres() const { return n_; }
  std::size_t radii() const { return k_; }
  /// Contacts within radius k of centre c (0 when undefined).
  std::int32_t total(std::size_t c, std::size_t k) const { return total_[c * k_ + k]; }
  std::int32_t critical(std::size_t c, std::size_t k) const { return critical_[c * k_ + k]; }
  /// nu_c(r_k), empty when the neighbourhood is empty or excluded.
  std::optional<double> nu(std::size_t c, std::size_t k) const {
    const std::int32_t t = total(c, k);
    if (t <= 0) return std::nullopt;
    return static_cast<double>(critical(c, k)) / static_cast<double>(t);
  }
  std::int32_t* total_row(std::size_t c) { return total_.data() + c * k_; }
  std::int32_t* critical_row(std::size_t c) { return critical_.data() + c * k_; }

 private:
  std::size_t n_ = 0, k_ = 0;
  std::vector<std::int32_t> total_, critical_;
};

/// Checks radii: finite, > 0, strictly increasing; throws cdpile::Error otherwise.
void validate_radii(std::span<const double> radii);

/// nu_i(r) of every contact (centres = the contacts themselves), for all `radii` [m]
/// (ascending). `points` and `critical` describe the contacts that count in one frame.
LocalStates local_states(std::span<const Vec2> points, std::span<const std::uint8_t> critical,
                         std::span<const double> radii, const LocalStateOptions& opt = {});

/// The same with an index built already, for a subset of centres (contact indices).
LocalStates local_states(const NeighbourIndex& index, std::span<const Vec2> points,
                         std::span<const std::uint8_t> critical, std::span<const double> radii,
                         std::span<const std::uint32_t> centres, const LocalStateOptions& opt = {});

/// Local states around arbitrary points (e.g. the nodes of a grid): the ratio of critical
/// contacts among the contacts within r of each point.
LocalStates local_states_at(const NeighbourIndex& index, std::span<const std::uint8_t> critical,
                            std::span<const Vec2> at, std::span<const double> radii);

/// The sums of nu_i(r_k) over the centres whose flag equals `which` (1: critical
/// contacts, giving nu_bar of eq 3; 0: non-critical ones). One Sums per radius; centres
/// with an undefined nu_i(r_k) are left out of that radius.
std::vector<Sums> state_sums(const LocalStates& s, std::span<const std::uint8_t> flag,
                             std::uint8_t which);

/// A histogram of values in [lo, hi] with equal bins; hi falls in the last bin, values
/// outside are counted in `outside`.
struct Histogram {
  double lo = 0.0, hi = 1.0;
  std::vector<std::int64_t> count;
  std::int64_t outside = 0;
  Histogram() = default;
  Histogram(double l, double h, std::size_t bins) : lo(l), hi(h), count(bins, 0) {}
  void add(double x);
  void add(const Histogram& o);
  std::int64_t total() const;
  double width() const { return (hi - lo) / static_cast<double>(count.size()); }
  double centre(std::size_t b) const { return lo + (static_cast<double>(b) + 0.5) * width(); }
  /// The probability density of bin b (count / (total width)); 0 when the histogram is empty.
  double density(std::size_t b) const;
};

/// Adds nu_i(r_k) of the centres flagged critical to `pc` and of the others to `pnc`
/// (the pdfs P_c and P_nc of Fig 3).
void add_to_pdfs(const LocalStates& s, std::span<const std::uint8_t> critical, std::size_t k,
                 Histogram& pc, Histogram& pnc);

/// The nu field on a regular grid (Fig 5): nodes x0 + a dx, y0 + b dx, a < nx, b < ny.
struct Field {
  double x0 = 0, y0 = 0, dx = 1;
  std::size_t nx = 0, ny = 0;
  double radius = 0;                ///< [m]
  std::vector<std::int32_t> total;  ///< contacts within radius of the node, [b * nx + a]
  std::vector<std::int32_t> critical;
  std::optional<double> nu(std::size_t a, std::size_t b) const {
    const std::int32_t t = total[b * nx + a];
    if (t <= 0) return std::nullopt;
    return static_cast<double>(critical[b * nx + a]) / static_cast<double>(t);
  }
};

/// The most nodes a field may have (8 bytes a node in each of three arrays: 2.4 GB).
inline constexpr double max_field_nodes = 1e8;

/// nu_field's grid would have more than max_field_nodes nodes; the caller names the
/// option that set the spacing.
class FieldTooLarge : public Error {
 public:
  explicit FieldTooLarge(double n) : Error("field grid too fine"), nodes(n) {}
  double nodes;
};

/// The field over the bounding box of the contact points, with node spacing `dx` [m];
/// FieldTooLarge beyond max_field_nodes.
Field nu_field(std::span<const Vec2> points, std::span<const std::uint8_t> critical, double radius,
               double dx);

}  // namespace cdpile::analysis
