#include "cdpile/cli/friction_options.hpp"

namespace cdpile::cli {

void declare_friction(Usage& u, const std::string& mu_help, const std::string& mu_wall_help,
                      std::optional<analysis::Friction> defaults) {
  if (defaults) {
    u.real("mu", defaults->grain, mu_help, "", mu_min, mu_max);
    u.real("mu-wall", defaults->wall, mu_wall_help, "", mu_min, mu_max);
  } else {
    u.real_opt("mu", mu_help, "", mu_min, mu_max);
    u.real_opt("mu-wall", mu_wall_help, "", mu_min, mu_max);
  }
}

analysis::FrictionChoice friction_choice(const Args& a) {
  return {a.real_opt("mu"), a.real_opt("mu-wall")};
}

}  // namespace cdpile::cli
