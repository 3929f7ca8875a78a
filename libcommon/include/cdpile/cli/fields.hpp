/// The tools' spelling of the library's fields (cdpile/fields.hpp): the option that sets
/// each field, for the library's messages. cli::run_tool installs it.
#pragma once

#include <string>

namespace cdpile::cli {

/// The option of `field`: the table's entry for a field whose option has another name
/// (rate_deg: --rate), else the option of the field's own name (max_sweeps: --max-sweeps).
std::string option_of_field(const std::string& field);

}  // namespace cdpile::cli
