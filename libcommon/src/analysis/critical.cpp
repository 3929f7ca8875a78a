#include "cdpile/analysis/critical.hpp"

#include "cdpile/error.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace cdpile::analysis {

void validate(const CriticalRule& rule, const Friction& mu) {
  if (!(std::isfinite(mu.grain) && mu.grain > 0.0))
    throw Error("friction coefficient mu must be > 0, got " + std::to_string(mu.grain));
  if (!(std::isfinite(mu.wall) && mu.wall > 0.0))
    throw Error("wall friction coefficient must be > 0, got " + std::to_string(mu.wall));
  if (!(rule.eps >= 0.0 && rule.eps < 1.0))
    throw Error("critical tolerance eps must be in [0, 1), got " + std::to_string(rule.eps));
}

std::size_t ContactSet::critical_count() const {
  return static_cast<std::size_t>(std::count(critical.begin(), critical.end(), 1));
}
std::size_t ContactSet::sliding_count() const {
  return static_cast<std::size_t>(std::count(sliding.begin(), sliding.end(), 1));
}

namespace {
bool is_floor_grain(std::int32_t id, std::span<const Species> species) {
  return id >= 0 && static_cast<std::size_t>(id) < species.size() &&
         species[static_cast<std::size_t>(id)] == Species::floor;
}
}  // namespace

ContactSet select_contacts(const Contacts& c, std::span<const Species> species, const Friction& mu,
                           const CriticalRule& rule) {
  validate(rule, mu);
  ContactSet s;
  const std::size_t n = c.size();
  s.row.reserve(n);
  s.i.reserve(n);
  s.j.reserve(n);
  s.point.reserve(n);
  s.critical.reserve(n);
  s.sliding.reserve(n);
  s.mobilisation.reserve(n);
  const bool have_status = c.status.size() == n;
  s.has_status = have_status;
  for (std::size_t k = 0; k < n; ++k) {
    const double fn = c.fn[k], ft = c.ft[k];
    if (!std::isfinite(fn) || !std::isfinite(ft) || !std::isfinite(c.point[k].x()) ||
        !std::isfinite(c.point[k].y()))
      throw Error("", "contact " + std::to_string(k), "force or contact point is not finite");
    if (!(fn > 0.0)) continue;  // not active
    const bool plane = c.j[k] < 0;
    const bool glued = rule.floor_grains_are_walls &&
                       (is_floor_grain(c.i[k], species) || is_floor_grain(c.j[k], species));
    if ((plane || glued) && !rule.include_walls) continue;
    const double m = plane ? mu.wall : mu.grain;
    s.row.push_back(k);
    s.i.push_back(c.i[k]);
    s.j.push_back(c.j[k]);
    s.point.push_back(c.point[k]);
    s.critical.push_back(is_critical(fn, ft, m, rule.eps) ? 1 : 0);
    s.sliding.push_back(have_status && c.status[k] == ContactStatus::slide ? 1 : 0);
    s.mobilisation.push_back(std::abs(ft) / (m * fn));
  }
  return s;
}

std::optional<double> critical_spacing(double z, double nu, double diameter) {
  if (!(z * nu > 0.0)) return std::nullopt;
  return std::sqrt(2.0 / (z * nu)) * diameter;  // eq (2)
}

PileState pile_state(const ContactSet& set, std::span<const Species> species,
                     std::int64_t free_grains, double diameter, RattlerRule rattlers) {
  PileState p;
  p.contacts = static_cast<std::int64_t>(set.size());
  p.critical = static_cast<std::int64_t>(set.critical_count());
  p.sliding = static_cast<std::int64_t>(set.sliding_count());
  p.grains = free_grains;
  if (p.contacts > 0) {
    p.nu = static_cast<double>(p.critical) / static_cast<double>(p.contacts);  // eq (1)
    p.nu_sliding = static_cast<double>(p.sliding) / static_cast<double>(p.contacts);
  }
  // Contacts per grain, for the rattler rule: sort the grain ends of the counted
  // contacts and count runs (ids may be large or sparse in a user's table). Wall ends
  // (id < 0) and glued grains are not grains of the count.
  std::vector<std::int32_t> ends;
  ends.reserve(2 * set.size());
  for (std::size_t k = 0; k < set.size(); ++k) {
    for (std::int32_t id : {set.i[k], set.j[k]}) {
      if (id < 0) continue;
      if (static_cast<std::size_t>(id) < species.size() &&
          species[static_cast<std::size_t>(id)] == Species::floor)
        continue;
      ends.push_back(id);
    }
  }
  std::sort(ends.begin(), ends.end());
  std::int64_t loaded = 0;
  for (std::size_t a = 0; a < ends.size();) {
    std::size_t b = a;
    while (b < ends.size() && ends[b] == ends[a]) ++b;
    if (b - a >= 2) ++loaded;
    a = b;
  }
  p.loaded_grains = loaded;
  const double two_n = 2.0 * static_cast<double>(p.contacts);
  if (free_grains > 0) p.z_all = two_n / static_cast<double>(free_grains);
  if (rattlers == RattlerRule::include) {
    p.z = p.z_all;
  } else if (loaded > 0) {
    p.z = two_n / static_cast<double>(loaded);
  }
  if (p.z && p.nu) p.lambda = critical_spacing(*p.z, *p.nu, diameter);
  return p;
}

StaticBound static_bound(const Contacts& c, std::span<const Species> species, const Friction& mu,
                         double eps) {
  CriticalRule rule;
  rule.eps = eps;
  validate(rule, mu);
  auto fixed = [&](std::int32_t id) { return id < 0 || is_floor_grain(id, species); };

  // The active contacts that involve at least one free grain (two fixed bodies touching
  // carry no unknown of the free grains' equilibrium).
  std::vector<std::size_t> active;
  std::vector<std::int32_t> ids;
  for (std::size_t k = 0; k < c.size(); ++k) {
    const double fn = c.fn[k], ft = c.ft[k];
    if (!std::isfinite(fn) || !std::isfinite(ft))
      throw Error("", "contact " + std::to_string(k), "force is not finite");
    if (!(fn > 0.0)) continue;
    if (fixed(c.i[k]) && fixed(c.j[k])) continue;
    active.push_back(k);
    for (std::int32_t id : {c.i[k], c.j[k]})
      if (!fixed(id)) ids.push_back(id);
  }
  // Free grains by index in the sorted ids (ids may be sparse), their contacts as lists.
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  auto index = [&](std::int32_t id) {
    return static_cast<std::size_t>(std::lower_bound(ids.begin(), ids.end(), id) - ids.begin());
  };
  std::vector<std::size_t> first(ids.size() + 1, 0), list;
  for (std::size_t a : active)
    for (std::int32_t id : {c.i[a], c.j[a]})
      if (!fixed(id)) ++first[index(id) + 1];
  for (std::size_t g = 0; g < ids.size(); ++g) first[g + 1] += first[g];
  list.resize(first.back());
  {
    std::vector<std::size_t> fill(first.begin(), first.end() - 1);
    for (std::size_t n = 0; n < active.size(); ++n)
      for (std::int32_t id : {c.i[active[n]], c.j[active[n]]})
        if (!fixed(id)) list[fill[index(id)]++] = n;
  }

  // Remove the rattlers: a grain with fewer than 2 remaining contacts goes, with its
  // contacts, which may leave a neighbour with fewer than 2 in turn.
  std::vector<std::int64_t> degree(ids.size());
  std::vector<std::uint8_t> grain_on(ids.size(), 1), contact_on(active.size(), 1);
  std::vector<std::size_t> queue;
  for (std::size_t g = 0; g < ids.size(); ++g) {
    degree[g] = static_cast<std::int64_t>(first[g + 1] - first[g]);
    if (degree[g] < 2) queue.push_back(g);
  }
  while (!queue.empty()) {
    const std::size_t g = queue.back();
    queue.pop_back();
    if (!grain_on[g]) continue;
    grain_on[g] = 0;
    for (std::size_t q = first[g]; q < first[g + 1]; ++q) {
      const std::size_t n = list[q];
      if (!contact_on[n]) continue;
      contact_on[n] = 0;
      for (std::int32_t id : {c.i[active[n]], c.j[active[n]]}) {
        if (fixed(id)) continue;
        const std::size_t h = index(id);
        if (h != g && grain_on[h] && --degree[h] < 2) queue.push_back(h);
      }
    }
  }

  StaticBound b;
  for (std::size_t g = 0; g < ids.size(); ++g) b.grains += grain_on[g];
  for (std::size_t n = 0; n < active.size(); ++n) {
    if (!contact_on[n]) continue;
    const std::size_t k = active[n];
    ++b.contacts;
    const double m = c.j[k] < 0 ? mu.wall : mu.grain;  // glued grains: grain friction
    if (is_critical(c.fn[k], c.ft[k], m, eps)) ++b.critical;
  }
  return b;
}

namespace {
template <class F>
double mean_over_free(const Grains& g, F value) {
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t k = 0; k < g.size(); ++k) {
    if (k < g.species.size() && g.species[k] != Species::free) continue;
    sum += value(k);
    ++n;
  }
  if (n == 0) {  // nothing marked free: use every grain
    for (std::size_t k = 0; k < g.size(); ++k) sum += value(k);
    n = g.size();
  }
  return n ? sum / static_cast<double>(n) : 0.0;
}
}  // namespace

double mean_diameter(const Grains& g) {
  return mean_over_free(g, [&](std::size_t k) { return 2.0 * g.radius[k]; });
}
double mean_mass(const Grains& g) {
  return mean_over_free(g, [&](std::size_t k) { return g.mass.size() > k ? g.mass[k] : 0.0; });
}
std::optional<double> mean_kinetic_energy(const Grains& g) {
  // Over the free grains, as the per-step Ek (the simulator's kinetic_energy sums the free
  // grains; critical divides it by free_grain_count): glued grains never move.
  if (g.velocity.size() != g.size() || g.mass.size() != g.size()) return std::nullopt;
  double sum = 0.0;
  std::int64_t n = 0;
  for (std::size_t k = 0; k < g.size(); ++k) {
    if (k < g.species.size() && g.species[k] != Species::free) continue;
    sum += 0.5 * g.mass[k] * g.velocity[k].squaredNorm();
    ++n;
  }
  if (n == 0) return std::nullopt;
  return sum / static_cast<double>(n);
}

FrameMotion frame_motion(const Grains& g, const Contacts& c) {
  FrameMotion m;
  std::vector<std::int64_t> touched(g.size(), 0);  // active contacts of each grain
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (!(c.fn[k] > 0.0)) continue;
    if (c.i[k] >= 0 && static_cast<std::size_t>(c.i[k]) < g.size())
      ++touched[static_cast<std::size_t>(c.i[k])];
    if (c.j[k] >= 0 && static_cast<std::size_t>(c.j[k]) < g.size())
      ++touched[static_cast<std::size_t>(c.j[k])];
  }
  std::int64_t contact_ends = 0;
  const bool moving = g.velocity.size() == g.size() && g.mass.size() == g.size();
  const bool turning = g.angular_velocity.size() == g.size() && g.inertia.size() == g.size();
  double energy = 0.0, speed = 0.0;
  std::int64_t n = 0;
  for (std::size_t k = 0; k < g.size(); ++k) {
    if (k < g.species.size() && g.species[k] != Species::free) continue;
    ++n;
    contact_ends += touched[k];
    if (touched[k] == 0) ++m.grains_without_contact;
    if (!moving) continue;
    energy += 0.5 * g.mass[k] * g.velocity[k].squaredNorm();
    if (turning) energy += 0.5 * g.inertia[k] * g.angular_velocity[k] * g.angular_velocity[k];
    speed = std::max(speed, g.velocity[k].norm());
  }
  if (n > 0) m.contacts_per_grain = static_cast<double>(contact_ends) / static_cast<double>(n);
  if (moving && n > 0) {
    m.agitation = energy / static_cast<double>(n);
    m.max_speed = speed;
  }
  return m;
}

std::vector<double> slip_speeds(const Contacts& c, const ContactSet& set, const Grains& g) {
  std::vector<double> out(set.size(), 0.0);
  if (g.velocity.size() != g.size() || g.position.size() != g.size()) return out;
  const bool turning = g.angular_velocity.size() == g.size();
  // velocity of body b's material point at p (a wall, or an unknown body, is at rest)
  auto at = [&](std::int32_t b, const Vec2& p) -> Vec2 {
    if (b < 0 || static_cast<std::size_t>(b) >= g.size()) return Vec2::Zero();
    const auto k = static_cast<std::size_t>(b);
    const Vec2 r = p - g.position[k];
    const double w = turning ? g.angular_velocity[k] : 0.0;
    return g.velocity[k] + w * Vec2(-r.y(), r.x());
  };
  for (std::size_t q = 0; q < set.size(); ++q) {
    const std::size_t k = set.row[q];
    const Vec2 u = at(c.i[k], c.point[k]) - at(c.j[k], c.point[k]);
    const Vec2& n = c.normal[k];
    out[q] = std::abs(u.x() * -n.y() + u.y() * n.x());
  }
  return out;
}

RestCount contacts_at_rest(const Contacts& c, const ContactSet& set, const Grains& g,
                           const std::vector<double>& u_t, double rest_speed, double slip_speed) {
  if (u_t.size() != set.size()) throw Error("contacts_at_rest: one slip speed per contact");
  auto slow = [&](std::int32_t b) {
    return b < 0 || static_cast<std::size_t>(b) >= g.size() ||
           g.velocity[static_cast<std::size_t>(b)].norm() < rest_speed;
  };
  RestCount n;
  for (std::size_t q = 0; q < set.size(); ++q) {
    const std::size_t row = set.row[q];
    if (!slow(c.i[row]) || !slow(c.j[row]) || u_t[q] > slip_speed) continue;
    ++n.contacts;
    n.critical += set.critical[q];
  }
  return n;
}

std::vector<std::int64_t> mobilisation_histogram(const ContactSet& set, std::size_t bins) {
  std::vector<std::int64_t> h(bins, 0);
  if (bins == 0) return h;
  for (double m : set.mobilisation) {
    if (!(m >= 0.0)) continue;
    const auto b = std::min(bins - 1, static_cast<std::size_t>(m * static_cast<double>(bins)));
    ++h[b];
  }
  return h;
}

std::int64_t free_grain_count(const Grains& g) {
  std::int64_t n = 0;
  for (std::size_t k = 0; k < g.size(); ++k)
    if (k >= g.species.size() || g.species[k] == Species::free) ++n;
  return n;
}

}  // namespace cdpile::analysis
