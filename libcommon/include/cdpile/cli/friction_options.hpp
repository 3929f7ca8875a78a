/// --mu and --mu-wall, the friction coefficients, declared in this one place for every tool
/// that takes them (deposit, tilt-cd, critical, localnu, to-xdmf), with one range.
#pragma once

#include "cdpile/analysis/run_record.hpp"
#include "cdpile/cli/command.hpp"

#include <optional>
#include <string>

namespace cdpile::cli {

/// The range of --mu and --mu-wall: a friction coefficient in [0, 1000]. 0 (frictionless)
/// is a simulator's choice; an analysis refuses it (analysis::choose_friction).
inline constexpr double mu_min = 0.0, mu_max = 1e3;

/// Declares --mu and --mu-wall with the tool's help texts: with `defaults`, options with
/// those default values (deposit); without, options absent unless given, whose default
/// comes from the input file.
void declare_friction(Usage& u, const std::string& mu_help, const std::string& mu_wall_help,
                      std::optional<analysis::Friction> defaults = {});

/// --mu and --mu-wall as given (empty when not given), for analysis::choose_friction.
analysis::FrictionChoice friction_choice(const Args& a);

}  // namespace cdpile::cli
