/// How a front end lets its users set one of the library's values: the kind of the value,
/// its default, help text, unit and range. The library declares its run parameters this
/// way (sim::run_parameters()) without knowing any front end, as it names its fields
/// (fields.hpp); the command-line tools declare each as an option (cli::Usage::declare),
/// so a parameter's option is written once, beside the parameter.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <variant>
#include <vector>

namespace cdpile {

/// A value given to an option: a real number, an integer or a name (one of its choices).
using OptionValue = std::variant<double, std::int64_t, std::string>;
/// Options' values by option name; an option neither given nor defaulted is absent.
using OptionValues = std::map<std::string, OptionValue>;

struct OptionDeclaration {
  std::string name;      ///< the option's name without dashes (rate)
  std::string group;     ///< its group in the front end's help (Tilt)
  bool integer = false;  ///< an integer, else a real number (or a name, with choices)
  /// The default; std::monostate: none, the option absent means "not given".
  std::variant<std::monostate, double, std::int64_t, std::string> default_value;
  std::string help;                  ///< one sentence
  std::string unit;                  ///< as the user writes it ("deg", "steps"), or empty
  double min = -1e308, max = 1e308;  ///< the range of a value given (inclusive)
  // The rest is optional: initialised, so that a declaration may end before it.
  std::string field{};  ///< the library's name of the value it sets (rate_deg; fields.hpp)
  std::vector<std::string> choices{};  ///< a name, one of these (the default one of them)
  /// Listed in the help after this option of its group, where that is not the declarations'
  /// order (which is also the order a branch lists its changes in); empty: in order.
  std::string after{};
  std::string old_name{};  ///< an old spelling still accepted (theta for theta-method), or empty
};

}  // namespace cdpile
