// The deposition protocol (deposit.hpp; docs/method.md, "Deposit").
#include "cdpile/sim/deposit.hpp"

#include "cdpile/analysis/critical.hpp"
#include "cdpile/error.hpp"
#include "cdpile/fields.hpp"
#include "cdpile/sim/common.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace cdpile::sim {
namespace h5 = io::h5;

double mean_mass(const DepositOptions& o) {
  // rho pi <D^2> / 4, <D^2> = (Dmin^2 + Dmin Dmax + Dmax^2) / 3.
  const double d_min = 2.0 * o.diameter / (1.0 + o.ratio), d_max = o.ratio * d_min;
  return o.density * M_PI / 4.0 * (d_min * d_min + d_min * d_max + d_max * d_max) / 3.0;
}

void validate(const DepositOptions& o) {
  auto bad = [](const std::string& what) { throw UsageError(what); };
  if (o.grains < 1) bad(field("grains") + " must be >= 1");
  if (!(o.diameter > 0.0) || !std::isfinite(o.diameter)) bad(field("diameter") + " must be > 0");
  if (!(o.ratio >= 1.0) || !std::isfinite(o.ratio)) bad(field("ratio") + " must be >= 1");
  // A row must hold at least one of the largest grains with its two minimum gaps.
  const double dmax = 2.0 * o.ratio / (1.0 + o.ratio);
  if (!(o.width >= dmax + 0.2) || !std::isfinite(o.width))
    bad(field("width") + " must be at least Dmax + 0.2 D = " + std::to_string(dmax + 0.2) + " D");
  if (!(o.density > 0.0) || !std::isfinite(o.density)) bad(field("density") + " must be > 0");
  if (!(o.settings.gravity > 0.0)) bad(field("gravity") + " must be > 0 to deposit a pile");
  if (!(o.rest_energy > 0.0) || !(o.rest_speed > 0.0)) bad("rest thresholds must be > 0");
  if (o.rest_steps < 1) bad(field("rest_steps") + " must be >= 1");
  if (o.max_steps < 1) bad(field("max_steps") + " must be >= 1");
  cd::validate(o.settings);
}

// Grains in rows (docs/method.md, "Deposit"): diameters are drawn uniform in
// [Dmin, Dmax] with Dmin = 2 D / (1 + ratio), so their mean is D. A row takes the next
// grains while they fit with a minimum gap of 0.05 D between neighbours and walls; the
// width left over is shared among the gaps by random weights, and each grain sits at a
// random height inside its row's band (as tall as the row's largest grain). Rows are
// 0.05 D apart, so no two grains overlap, and the column is about twice as loose as the
// final pile: grains fall at most about the pile's height, not from high above it.
Placement place_grains(const DepositOptions& o) {
  validate(o);
  const double D = o.diameter;
  const double dmin = 2.0 * D / (1.0 + o.ratio), dmax = o.ratio * dmin;
  const double W = o.width * D;
  const double gmin = 0.05 * D;
  Random rng(o.seed);
  const auto n = static_cast<std::size_t>(o.grains);
  std::vector<double> d(n);
  for (double& x : d) x = rng.uniform(dmin, dmax);

  Placement p;
  p.box.width = W;
  // The rough floor: glued grains side by side on the floor plane, touching, the width
  // left over spread evenly between them (less than one diameter over the whole box).
  std::vector<double> floor_x, floor_r;
  if (o.rough_floor) {
    double x = 0.0;
    for (;;) {
      const double dd = rng.uniform(dmin, dmax);
      if (x + dd > W) break;
      floor_x.push_back(x + 0.5 * dd);
      floor_r.push_back(0.5 * dd);
      x += dd;
    }
    const double gap = (W - x) / static_cast<double>(floor_x.size() + 1);
    for (std::size_t k = 0; k < floor_x.size(); ++k) floor_x[k] += gap * static_cast<double>(k + 1);
  }
  double floor_top = 0.0;
  for (double r : floor_r) floor_top = std::max(floor_top, 2.0 * r);

  p.grains.radius.reserve(n + floor_x.size());
  std::vector<Vec2> centre(n);
  double y = floor_top + gmin;
  std::size_t i = 0;
  while (i < n) {
    std::size_t j = i;
    double sum = 0.0, tallest = 0.0;
    while (j < n && sum + d[j] + static_cast<double>(j - i + 2) * gmin <= W) {
      sum += d[j];
      tallest = std::max(tallest, d[j]);
      ++j;
    }
    const std::size_t count = j - i;  // >= 1: validate() checked W >= Dmax + 0.2 D
    const double extra = W - sum - static_cast<double>(count + 1) * gmin;
    std::vector<double> w(count + 1);
    double total = 0.0;
    for (double& x : w) total += (x = rng.uniform());
    if (!(total > 0.0)) total = 1.0;
    double x = 0.0;
    for (std::size_t k = 0; k < count; ++k) {
      const double dk = d[i + k];
      x += gmin + extra * w[k] / total;
      centre[i + k] = Vec2(x + 0.5 * dk, y + 0.5 * dk + rng.uniform() * (tallest - dk));
      x += dk;
    }
    y += tallest + gmin;
    i = j;
  }
  for (std::size_t k = 0; k < n; ++k)
    p.grains.add_disk(0.5 * d[k], o.density, centre[k], Species::free);
  for (std::size_t k = 0; k < floor_x.size(); ++k)
    p.grains.add_disk(floor_r[k], o.density, Vec2(floor_x[k], floor_r[k]), Species::floor);
  p.column_top = y;
  p.box.height = y;
  return p;
}

namespace {

/// Area of a disk (centre height c, radius r) between the lines y = a and y = b (a < b):
/// the area below a line at t = (y - c) / r is r^2 (acos(-t) + t sqrt(1 - t^2)).
double disk_area_in_slab(double c, double r, double a, double b) {
  auto below = [&](double yline) {
    const double t = std::clamp((yline - c) / r, -1.0, 1.0);
    return r * r * (std::acos(-t) + t * std::sqrt(1.0 - t * t));
  };
  return below(b) - below(a);
}

}  // namespace

Tiling tile_side_by_side(const Box& box, const Grains& g, const Contacts& c, int copies) {
  if (copies < 1) throw UsageError("tiling: the number of copies must be >= 1");
  Tiling t;
  t.box = {copies * box.width, box.height};
  const auto n = static_cast<std::int32_t>(g.size());
  for (int k = 0; k < copies; ++k) {
    const Vec2 shift(k * box.width, 0.0);
    for (std::size_t i = 0; i < g.size(); ++i) {
      t.grains.radius.push_back(g.radius[i]);
      t.grains.mass.push_back(g.mass[i]);
      t.grains.inertia.push_back(g.inertia[i]);
      t.grains.species.push_back(g.species[i]);
      t.grains.position.push_back(g.position[i] + shift);
      t.grains.velocity.push_back(g.velocity[i]);
      t.grains.orientation.push_back(g.orientation[i]);
      t.grains.angular_velocity.push_back(g.angular_velocity[i]);
    }
    for (std::size_t q = 0; q < c.size(); ++q) {
      if (c.j[q] == wall_left && k > 0) continue;
      if (c.j[q] == wall_right && k < copies - 1) continue;
      const std::int32_t j = c.j[q] < 0 ? c.j[q] : c.j[q] + k * n;
      t.contacts.push_back(c.i[q] + k * n, j, c.point[q] + shift, c.normal[q], c.fn[q], c.ft[q],
                           c.gap[q], c.status[q]);
    }
  }
  return t;
}

PileMeasures measure_pile(const Box& box, const Grains& g, const Contacts& c) {
  PileMeasures m;
  const double D = analysis::mean_diameter(g);
  if (g.size() == 0 || !(D > 0.0)) return m;
  // Bed height: the free surface sampled in columns of width about D.
  const auto ncol = static_cast<std::size_t>(std::max(1.0, std::floor(box.width / D)));
  const double colw = box.width / static_cast<double>(ncol);
  std::vector<double> top(ncol, -std::numeric_limits<double>::infinity());
  double dmax = 0.0;
  for (std::size_t i = 0; i < g.size(); ++i) {
    dmax = std::max(dmax, 2.0 * g.radius[i]);
    if (g.species[i] != Species::free) continue;
    const auto col =
        std::min(ncol - 1, static_cast<std::size_t>(std::max(0.0, g.position[i].x() / colw)));
    top[col] = std::max(top[col], g.position[i].y() + g.radius[i]);
  }
  double sum = 0.0;
  std::size_t filled = 0;
  for (double t : top)
    if (std::isfinite(t)) {
      sum += t;
      ++filled;
    }
  m.bed_height = filled ? sum / static_cast<double>(filled) : 0.0;
  // Packing fraction in the bulk: leave out two Dmax at the bottom (the floor layer and
  // the first grains on it) and two Dmax below the rough free surface; a pile too thin
  // for that uses the whole bed.
  m.slab_bottom = 2.0 * dmax;
  m.slab_top = m.bed_height - 2.0 * dmax;
  if (m.slab_top - m.slab_bottom < dmax) {
    m.slab_bottom = 0.0;
    m.slab_top = m.bed_height;
  }
  double area = 0.0;
  for (std::size_t i = 0; i < g.size(); ++i)
    area += disk_area_in_slab(g.position[i].y(), g.radius[i], m.slab_bottom, m.slab_top);
  if (m.slab_top > m.slab_bottom)
    m.packing_fraction = area / (box.width * (m.slab_top - m.slab_bottom));
  // Coordination: active contacts between free grains (analysis/critical.hpp). z counts
  // contacts and does not classify them, so friction does not enter: the selection is
  // given mu = 1 only because it also marks critical contacts, which need mu > 0, and a
  // pile may settle without friction (deposit --mu 0).
  const analysis::Friction any_mu{1.0, 1.0};
  const analysis::ContactSet set =
      analysis::select_contacts(c, g.species, any_mu, analysis::CriticalRule{});
  const analysis::PileState st = analysis::pile_state(set, g.species, analysis::free_grain_count(g),
                                                      D, analysis::RattlerRule::exclude);
  m.z = st.z.value_or(0.0);
  m.z_all = st.z_all.value_or(0.0);
  return m;
}

Pile deposit(const DepositOptions& o, const std::function<void(const DepositProgress&)>& progress,
             const std::function<bool()>& stop) {
  Placement place = place_grains(o);
  cd::Engine engine(place.box, place.grains, o.settings);
  const Agitation agitation(place.grains, o.settings.gravity);
  const double speed_limit = o.rest_speed * std::sqrt(o.settings.gravity * o.diameter);
  Pile pile;
  pile.box = place.box;
  pile.series = observables_series();
  std::int64_t quiet = 0, unconverged = 0;
  double last_agitation = 0.0;
  engine.set_cancel(stop);  // a step at the sweep cap may take longer than a signal may wait
  for (std::int64_t k = 1; k <= o.max_steps; ++k) {
    cd::StepReport r;
    try {
      r = engine.step(0.0);
    } catch (const cd::StepCancelled&) {
      break;
    }
    const Contacts c = engine.contacts();
    append_observables(pile.series, r,
                       count_critical(c, engine.grains().species, o.settings.mu_grain,
                                      o.settings.mu_wall, analysis::default_eps));
    if (!r.converged) ++unconverged;
    last_agitation = agitation(r.kinetic_energy + r.rotational_energy);
    quiet = (last_agitation < o.rest_energy && r.max_speed < speed_limit) ? quiet + 1 : 0;
    pile.steps = r.step;
    pile.time = r.time;
    if (progress) progress({r.step, last_agitation, quiet});
    if (quiet >= o.rest_steps) {
      pile.settled = true;
      break;
    }
    if (stop && stop()) break;
  }
  pile.grains = engine.grains();
  pile.contacts = engine.contacts();
  pile.box.height = place.column_top;

  const double dmin = 2.0 * o.diameter / (1.0 + o.ratio);
  pile.parameters = settings_parameters(o.settings);
  pile.parameters.insert({
      {"grains", o.grains},
      {"floor_grains", static_cast<std::int64_t>(place.grains.size()) - o.grains},
      {"diameter_mean_m", o.diameter},
      {"diameter_ratio", o.ratio},
      {"diameter_min_m", dmin},
      {"diameter_max_m", o.ratio * dmin},
      {"box_width_m", place.box.width},
      {"box_width_D", o.width},
      {"density_kg_m3", o.density},
      {"rough_floor", std::int64_t{o.rough_floor ? 1 : 0}},
      {"seed", static_cast<std::int64_t>(o.seed)},
      {"rest_energy", o.rest_energy},
      {"rest_speed", o.rest_speed},
      {"rest_steps", o.rest_steps},
      {"settle_max_steps", o.max_steps},
  });
  const PileMeasures m = measure_pile(pile.box, pile.grains, pile.contacts);
  double overlap = 0.0;
  for (std::size_t k = 0; k < pile.contacts.size(); ++k)
    if (pile.contacts.fn[k] > 0.0) overlap = std::max(overlap, -pile.contacts.gap[k]);
  pile.results = {
      {"settled", std::int64_t{pile.settled ? 1 : 0}},
      {"settle_steps", pile.steps},
      {"settle_time_s", pile.time},
      {"final_agitation", last_agitation},
      {"unconverged_steps", unconverged},
      {"bed_height_m", m.bed_height},
      {"bed_height_D", m.bed_height / o.diameter},
      {"packing_fraction", m.packing_fraction},
      {"packing_slab_bottom_m", m.slab_bottom},
      {"packing_slab_top_m", m.slab_top},
      {"coordination_number", m.z},
      {"coordination_number_all", m.z_all},
      {"max_overlap_m", overlap},
  };
  return pile;
}

void write_pile(io::h5::File& f, const Pile& p, const io::Provenance& prov) {
  io::RunHeader h;
  h.kind = "pile";
  h.box = p.box;
  h.parameters = p.parameters;
  h.results = p.results;
  h.provenance = {prov};
  io::RunWriter w(f, h, p.grains);
  Frame fr;
  fr.step = p.steps;
  fr.time = p.time;
  fr.tilt_angle = 0.0;
  fr.grains = p.grains;
  fr.contacts = p.contacts;
  w.append_frame(fr);
  w.append_series(p.series);
}

}  // namespace cdpile::sim
