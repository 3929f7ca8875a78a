// The friction coefficients of an analysis (analysis/studies.hpp, choose_friction), and the
// rule a view of a run flags its critical contacts by (view_rule).
#include "cdpile/analysis/run_record.hpp"
#include "cdpile/error.hpp"
#include "cdpile/fields.hpp"

#include <charconv>
#include <cmath>

namespace cdpile::analysis {

namespace {
// The shortest text that reads back to v (NA when not finite), as the products write it.
std::string shortest(double v) {
  if (!std::isfinite(v)) return "NA";
  if (v == 0.0) return "0";
  char buf[64];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return ec == std::errc() ? std::string(buf, end) : "NA";
}
}  // namespace

Friction choose_friction(const FrictionChoice& given, const RecordedRule* run,
                         const std::string& file) {
  // A value given is refused before anything of the file is used.
  for (const auto& [value, name] : {std::pair{given.grain, "mu"}, {given.wall, "mu_wall"}})
    if (value && !(*value > 0.0 && std::isfinite(*value)))
      throw UsageError(field(name) +
                       " must be > 0 (mu = 0 makes every active contact critical), got " +
                       shortest(*value));
  Friction mu;
  if (given.grain) {
    mu.grain = *given.grain;
  } else if (run) {
    if (!run->mu_grain) throw Error(file, "/parameters", "no mu_grain; give " + field("mu"));
    mu.grain = *run->mu_grain;
  } else {
    throw Error(file, "", "a contact table has no friction coefficient; give " + field("mu"));
  }
  if (given.wall)
    mu.wall = *given.wall;
  else if (run && !given.grain && run->mu_wall)
    mu.wall = *run->mu_wall;
  else
    mu.wall = mu.grain;
  if (!(mu.grain > 0.0) || !std::isfinite(mu.grain))
    throw Error(file, run ? "/parameters" : "", "mu_grain must be > 0, got " + shortest(mu.grain));
  if (!(mu.wall > 0.0) || !std::isfinite(mu.wall))
    throw Error(file, run ? "/parameters" : "", "mu_wall must be > 0, got " + shortest(mu.wall));
  return mu;
}

CriticalRule view_rule(std::optional<double> given, bool include_walls, const RecordedRule& run,
                       const Friction& mu) {
  CriticalRule rule;
  rule.eps = given ? *given : run.eps.value_or(default_eps);
  rule.include_walls = include_walls;
  validate(rule, mu);
  return rule;
}

}  // namespace cdpile::analysis
