// The warnings of a tilt run (warnings.hpp; docs/method.md, "Warnings").
#include "cdpile/sim/warnings.hpp"

#include "cdpile/fields.hpp"

#include <cmath>
#include <cstdio>

namespace cdpile::sim {

std::vector<std::string> run_warnings(std::int64_t steps, std::int64_t unconverged,
                                      double max_overlap_grown_m, double diameter_m,
                                      double contact_stiffness, int max_substeps) {
  std::vector<std::string> w;
  char line[400];
  // 1 %: a few isolated cap hits during impacts are expected and harmless; beyond that the
  // forces of a visible part of the run are those of a truncated Gauss-Seidel, whose
  // critical contacts differ from the converged ones (docs/performance.md). What converges
  // them: with a contact stiffness, sub-steps (docs/method.md, "Sub-steps"); rigid
  // contacts only get more sweeps.
  if (steps > 0 && unconverged * 100 > steps) {
    const std::string cure =
        contact_stiffness <= 0.0
            ? "raise " + field("max_sweeps") + "; docs/performance.md"
        : max_substeps <= 1
            ? "allow sub-steps, " + field("max_substeps") + " 64; docs/method.md, Sub-steps"
            : "raise " + field("max_substeps") + "; docs/method.md, Sub-steps";
    std::snprintf(line, sizeof line,
                  "%lld of %lld steps (%.1f %%) hit the sweep cap; their forces are not converged "
                  "(%s)",
                  static_cast<long long>(unconverged), static_cast<long long>(steps),
                  100.0 * static_cast<double>(unconverged) / static_cast<double>(steps),
                  cure.c_str());
    w.emplace_back(line);
  }
  // 1e-3 D: the documented bound of the overlaps (docs/method.md); larger ones mean grains
  // travel too far in one step for the velocity-level contact law to hold them apart.
  // Measured beyond the pile's own overlaps (sim/overlap.hpp): those a compliant deposit's
  // impacts left are the pile's, not the run's. With a contact stiffness k an overlap is the
  // compliance, an impact at speed v compressing a contact by about v sqrt(m/k) and a
  // static force f by f / k (docs/method.md, "Force selection"): the warning then says so
  // instead of blaming h.
  if (diameter_m > 0.0 && max_overlap_grown_m > 1e-3 * diameter_m) {
    if (contact_stiffness > 0.0)
      std::snprintf(line, sizeof line,
                    "the run's overlaps grew by up to %.2g D, beyond 1e-3 D: the compliance of "
                    "the contact stiffness (an impact at speed v compresses a contact by about "
                    "v sqrt(m/k); a stiffer k makes it smaller)",
                    max_overlap_grown_m / diameter_m);
    else
      std::snprintf(
          line, sizeof line,
          "the run's overlaps grew by up to %.2g D, beyond 1e-3 D; the time step is too large "
          "for these speeds (lower %s)",
          max_overlap_grown_m / diameter_m, field("time_step").c_str());
    w.emplace_back(line);
  }
  return w;
}

std::vector<std::string> settings_warnings(const cd::Settings& s, double diameter_m) {
  std::vector<std::string> w;
  char line[300];
  // The map's grid has h sqrt(g/D) = 0.0099 (no overlap at any tolerance of 1e-3 or
  // tighter) and 0.04 (overlaps at 1e-3 and looser, at nearly every tolerance from 0.16):
  // 0.02 is the geometric middle of the last sound point and the first failing one.
  const double h_hat = diameter_m > 0.0 ? s.time_step * std::sqrt(s.gravity / diameter_m) : 0.0;
  if (h_hat > 0.02) {
    std::snprintf(
        line, sizeof line,
        "h sqrt(g/D) = %.3g is above 0.02; runs of the stability map overlapped beyond 1e-3 D "
        "from 0.04 on (lower %s; docs/performance.md)",
        h_hat, field("time_step").c_str());
    w.emplace_back(line);
  }
  // At 1e-2 and 1e-1 every run of the map at h >= 1e-4 s overlapped, or avalanched more
  // than 2 degrees from the reference (the artificial stiffness of a truncated solver).
  // The map measured the sweep criteria; 'law' is in units of g h, another scale.
  if (s.tolerance >= 1e-2 && s.criterion != cd::Criterion::law) {
    std::snprintf(
        line, sizeof line,
        "the tolerance %.3g is 1e-2 or looser; runs of the stability map overlapped or moved "
        "the avalanche there (lower %s; docs/performance.md)",
        s.tolerance, field("tolerance").c_str());
    w.emplace_back(line);
  }
  return w;
}

}  // namespace cdpile::sim
