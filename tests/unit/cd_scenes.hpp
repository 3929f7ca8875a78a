// Scenes of the cd unit tests: the scale of their disks, a hyperstatic stack and a wedged
// disk.
#pragma once

#include "cdpile/cd/contact_system.hpp"
#include "cdpile/model.hpp"

#include <cmath>
#include <numbers>

namespace cd_scenes {

inline constexpr double kDeg = std::numbers::pi / 180.0;
inline constexpr double kR = 0.5e-3;    // disk radius [m]
inline constexpr double kRho = 2500.0;  // [kg/m^3]
inline constexpr double kG = 9.81;      // [m/s^2]

/// A triangular stack of disks of radius kR between the side walls of a box 2 base kR
/// wide, `base` disks on the floor and one fewer on each row above: every disk touches its
/// neighbours, a hyperstatic network.
inline cdpile::Grains triangular_stack(int base) {
  cdpile::Grains g;
  const double r3 = std::sqrt(3.0) * kR;
  for (int row = 0; row < base; ++row)
    for (int k = 0; k < base - row; ++k)
      g.add_disk(kR, kRho, cdpile::Vec2((1 + row + 2 * k) * kR, kR + row * r3));
  return g;
}

/// A disk of radius kR wedged between the two side walls of a box 2 kR wide, far above
/// the floor, at rest under gravity g = (0, -g), time step h: two contacts, no floor.
/// Rows in pair order: the right wall (j = -1, n = (-1, 0)) then the left wall (j = -2,
/// n = (1, 0)). Impulses start at (rn, rt) = start for both rows (rt signed so that both
/// hold the disk up), anchored at `anchor` the same way; `stiffness` k [N/m^2] gives the
/// compliance 1/(k h^2), 0 rigid contacts.
struct Wedge {
  cdpile::cd::ContactSystem system;
  double m = 0.0;
};

inline Wedge wedged_disk(double start_n, double anchor_n, double anchor_t, double stiffness,
                         double h) {
  Wedge w;
  w.m = kRho * std::numbers::pi * kR * kR;
  const double inv_m = 1.0 / w.m, inv_i = 2.0 / (w.m * kR * kR);
  cdpile::cd::ContactSystem& s = w.system;
  s.bodies = {{0.0, -kG * h, 0.0, inv_m, inv_i}, {0.0, 0.0, 0.0, 0.0, 0.0}};
  if (stiffness > 0.0) s.compliance_n = s.compliance_t = 1.0 / (stiffness * h * h);
  // Tangent t = (-n_y, n_x): (0, -1) on the right wall, (0, 1) on the left one, so a
  // supporting friction impulse is -a on the right and +a on the left.
  for (const double nx : {-1.0, 1.0}) {
    cdpile::cd::ContactRow r{};
    r.i = 0;
    r.j = nx < 0 ? cdpile::wall_right : cdpile::wall_left;
    r.bi = 0;
    r.bj = 1;
    r.nx = nx;
    r.ny = 0.0;
    r.ri = kR;
    r.rj = 0.0;
    r.mu = 0.5;
    r.gap = 0.0;
    r.gap_velocity = 0.0;
    r.w_nn = inv_m + s.compliance_n;
    r.w_tt = inv_m + kR * kR * inv_i + s.compliance_t;
    const double sign = nx < 0 ? -1.0 : 1.0;
    r.rn0 = anchor_n;
    r.rt0 = sign * anchor_t;
    r.rn = start_n;
    r.rt = sign * anchor_t;
    s.rows.push_back(r);
  }
  for (const cdpile::cd::ContactRow& r : s.rows) s.apply_impulse(r, r.rn, r.rt);
  return w;
}

}  // namespace cd_scenes
