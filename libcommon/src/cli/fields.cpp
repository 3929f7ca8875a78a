// The tools' spelling of the library's fields (cli/fields.hpp).
#include "cdpile/cli/fields.hpp"

#include "cdpile/fields.hpp"

#include <map>

namespace cdpile::cli {

std::string option_of_field(const std::string& field) {
  // The fields whose option is not their name: sim::TiltOptions' fields carry their unit
  // (docs/tools/tilt-cd.md lists the options), the output is -o. The run parameters'
  // options are declared in sim::run_parameters() (cli cannot read sim, a layer of its
  // level): a unit test (test_sim_run_parameters.cpp) checks these entries against it.
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
