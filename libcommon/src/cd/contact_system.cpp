// Debug-build checks of the contact system's invariants (contact_system.hpp, check.hpp).
// Their bodies are compiled only without NDEBUG: a Release build neither loops nor checks.
#include "cdpile/cd/contact_system.hpp"

#include "cdpile/check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace cdpile::cd {

namespace {

[[maybe_unused]] std::string num(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", x);
  return text;
}

[[maybe_unused]] std::string row_name(const ContactSystem& s, std::size_t a) {
  const ContactRow& r = s.rows[a];
  return "row " + std::to_string(a) + " (" + std::to_string(r.i) + ", " + std::to_string(r.j) + ")";
}

}  // namespace

void debug_check_rows([[maybe_unused]] const ContactSystem& s) {
#ifndef NDEBUG
  const auto bodies = static_cast<std::int32_t>(s.bodies.size());
  for (std::size_t a = 0; a < s.rows.size(); ++a) {
    const ContactRow& r = s.rows[a];
    CDPILE_DEBUG_CHECK(a == 0 || pair_key(s.rows[a - 1].i, s.rows[a - 1].j) < pair_key(r.i, r.j),
                       row_name(s, a) + " is not after " + row_name(s, a - 1) +
                           " in pair order: the warm start would miss its impulse");
    CDPILE_DEBUG_CHECK(r.j < 0 || r.i < r.j, row_name(s, a) + ": a grain pair has i < j");
    CDPILE_DEBUG_CHECK(r.bi >= 0 && r.bi < bodies && r.bj >= 0 && r.bj < bodies,
                       row_name(s, a) + ": body index out of range");
    CDPILE_DEBUG_CHECK(
        r.w_nn > 0.0 && r.w_tt > 0.0,
        row_name(s, a) + ": W_nn " + num(r.w_nn) + ", W_tt " + num(r.w_tt) + " (both must be > 0)");
  }
#endif
}

void debug_check_admissible([[maybe_unused]] const ContactSystem& s) {
#ifndef NDEBUG
  for (std::size_t a = 0; a < s.rows.size(); ++a) {
    const ContactRow& r = s.rows[a];
    CDPILE_DEBUG_CHECK(
        std::isfinite(r.rn) && std::isfinite(r.rt) && r.rn >= 0.0 && std::abs(r.rt) <= r.mu * r.rn,
        row_name(s, a) + ": impulse (" + num(r.rn) + ", " + num(r.rt) +
            ") outside the Coulomb cone of mu " + num(r.mu));
  }
#endif
}

void debug_check_velocities([[maybe_unused]] const ContactSystem& s,
                            [[maybe_unused]] const std::vector<Body>& free_bodies,
                            [[maybe_unused]] double velocity_unit) {
#ifndef NDEBUG
  CDPILE_DEBUG_CHECK(free_bodies.size() == s.bodies.size(), "one free body per body");
  ContactSystem rebuilt;
  rebuilt.bodies = free_bodies;
  std::vector<double> lever(s.bodies.size(), 0.0);
  double scale = velocity_unit;
  for (const Body& b : free_bodies) scale = std::max(scale, std::hypot(b.vx, b.vy));
  for (const ContactRow& r : s.rows) {
    rebuilt.apply_impulse(r, r.rn, r.rt);
    scale = std::max({scale, r.w_nn * std::abs(r.rn), r.w_tt * std::abs(r.rt)});
    lever[static_cast<std::size_t>(r.bi)] = std::max(lever[static_cast<std::size_t>(r.bi)], r.ri);
    lever[static_cast<std::size_t>(r.bj)] = std::max(lever[static_cast<std::size_t>(r.bj)], r.rj);
  }
  const double tolerance = 1e-9 * scale;
  for (std::size_t k = 0; k < s.bodies.size(); ++k) {
    const Body& a = s.bodies[k];
    const Body& b = rebuilt.bodies[k];
    const double dv = std::hypot(a.vx - b.vx, a.vy - b.vy);
    const double dw = std::abs(a.w - b.w);
    CDPILE_DEBUG_CHECK(dv <= tolerance && (lever[k] > 0.0 ? dw * lever[k] <= tolerance : dw == 0.0),
                       "body " + std::to_string(k) + " is " + num(dv) + " m/s, " + num(dw) +
                           " rad/s away from v_free + M^-1 H^T R " + "(velocity scale " +
                           num(scale) + " m/s)");
  }
#endif
}

}  // namespace cdpile::cd
