/// The option of the critical test's tolerance eps, declared by every tool that applies the
/// test: tilt-cd (its row of sim::run_parameters(), recorded as critical_eps), critical and
/// localnu (cli::declare_critical_rule) and to-xdmf. Declared here, below both sim and cli,
/// so that its name, default, help and range are written once for the four.
#pragma once

#include "cdpile/analysis/critical.hpp"
#include "cdpile/option.hpp"

#include <sstream>
#include <string>

namespace cdpile::analysis {

/// Whether the option's default is default_eps, or the input run's own critical_eps (a
/// tool that re-reads a run, to-xdmf: the option is then absent unless given).
enum class EpsDefault { fixed, from_run };

/// --eps in `group` of the tool's help. The range is validate()'s [0, 1): the test
/// |f_t| >= (1 - eps) mu f_n means nothing at eps = 1 (every active contact critical),
/// and a command line checks inclusive bounds, so it stops at 1 - 1e-6.
inline OptionDeclaration eps_option(const std::string& group, EpsDefault from = EpsDefault::fixed) {
  OptionDeclaration d;
  d.name = "eps";
  d.field = "eps";
  d.group = group;
  d.help = "tolerance of the critical-contact test |f_t| >= (1 - eps) mu f_n";
  d.min = 0.0;
  d.max = 0.999999;
  if (from == EpsDefault::fixed) {
    d.default_value = default_eps;
  } else {
    std::ostringstream fallback;
    fallback << default_eps;
    d.help += " (default: the run's critical_eps, else " + fallback.str() + ")";
  }
  return d;
}

}  // namespace cdpile::analysis
