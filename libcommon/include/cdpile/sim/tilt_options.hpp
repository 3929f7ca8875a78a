/// The options of the tilt protocol (docs/method.md, "Tilt"), as run parameters and back,
/// and those of a branch or a resume, which come from the run they continue.
#pragma once

#include "cdpile/analysis/critical.hpp"
#include "cdpile/analysis/series.hpp"
#include "cdpile/cd/engine.hpp"
#include "cdpile/io/schema.hpp"

#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace cdpile::sim {

struct TiltOptions {
  cd::Settings settings;         ///< engine settings (alert distance in m)
  double rate_deg = 0.001;       ///< tilt per step [deg]
  double from_deg = 0.0;         ///< tilt of step 0 [deg]
  std::optional<double> to_deg;  ///< run to this tilt whatever happens [deg]
  double max_deg = 90.0;         ///< without to_deg: stop here if no avalanche [deg]
  double margin_deg = 1.0;       ///< keep tilting this much after the avalanche is confirmed [deg]
  /// The avalanche rule (analysis::AvalancheRule, whose defaults these are): the threshold
  /// of Ek per grain / (m g D), and how long the agitation must stay above it [deg].
  double avalanche_energy = analysis::AvalancheRule{}.threshold;
  double avalanche_hold_deg = analysis::AvalancheRule{}.hold;
  std::int64_t frame_every = 500;        ///< a full frame every this many steps (and the last step)
  std::int64_t checkpoint_every = 2000;  ///< steps between checkpoints (file output)
  double eps = analysis::default_eps;    ///< tolerance of the critical-contact test
};

/// Checks the options; throws cdpile::UsageError naming the bad one.
void validate(const TiltOptions& o);
/// The options as run parameters (unit suffixes; docs/tools/tilt-cd.md lists them).
io::Values tilt_parameters(const TiltOptions& o);
/// Steps of the avalanche hold and of the margin at the options' rate.
std::int64_t hold_steps(const TiltOptions& o);

/// Which run parameter each tilt-cd option sets: a branch or a resume takes these from
/// the run unless they are given (option names without dashes; --frame-every and
/// --frame-every-deg both set frame_every_steps).
const std::vector<std::pair<std::string, std::string>>& tilt_option_parameters();

/// The tilt options a run was made with, read back from its /parameters (the inverse of
/// tilt_parameters); an Error names `file` if one is missing or bad.
TiltOptions tilt_options_from_parameters(const io::Values& v, const std::string& file);

/// One option of a branch or resume whose value differs from the run's.
struct OptionChange {
  std::string option;            ///< the option given (without dashes); empty for a derived value
  std::string parameter;         ///< the run parameter it sets
  std::string run_value, value;  ///< as text
};
struct InheritedOptions {
  TiltOptions options;
  std::vector<OptionChange> changes;  ///< in the order of tilt_option_parameters
};
/// The options of a branch or a resume: the run's (`run`, its /parameters), except those
/// the user gave (`given`, option names), which are taken from `asked` (the command line's
/// options). A frame interval not given keeps the run's interval in degrees when the
/// rate changes. `start_deg`: a branch starts at its frame's tilt, not at the run's
/// --from (not counted as a change). checkpoint_every is always `asked`'s (not a parameter).
InheritedOptions inherit_options(const io::Values& run, const TiltOptions& asked,
                                 const std::set<std::string>& given,
                                 std::optional<double> start_deg, const std::string& file);

}  // namespace cdpile::sim
