// Where a tilt starts: a pile, a run's frame, a partial run (tilt_input.hpp).
#include "cdpile/sim/tilt_input.hpp"

#include "cdpile/error.hpp"
#include "cdpile/parameter_keys.hpp"
#include "cdpile/sim/recorder.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace cdpile::sim {
namespace h5 = io::h5;

namespace {
constexpr double kDeg = M_PI / 180.0;

/// The physical parameters a tilt takes from its pile unless options override them: a
/// bad one is the file's error (exit 1, the file named), not a usage error.
void check_pile_parameters(const io::Values& v, const std::string& file) {
  auto check = [&](const char* key, bool positive) {
    if (!v.count(key)) return;
    const double x = io::as_real(v, key, file);
    if (positive ? !(x > 0) : !(x >= 0)) {
      char what[160];
      std::snprintf(what, sizeof what, "%s must be %s 0, got %g", key, positive ? ">" : ">=", x);
      throw Error(file, "/parameters", what);
    }
  };
  check(keys::mu_grain, false);
  check(keys::mu_wall, false);
  check(keys::gravity_m_s2, false);
  check("diameter_mean_m", true);
}

/// Frame k of a pile or run as the start of a tilt.
PileInput start_from_frame(const io::h5::File& f, const io::RunReader& r, std::size_t k) {
  check_pile_parameters(r.header().parameters, f.name());
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
