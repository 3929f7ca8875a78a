// The avalanche rule's options (avalanche_options.hpp; docs/method.md, "Avalanche").
#include "cdpile/cli/avalanche_options.hpp"

#include "cdpile/cli/fields.hpp"

namespace cdpile::cli {

void declare_avalanche_rule(Usage& u, const std::string& threshold_help,
                            const std::string& hold_help) {
  const analysis::AvalancheRule d;
  u.real("avalanche-ek", d.threshold, threshold_help, "", 1e-300, 1e300);
  u.real("avalanche-hold", d.hold, hold_help, "deg", 0.0, 90.0);
  // tilt-cd's fields of the rule (sim::TiltOptions), named by these options in messages.
  spell_field("avalanche_energy", "--avalanche-ek");
  spell_field("avalanche_hold_deg", "--avalanche-hold");
}

analysis::AvalancheRule avalanche_rule(const Args& a) {
  return {a.real("avalanche-ek"), a.real("avalanche-hold")};
}

}  // namespace cdpile::cli
