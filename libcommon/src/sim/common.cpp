#include "cdpile/sim/common.hpp"

#include "cdpile/analysis/critical.hpp"
#include "cdpile/error.hpp"

#include <cmath>

namespace cdpile::sim {

CriticalCounts count_critical(const Contacts& c, const std::vector<Species>& species,
                              double mu_grain, double mu_wall, double eps) {
  CriticalCounts n;
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (!(c.fn[k] > 0.0)) continue;
    const bool plane = c.j[k] < 0;
    const double mu = plane ? mu_wall : mu_grain;
    if (!analysis::is_critical(c.fn[k], c.ft[k], mu, eps)) continue;
    ++n.all;
    const bool glued = species[static_cast<std::size_t>(c.i[k])] == Species::floor ||
                       (!plane && species[static_cast<std::size_t>(c.j[k])] == Species::floor);
    if (!plane && !glued) ++n.grain;
  }
  return n;
}

using Real = Observable::Real;
using Integer = Observable::Integer;

const std::vector<Observable>& observables() {
  using R = const cd::StepReport&;
  using C = const CriticalCounts&;
  static const std::vector<Observable> table = {
      {"tilt_angle", "degree", Real{[](R r, C) { return r.tilt_angle * 180.0 / M_PI; }}},
      {"kinetic_energy", "J m-1", Real{[](R r, C) { return r.kinetic_energy; }}},
      {"rotational_energy", "J m-1", Real{[](R r, C) { return r.rotational_energy; }}},
      {"residual", "", Real{[](R r, C) { return r.residual; }}},
      {"residual_rms", "", Real{[](R r, C) { return r.residual_rms; }}},
      {"law_residual", "", Real{[](R r, C) { return r.law_residual; }}},
      {"law_residual_rms", "", Real{[](R r, C) { return r.law_residual_rms; }}},
      {"max_overlap", "m", Real{[](R r, C) { return r.max_overlap; }}},
      {"max_speed", "m s-1", Real{[](R r, C) { return r.max_speed; }}},
      {"contacts", "", Integer{[](R r, C) { return std::int64_t{r.contacts}; }}},
      {"contacts_grain", "", Integer{[](R r, C) { return std::int64_t{r.contacts_grain}; }}},
      {"sliding", "", Integer{[](R r, C) { return std::int64_t{r.sliding}; }}},
      {"sweeps", "", Integer{[](R r, C) { return std::int64_t{r.sweeps}; }}},
      {"substeps", "", Integer{[](R r, C) { return std::int64_t{r.substeps}; }}},
      {"finishes", "", Integer{[](R r, C) { return std::int64_t{r.finishes}; }}},
      {"converged", "", Integer{[](R r, C) { return std::int64_t{r.converged ? 1 : 0}; }}},
      {"critical", "", Integer{[](R, C c) { return c.all; }}},
      {"critical_grain", "", Integer{[](R, C c) { return c.grain; }}},
      {"grains_without_contact", "",
       Integer{[](R r, C) { return std::int64_t{r.grains_without_contact}; }}}};
  return table;
}

io::Series observables_series() {
  io::Series s;
  for (const Observable& o : observables()) {
    if (std::holds_alternative<Real>(o.value))
      s.real[o.name] = {};
    else
      s.integer[o.name] = {};
    s.unit[o.name] = o.unit;
  }
  return s;
}

void append_observables(io::Series& s, const cd::StepReport& r, const CriticalCounts& c) {
  s.step.push_back(r.step);
  s.time.push_back(r.time);
  for (const Observable& o : observables()) {
    if (const Real* f = std::get_if<Real>(&o.value))
      s.real[o.name].push_back((*f)(r, c));
    else
      s.integer[o.name].push_back(std::get<Integer>(o.value)(r, c));
  }
}

Agitation::Agitation(const Grains& g, double gravity) {
  double mass = 0.0, diameter = 0.0;
  for (std::size_t i = 0; i < g.size(); ++i) {
    if (g.species[i] != Species::free) continue;
    ++free_;
    mass += g.mass[i];
    diameter += 2.0 * g.radius[i];
  }
  if (free_ > 0) {
    const double n = static_cast<double>(free_);
    diameter_ = diameter / n;
    // Mean Ek per grain / (m g D) = Ek / (N m g D) = Ek / (total mass g D).
    scale_ = mass * gravity * diameter_;
    if (!(scale_ > 0.0)) scale_ = 1.0;
  }
}

Frame frame_of(const cd::Engine& e, double tilt_angle) {
  Frame f;
  const cd::EngineState s = e.state();
  f.step = s.step;
  f.time = s.time;
  f.tilt_angle = tilt_angle;
  f.grains = e.grains();
  f.contacts = e.contacts();
  return f;
}

}  // namespace cdpile::sim
