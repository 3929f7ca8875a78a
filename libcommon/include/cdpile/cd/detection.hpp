/// Contact detection, stage 2 of a step (docs/method.md, "The scheme"): the candidate
/// contacts of grains at their predicted positions, with the walls and with each other,
/// found with a cell grid. Kept apart from the engine as Box2D keeps its broad phase apart
/// from its solver: it reads positions, radii and margins, and writes rows.
#pragma once

#include "cdpile/cd/contact_system.hpp"
#include "cdpile/cd/team.hpp"
#include "cdpile/model.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace cdpile::cd {

/// What detection reads of the grains, one entry per grain.
struct DetectionInput {
  std::span<const Vec2> position;    ///< predicted positions [m]
  std::span<const double> radius;    ///< [m]
  std::span<const double> margin;    ///< how far the grain can travel in the step [m]
  std::span<const double> inv_mass;  ///< 0: a glued grain (no wall rows, no glued pairs)
  double width = 0.0;                ///< the box: walls x = 0, x = width, y = 0 [m]
  double alert = 0.0;                ///< the alert distance [m]
};

class ContactDetection {
 public:
  /// Replaces `rows` by every candidate: for each grain i in order, its walls (right, left,
  /// floor) and then the grains j > i in increasing j whose gap is below the alert distance
  /// plus both margins. Each row has i, j, bi, bj (a wall is body N), the normal from j to i
  /// and the gap; the rest is the caller's. The same list on any number of threads of
  /// `team` (null: one).
  void detect(const DetectionInput& in, std::vector<ContactRow>& rows, Team* team);

 private:
  // The cell grid of the predicted positions: counting sort, row-major (cy then cx).
  void build_grid(const DetectionInput& in, double r_max, double m_max);
  void cell_of(const Vec2& p, std::int32_t& cx, std::int32_t& cy) const;
  // The candidates of grain i, appended to out (neighbours: scratch).
  void detect_grain(const DetectionInput& in, std::size_t i, std::vector<ContactRow>& out,
                    std::vector<std::int32_t>& neighbours) const;

  Vec2 lo_ = Vec2::Zero();
  double cell_ = 0.0;
  std::int32_t nx_ = 0, ny_ = 0;
  std::vector<std::int32_t> cell_start_, cell_items_;
  // The candidates of a range of grains and that range's neighbour list, one per thread
  struct Part {
    std::vector<ContactRow> rows;
    std::vector<std::int32_t> neighbours;
  };
  std::vector<Part> parts_;
};

}  // namespace cdpile::cd
