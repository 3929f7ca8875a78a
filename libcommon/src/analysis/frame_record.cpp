// One frame of a run as `critical` reads it (analysis/studies.hpp, frame_record).
#include "cdpile/analysis/run_record.hpp"

#include <cmath>

namespace cdpile::analysis {

FrameRecord frame_record(const Contacts& c, const Grains& g, const ContactSet& set,
                         const RunRecord& run, double eps, RattlerRule rattlers, double slip_speed,
                         double rest_speed, bool per_contact) {
  FrameRecord f;
  if (per_contact) {
    f.contacts = FrameContacts{set.i, set.j, set.critical, std::nullopt, std::nullopt};
    if (set.has_status) f.contacts->sliding = set.sliding;
  }
  // the slip threshold in m/s: slip_speed sqrt(g D), unknown without g or D
  const double slip = run.gravity > 0.0 && run.diameter > 0.0
                          ? slip_speed * std::sqrt(run.gravity * run.diameter)
                          : 0.0;
  f.state = pile_state(set, g.species, run.free_grains, run.diameter, rattlers);
  f.kinetic_energy = mean_kinetic_energy(g);
  const FrameMotion motion = frame_motion(g, c);
  f.agitation = motion.agitation;
  f.max_speed = motion.max_speed;
  f.grains_without_contact = motion.grains_without_contact;
  f.z_paper = motion.contacts_per_grain;
  if (slip > 0.0 && motion.max_speed) {
    const std::vector<double> u = slip_speeds(c, set, g);
    std::int64_t slipping = 0, critical = 0;
    if (per_contact) f.contacts->slip.emplace(u.size(), std::uint8_t{0});
    for (std::size_t q = 0; q < u.size(); ++q) {
      if (!(u[q] > slip)) continue;
      ++slipping;
      critical += set.critical[q];
      if (per_contact) (*f.contacts->slip)[q] = 1;
    }
    f.slipping = slipping;
    f.critical_slipping = critical;
    const RestCount at_rest =
        contacts_at_rest(c, set, g, u, rest_speed * std::sqrt(run.gravity * run.diameter), slip);
    f.contacts_at_rest = at_rest.contacts;
    f.critical_at_rest = at_rest.critical;
  }
  f.mobilisation = mobilisation_histogram(set, mobilisation_bins);
  f.bound = static_bound(c, g.species, run.mu, eps);
  return f;
}

}  // namespace cdpile::analysis
