/// The options of the tilt protocol (docs/method.md, "Tilt"), as run parameters and back,
/// and those of a branch or a resume, which come from the run they continue.
#pragma once

#include "cdpile/analysis/critical.hpp"
#include "cdpile/analysis/series.hpp"
#include "cdpile/cd/engine.hpp"
#include "cdpile/io/schema.hpp"
#include "cdpile/option.hpp"

#include <cmath>
#include <cstdint>
#include <functional>
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

// ---------------------------------------------------------------------------------
// The run parameters, each declared once: the field of TiltOptions (or of its engine
// settings) that holds it, the file key it is recorded under in /parameters (docs/schema.md,
// unit suffixes), its unit, the tilt-cd option that sets it and how that option is
// declared (help, unit, range; the default is the field's), and whether a branch or a
// resume takes it from the run it continues. settings_parameters (common.hpp) and its
// inverse, tilt_parameters and its inverse, tilt_option_parameters and inherit_options
// all derive from this one table, so a parameter cannot be recorded and yet not inherited
// (docs/architecture.md, "A new run parameter").

/// Whether a branch or a resume takes a value from the run it continues.
enum class Inherit {
  from_run,  ///< recorded: the run's value unless the option is given
  as_asked,  ///< not recorded (how fast, not what: threads, checkpoints): the command line's
};

/// Which group of a run's parameters a value belongs to: the engine's settings (deposit
/// and tilt-cd record them) or the tilt protocol's (tilt-cd only).
enum class ParameterGroup { settings, tilt };

/// The unit an option is given in where it is not its field's SI unit: the pile's mean
/// diameter D (the alert distance), or m g / D, a mean grain's weight per diameter (the
/// contact stiffness), so that one value suits piles of any grain size.
enum class OptionScale { none, diameter, weight_per_diameter };
/// The pile's scales that convert those options: D [m], the mean grain mass m [kg/m] (per
/// unit thickness) and g [m/s^2].
struct PileScale {
  double diameter = 1.0, mass = 1.0, gravity = 1.0;
};

/// The values the library accepts for a field, whatever the front end (validate(); an
/// option's declared range, the front end's, may be narrower): at least `low` (above it if
/// `low_open`), below `below` if given, and finite if `finite`. A NaN is refused.
struct Accepted {
  double low = -HUGE_VAL;
  bool low_open = false;
  std::optional<double> below;
  bool finite = false;
};

struct RunParameter {
  std::string field;        ///< the library's name (cdpile::field() spells it for messages)
  std::string key;          ///< the /parameters key; empty: not recorded
  std::string unit;         ///< of the recorded value, SI ("" dimensionless or text)
  std::string option;       ///< tilt-cd's option without dashes; empty: none (from the pile)
  std::string also_option;  ///< a second option setting it (frame-every-deg), or empty
  ParameterGroup group = ParameterGroup::tilt;
  Inherit inherit = Inherit::from_run;
  /// The value a file written before the solver seam holds implicitly (pre_seam_settings).
  std::optional<io::Value> pre_seam;
  /// A value shown as a word in the messages of a branch (tilt_to_deg -1: "none").
  std::optional<std::pair<io::Value, std::string>> shown_as;
  /// The field's value as recorded (an engine setting's from o.settings).
  std::function<io::Value(const TiltOptions& o)> get;
  /// Sets the field from `v`'s entry under `name`; throws cdpile::Error naming `file` if
  /// it is missing or of the wrong kind. A text value (an enum's name) is set by its
  /// name and throws cdpile::UsageError if the name is unknown.
  std::function<void(TiltOptions& o, const io::Values& v, const std::string& name,
                     const std::string& file)>
      set;
  bool text = false;  ///< recorded as text (an enum's name)
  /// The option's declaration, its kind and default from the field's type and its default
  /// as an option (option_defaults()); empty for an option declared by one of the tools'
  /// bundles (the avalanche rule, the friction: cli/*_options.hpp) or by tilt-cd itself
  /// (the frame interval).
  std::optional<OptionDeclaration> declaration;
  OptionScale scale = OptionScale::none;  ///< the option's unit, if not the field's
  /// The values validate() accepts, with a message naming the field and the range; empty:
  /// any (or checked with another field, or by cd::validate for the engine's settings).
  std::optional<Accepted> accepted;
  /// Sets the field from its option's value (in the field's unit); absent (an option
  /// without a default, not given) leaves an optional field empty (to_deg: none).
  std::function<void(TiltOptions& o, const std::optional<OptionValue>& v)> set_option;
};

/// Every run parameter, in the order a branch lists its changes (tilt-cd's options: the
/// tilt, the avalanche, the recording, the friction, the solver).
const std::vector<RunParameter>& run_parameters();
/// The /parameters key of the run parameter of `field` (its row's), for the code that
/// reads one parameter by name; std::logic_error if no row has that field.
const std::string& parameter_key(const std::string& field);
/// The keys `group` records, in the table's order, comma-separated, a value recorded for a
/// word said ("tilt_to_deg (-1 if none)"): deposit's and tilt-cd's --help list the
/// parameters from here, so a new row is listed with no other edit.
std::string recorded_keys(ParameterGroup group);

/// The options declared in run_parameters(), in its order: tilt-cd declares them
/// (cli::Usage::declare) and reads them back into TiltOptions (set_declared_options and
/// settings_from_options); deposit declares and reads those of the engine's settings, the
/// "Solver" group.
std::vector<OptionDeclaration> declared_options();
/// Sets the tilt protocol's fields of declared_options() from their values
/// (cli::option_values).
void set_declared_options(TiltOptions& o, const OptionValues& values);
/// The engine's settings from the values of declared_options() (cli::option_values), the
/// options in D or m g / D converted by `scale`; those without an option (gravity, the
/// friction) are cd::Settings' defaults; --max-substeps and --max-sweeps not given take
/// option_defaults()' values, rigid_option_defaults()' with --stiffness 0. Throws
/// cdpile::UsageError for a number of sub-steps that is not a power of two.
cd::Settings settings_from_options(const OptionValues& values, const PileScale& scale);
/// The engine's settings the options default to: cd::Settings' with the solver that
/// converges the compliant steps (pcg), the tolerance at which their critical contacts
/// converge (1e-6), and sub-steps that rescue the rare step pcg leaves unconverged after
/// 1000 sweeps (docs/method.md, "Defaults and their reasons").
cd::Settings option_defaults();
/// The options' defaults with --stiffness 0: option_defaults() with rigid contacts, no
/// sub-steps (halving h does not improve a rigid step's conditioning) and a sweep cap of
/// 100 000 at h, which settings_from_options takes where --max-substeps or --max-sweeps is
/// not given (docs/method.md, "Sub-steps").
cd::Settings rigid_option_defaults();

/// Checks the options: each field's range (RunParameter::accepted), then the tilts against
/// the start and the frame interval, then the engine's settings (cd::validate); throws
/// cdpile::UsageError naming the first bad one.
void validate(const TiltOptions& o);
/// The options as run parameters (unit suffixes; docs/tools/tilt-cd.md lists them).
io::Values tilt_parameters(const TiltOptions& o);
/// Steps of the avalanche hold and of the margin at the options' rate.
std::int64_t hold_steps(const TiltOptions& o);

/// Which run parameter each tilt-cd option sets: a branch or a resume takes these from
/// the run unless they are given (option names without dashes; --frame-every and
/// --frame-every-deg both set frame_every_steps). Derived from run_parameters(),
/// as are tilt_parameters and its inverse.
const std::vector<std::pair<std::string, std::string>>& tilt_option_parameters();

/// The tilt options a run was made with, read back from its /parameters (the inverse of
/// tilt_parameters); an Error names `file` if one is missing or bad.
TiltOptions tilt_options_from_parameters(const io::Values& v, const std::string& file);

/// One option of a branch or resume whose value differs from the run's.
struct OptionChange {
  std::string option;            ///< the option given (without dashes); empty for a derived value
  std::string parameter;         ///< the run parameter it sets
  std::string run_value, value;  ///< as text
  std::string reason;            ///< why a derived value changed; empty for an option given
};
struct InheritedOptions {
  TiltOptions options;
  std::vector<OptionChange> changes;  ///< in the order of run_parameters()
};
/// The options of a branch or a resume: the run's (`run`, its /parameters), except those
/// the user gave (`given`, option names), which are taken from `asked` (the command line's
/// options). A frame interval not given keeps the run's interval in degrees when the
/// rate changes; a branch that makes the contacts rigid (or compliant) takes their
/// defaults of --max-substeps and --max-sweeps where not given. `start_deg`: a branch starts at
/// its frame's tilt, not at the run's
/// --from (not counted as a change). What is not a parameter (checkpoint_every, threads:
/// Inherit::as_asked in run_parameters()) is always `asked`'s.
InheritedOptions inherit_options(const io::Values& run, const TiltOptions& asked,
                                 const std::set<std::string>& given,
                                 std::optional<double> start_deg, const std::string& file);

}  // namespace cdpile::sim
