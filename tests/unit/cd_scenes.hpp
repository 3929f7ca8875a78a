// Scenes of the cd unit tests: the scale of their disks and a hyperstatic stack.
#pragma once

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

}  // namespace cd_scenes
