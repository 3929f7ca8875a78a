// A run of three grains in a row whose contacts are known, for the views' tests (io's
// writers, reading's flags): (0, 1) critical (|f_t| = mu f_n with mu 0.5), (1, 2) not, (2,
// floor) a wall contact, so f_n / <f_n> is 2/2, 1/2, 3/2. The run records mu_grain = mu_wall
// = 0.5 and critical_eps = 1e-3.
#pragma once

#include "cdpile/io/h5.hpp"
#include "cdpile/io/schema.hpp"

#include <string>

namespace cdpile::test {

/// The run, written to `path`.
inline void three_in_a_row(const std::string& path) {
  io::RunHeader h;
  h.kind = "run";
  h.box = {0.006, 0.004};
  h.parameters = {{"mu_grain", 0.5}, {"mu_wall", 0.5}, {"critical_eps", 1e-3}};
  Frame fr;
  for (int g = 0; g < 3; ++g) fr.grains.add_disk(0.001, 2500, Vec2(0.001 + 0.002 * g, 0.001));
  fr.step = 40;
  fr.time = 0.004;
  fr.tilt_angle = 0.1;
  const Vec2 x{1, 0}, y{0, 1};
  fr.contacts.push_back(1, 0, Vec2(0.002, 0.001), x, 2.0, 1.0, 0, ContactStatus::slide);
  fr.contacts.push_back(2, 1, Vec2(0.004, 0.001), x, 1.0, 0.1, 0, ContactStatus::stick);
  fr.contacts.push_back(2, wall_floor, Vec2(0.005, 0.0), y, 3.0, 0.0, 0, ContactStatus::stick);
  io::h5::File f = io::h5::create(path, "run.h5");
  io::RunWriter w(f, h, fr.grains);
  w.append_frame(fr);
  f.close();
}

}  // namespace cdpile::test
