// The tools' spelling of the library's fields (cli/fields.hpp).
#include "cdpile/cli/fields.hpp"

#include "cdpile/fields.hpp"

#include <map>

namespace cdpile::cli {

namespace {
// Field -> option. The options the library declares (sim::run_parameters()) enter here as
// a tool declares them (Usage::declare), so their spelling is written once, in their row.
// The others whose option is not their field's name are spelled where they are declared:
// the avalanche rule's bundle (shared with tools that do not link sim) and the output.
std::map<std::string, std::string>& spellings() {
  static std::map<std::string, std::string> table = {{"output", "-o"}};
  return table;
}
}  // namespace

void spell_field(const std::string& field, const std::string& option) {
  spellings()[field] = option;
}

std::string option_of_field(const std::string& field) {
  const auto& table = spellings();
  const auto it = table.find(field);
  return it != table.end() ? it->second : default_field_spelling(field);
}

}  // namespace cdpile::cli
