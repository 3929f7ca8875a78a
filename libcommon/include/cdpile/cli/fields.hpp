/// The tools' spelling of the library's fields (cdpile/fields.hpp): the option that sets
/// each field, for the library's messages. cli::run_tool installs it.
#pragma once

#include <string>

namespace cdpile::cli {

/// The option of `field`: the option declared for it (Usage::declare, spell_field) where
/// its name is another (rate_deg: --rate), else the option of the field's own name
/// (max_sweeps: --max-sweeps).
std::string option_of_field(const std::string& field);

/// Declares that `option` (with its dashes) sets `field`, for the library's messages; an
/// option declared by the library (OptionDeclaration::field) is recorded by Usage::declare.
void spell_field(const std::string& field, const std::string& option);

}  // namespace cdpile::cli
