// The avalanche rule's options (avalanche_options.hpp; docs/method.md, "Avalanche").
#include "cdpile/cli/avalanche_options.hpp"

namespace cdpile::cli {

void declare_avalanche_rule(Usage& u, const std::string& threshold_help,
                            const std::string& hold_help) {
  const analysis::AvalancheRule d;
  u.real("avalanche-ek", d.threshold, threshold_help, "", 1e-300, 1e300);
  u.real("avalanche-hold", d.hold, hold_help, "deg", 0.0, 90.0);
}

analysis::AvalancheRule avalanche_rule(const Args& a) {
  return {a.real("avalanche-ek"), a.real("avalanche-hold")};
}

}  // namespace cdpile::cli
