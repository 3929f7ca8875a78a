/// --avalanche-ek and --avalanche-hold, the avalanche rule (analysis::AvalancheRule, whose
/// defaults they take), declared in this one place for every tool that applies it (tilt-cd
/// as the run goes, critical and localnu over a recorded run), with one range.
#pragma once

#include "cdpile/analysis/series.hpp"
#include "cdpile/cli/command.hpp"

#include <string>

namespace cdpile::cli {

/// Declares --avalanche-ek and --avalanche-hold in the current group, with the tool's help
/// texts (by default the analysis tools').
void declare_avalanche_rule(
    Usage& u,
    const std::string& threshold_help = "threshold of Ek/(m g D) that marks the avalanche",
    const std::string& hold_help = "Ek must stay above the threshold this long");

/// The rule of declare_avalanche_rule's options.
analysis::AvalancheRule avalanche_rule(const Args& a);

}  // namespace cdpile::cli
