// The tools' spelling of the library's fields (cli/fields.hpp).
#include "cdpile/cli/fields.hpp"

#include "cdpile/fields.hpp"

#include <map>

namespace cdpile::cli {

std::string option_of_field(const std::string& field) {
  // The fields whose option is not their name: sim::TiltOptions' fields carry their unit
  // (docs/tools/tilt-cd.md lists the options), the output is -o.
  static const std::map<std::string, std::string> table = {
      {"rate_deg", "--rate"},
      {"from_deg", "--from"},
      {"to_deg", "--to"},
      {"max_deg", "--max-angle"},
      {"margin_deg", "--margin"},
      {"avalanche_energy", "--avalanche-ek"},
      {"avalanche_hold_deg", "--avalanche-hold"},
      {"contact_stiffness", "--stiffness"},
      {"output", "-o"}};
  const auto it = table.find(field);
  return it != table.end() ? it->second : default_field_spelling(field);
}

}  // namespace cdpile::cli
