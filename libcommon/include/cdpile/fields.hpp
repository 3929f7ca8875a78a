/// How the library's messages name a field of its options, inputs and choices.
///
/// A message names a field by the library's own name for it, through field(), and never
/// spells a front end's option: the front end says how its users write each field. The
/// command-line tools install their spelling in cli::run_tool (cli/fields.hpp maps the
/// fields whose option is not the field's name: rate_deg is --rate); another front end
/// installs its own (a Python binding would name its keyword arguments). Without one a
/// field reads as the long option of its name, max_sweeps as --max-sweeps, which is also
/// the tools' spelling of most fields.
#pragma once

#include <string>

namespace cdpile {

/// A front end's spelling of a field; nullptr for the default.
using FieldSpelling = std::string (*)(const std::string& field);

/// The default spelling: "--" and the name with '-' for '_' (max_sweeps: --max-sweeps).
inline std::string default_field_spelling(const std::string& field) {
  std::string s = "--" + field;
  for (char& c : s)
    if (c == '_') c = '-';
  return s;
}

inline FieldSpelling& installed_field_spelling() {
  static FieldSpelling spelling = nullptr;
  return spelling;
}

/// Installs a front end's spelling (once, before any work; not thread-safe).
inline void set_field_spelling(FieldSpelling spelling) { installed_field_spelling() = spelling; }

/// The field `name` as the front end's users write it, for a message.
inline std::string field(const std::string& name) {
  const FieldSpelling s = installed_field_spelling();
  return s ? s(name) : default_field_spelling(name);
}

}  // namespace cdpile
