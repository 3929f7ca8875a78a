#include "cdpile/model.hpp"

#include <numbers>

namespace cdpile {

const char* wall_name(std::int32_t wall_id) {
  switch (wall_id) {
    case wall_floor: return "floor";
    case wall_left: return "left";
    case wall_right: return "right";
    default: return "grain";
  }
}

void Grains::resize(std::size_t n) {
  radius.resize(n);
  mass.resize(n);
  inertia.resize(n);
  species.resize(n, Species::free);
  position.resize(n, Vec2::Zero());
  velocity.resize(n, Vec2::Zero());
  orientation.resize(n, 0.0);
  angular_velocity.resize(n, 0.0);
}

void Grains::add_disk(double r, double rho, const Vec2& x, Species s) {
  const double m = rho * std::numbers::pi * r * r;
  radius.push_back(r);
  mass.push_back(m);
  inertia.push_back(0.5 * m * r * r);  // uniform disk
  species.push_back(s);
  position.push_back(x);
  velocity.push_back(Vec2::Zero());
  orientation.push_back(0.0);
  angular_velocity.push_back(0.0);
}

void Contacts::clear() {
  i.clear();
  j.clear();
  point.clear();
  normal.clear();
  fn.clear();
  ft.clear();
  gap.clear();
  status.clear();
}

void Contacts::reserve(std::size_t n) {
  i.reserve(n);
  j.reserve(n);
  point.reserve(n);
  normal.reserve(n);
  fn.reserve(n);
  ft.reserve(n);
  gap.reserve(n);
  status.reserve(n);
}

void Contacts::resize(std::size_t n) {
  i.resize(n);
  j.resize(n);
  point.resize(n);
  normal.resize(n);
  fn.resize(n);
  ft.resize(n);
  gap.resize(n);
  status.resize(n);
}

void Contacts::push_back(std::int32_t ii, std::int32_t jj, const Vec2& p, const Vec2& n, double f_n,
                         double f_t, double g, ContactStatus s) {
  i.push_back(ii);
  j.push_back(jj);
  point.push_back(p);
  normal.push_back(n);
  fn.push_back(f_n);
  ft.push_back(f_t);
  gap.push_back(g);
  status.push_back(s);
}

}  // namespace cdpile
