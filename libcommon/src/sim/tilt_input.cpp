// Where a tilt starts: a pile, a run's frame, a partial run (tilt_input.hpp).
#include "cdpile/sim/tilt_input.hpp"

#include "cdpile/error.hpp"
#include "cdpile/parameter_keys.hpp"
#include "cdpile/analysis/critical.hpp"
#include "cdpile/sim/recorder.hpp"
#include "cdpile/sim/tilt_options.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace cdpile::sim {
namespace h5 = io::h5;

namespace {
constexpr double kDeg = M_PI / 180.0;

/// The physical parameters a tilt takes from its pile unless options override them: a
/// bad one is the file's error (exit 1, the file named), not a usage error.
/// Their ranges (docs/schema.md, "Ranges"): friction within --mu's [0, 1e3], gravity within
/// deposit's --gravity up to 1e6 m/s^2, the nominal mean diameter D within deposit's --ratio
/// (Dmax / Dmin <= 100) of every grain's: in [d_max / 100, 100 d_min].
void check_pile_parameters(const io::Values& v, const Grains& g, const std::string& file) {
  auto check = [&](const char* key, bool positive, double max) {
    if (!v.count(key)) return;
    const double x = io::as_real(v, key, file);
    char what[160] = "";
    if (positive ? !(x > 0) : !(x >= 0))
      std::snprintf(what, sizeof what, "%s must be %s 0, got %g", key, positive ? ">" : ">=", x);
    else if (!(x <= max))
      std::snprintf(what, sizeof what, "%s must be <= %g, got %g", key, max, x);
    if (*what) throw Error(file, "/parameters", what);
  };
  check(keys::mu_grain, false, 1e3);
  check(keys::mu_wall, false, 1e3);
  check(keys::gravity_m_s2, false, 1e6);
  double d_min = std::numeric_limits<double>::infinity(), d_max = 0;
  for (double r : g.radius) {
    d_min = std::min(d_min, 2 * r);
    d_max = std::max(d_max, 2 * r);
  }
  check("diameter_mean_m", true, g.size() ? 100 * d_min : 1e300);
  if (v.count("diameter_mean_m") && g.size() &&
      !(io::as_real(v, "diameter_mean_m", file) >= d_max / 100)) {
    char what[160];
    std::snprintf(what, sizeof what, "diameter_mean_m must be >= %g, got %g", d_max / 100,
                  io::as_real(v, "diameter_mean_m", file));
    throw Error(file, "/parameters", what);
  }
}

/// Frame k of a pile or run as the start of a tilt.
PileInput start_from_frame(const io::h5::File& f, const io::RunReader& r, std::size_t k) {
  check_pile_parameters(r.header().parameters, r.grain_properties(), f.name());
  PileInput p;
  p.name = f.name();
  p.box = r.header().box;
  const Frame fr = r.frame(k);
  p.grains = fr.grains;
  p.contacts = fr.contacts;
  p.parameters = r.header().parameters;
  p.provenance = r.header().provenance;
  return p;
}

void check_grains(const io::h5::File& f, const io::RunReader& r, const std::string& what) {
  if (r.frame_count() == 0)
    throw Error(f.name(), "/particles/grains/position", "the " + what + " has no frame");
  if (r.grain_count() == 0)
    throw Error(f.name(), "/particles/grains", "the " + what + " has no grain");
}

}  // namespace

PileInput read_pile(const io::h5::File& f) {
  io::RunReader r(f);
  if (r.header().kind != "pile")
    throw Error(f.name(), "/",
                "is a '" + r.header().kind + "' file, expected a pile (made by deposit)");
  check_grains(f, r, "pile");
  return start_from_frame(f, r, r.frame_count() - 1);
}

cd::EngineState warm_start_state(const Contacts& contacts, double time_step) {
  cd::EngineState es;
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    if (contacts.fn[k] == 0.0 && contacts.ft[k] == 0.0) continue;
    es.impulses.push_back(
        {contacts.i[k], contacts.j[k], contacts.fn[k] * time_step, contacts.ft[k] * time_step});
  }
  std::sort(es.impulses.begin(), es.impulses.end(),
            [](const cd::StoredImpulse& a, const cd::StoredImpulse& b) {
              return cd::pair_key(a.i, a.j) < cd::pair_key(b.i, b.j);
            });
  return es;
}

PileInput read_branch(const io::h5::File& f, double at_deg) {
  io::RunReader r(f);
  if (r.header().kind != "run")
    throw Error(
        f.name(), "/",
        "is a '" + r.header().kind + "' file; a branch starts from a run (made by tilt-cd)");
  check_grains(f, r, "run");
  // The last frame at or below the requested tilt (frames are in step order, and the
  // tilt grows with the step). Angles are compared in degrees to 1e-9 so that a frame
  // written at "5 degrees" is found by --branch-at 5.
  std::optional<std::size_t> pick;
  for (std::size_t k = 0; k < r.frame_count(); ++k)
    if (r.frame_tilt_angle(k) / kDeg <= at_deg + 1e-9) pick = k;
  if (!pick) {
    char what[160];
    std::snprintf(what, sizeof what, "has no frame at or below %g deg (the first is at %g deg)",
                  at_deg, r.frame_tilt_angle(0) / kDeg);
    throw Error(f.name(), "/particles/grains/position", what);
  }
  PileInput p = start_from_frame(f, r, *pick);
  p.branch = PileInput::Branch{r.frame_steps()[*pick], r.frame_tilt_angle(*pick) / kDeg};
  return p;
}

cd::Settings pile_settings(const PileInput& pile, const OptionValues& values,
                           std::optional<double> mu, std::optional<double> mu_wall) {
  auto param = [&](const std::string& key, double fallback) {
    return pile.parameters.count(key) ? io::as_real(pile.parameters, key, pile.name) : fallback;
  };
  const double diameter = param("diameter_mean_m", analysis::mean_diameter(pile.grains));
  const double gravity = param(parameter_key("gravity"), cd::Settings{}.gravity);
  cd::Settings s =
      settings_from_options(values, {diameter, analysis::mean_mass(pile.grains), gravity});
  s.gravity = gravity;
  s.mu_grain = mu.value_or(param(parameter_key("mu_grain"), s.mu_grain));
  s.mu_wall = mu_wall.value_or(param(parameter_key("mu_wall"), s.mu_wall));
  return s;
}

PileInput read_partial(const std::string& output) {
  const std::string partial = partial_path(output);
  h5::File f = h5::open_read(partial, partial);
  io::RunReader r(f);
  PileInput p;
  p.name = partial;
  p.box = r.header().box;
  p.parameters = r.header().parameters;
  p.provenance = r.header().provenance;
  p.grains = read_checkpoint(f, r.grain_properties()).grains;
  return p;
}

}  // namespace cdpile::sim
