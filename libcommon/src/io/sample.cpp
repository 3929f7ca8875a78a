#include "cdpile/io/sample.hpp"

#include "cdpile/parameter_keys.hpp"

#include <random>

namespace cdpile::io {

RunHeader sample_header(double diameter) {
  RunHeader h;
  h.kind = "pile";
  h.box = {10 * diameter * 4, 10 * diameter};
  h.parameters = {{keys::mu_grain, 0.5},       {keys::mu_wall, 0.5},
                  {keys::gravity_m_s2, 9.81},      {"density_kg_m3", 2500.0},
                  {"grains", std::int64_t{0}}, {"note", std::string("sample")}};
  return h;
}

Frame sample_frame(std::size_t n, double d, std::uint64_t seed) {
  // Grains on the floor, side by side with small random radii variations: each rests on
  // the floor, so its floor contact carries its weight m g (forces per unit thickness).
  std::mt19937_64 rng(seed);
  Frame fr;
  fr.step = 0;
  fr.time = 0.0;
  fr.tilt_angle = 0.0;
  double x = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double r = 0.5 * d * (0.8 + 0.4 * static_cast<double>(rng() >> 11) * 0x1.0p-53);
    x += r;
    fr.grains.add_disk(r, 2500.0, Vec2(x, r));
    x += r;
  }
  for (std::size_t k = 0; k < n; ++k) {
    const double w = fr.grains.mass[k] * 9.81;
    fr.contacts.push_back(static_cast<std::int32_t>(k), wall_floor,
                          Vec2(fr.grains.position[k].x(), 0.0), Vec2(0, 1), w, 0.0, 0.0,
                          ContactStatus::stick);
  }
  return fr;
}

Series sample_series(std::size_t steps) {
  Series s;
  for (std::size_t k = 0; k < steps; ++k) {
    s.step.push_back(static_cast<std::int64_t>(k));
    s.time.push_back(1e-4 * static_cast<double>(k));
    s.real["tilt_angle"].push_back(0.001 * static_cast<double>(k));
    s.real["kinetic_energy"].push_back(0.0);
    s.integer["contacts"].push_back(static_cast<std::int64_t>(k));
  }
  s.unit = {{"tilt_angle", "degree"}, {"kinetic_energy", "J m-1"}, {"contacts", ""}};
  return s;
}

void write_sample_pile(h5::File& f, std::size_t grains, double diameter, std::uint64_t seed,
                       const Provenance& p) {
  RunHeader h = sample_header(diameter);
  h.parameters["grains"] = static_cast<std::int64_t>(grains);
  h.provenance.push_back(p);
  Frame fr = sample_frame(grains, diameter, seed);
  h.box.width = fr.grains.position.back().x() + fr.grains.radius.back();
  RunWriter w(f, h, fr.grains);
  w.append_frame(fr);
  w.append_series(sample_series(4));
}

}  // namespace cdpile::io
