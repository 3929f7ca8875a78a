/// The tilt protocol (docs/method.md, "Tilt" and "Checkpoints"): gravity turns by a fixed
/// angle per step from a static pile until the avalanche is detected plus a margin, or
/// to a given angle; every step's observables and frames at an interval are recorded.
///
/// A run to a file is kept in OUTPUT.partial until it is complete. The partial is a valid
/// run file (docs/schema.md) with one more group, /checkpoint, holding what the engine
/// needs to continue bit for bit (grain state, warm-start impulses, clock, avalanche
/// detector). Every checkpoint copies the partial to a temporary beside it, appends the
/// steps and frames done since, rewrites /checkpoint, closes it and renames it over the
/// partial: the partial on disk is always a complete, closed HDF5 file, whatever moment
/// the process is killed at. The finished run is written from the partial to a
/// temporary, renamed onto OUTPUT, and the partial is removed.
#pragma once

#include "cdpile/analysis/critical.hpp"
#include "cdpile/cd/engine.hpp"
#include "cdpile/io/schema.hpp"
#include "cdpile/model.hpp"

#include <cstdint>
#include <functional>
#include <optional>
#include <set>
#include <utility>
#include <string>
#include <vector>

namespace cdpile::sim {

struct TiltOptions {
  cd::Settings settings;          ///< engine settings (alert distance in m)
  double rate_deg = 0.001;        ///< tilt per step [deg]
  double from_deg = 0.0;          ///< tilt of step 0 [deg]
  std::optional<double> to_deg;   ///< run to this tilt whatever happens [deg]
  double max_deg = 90.0;          ///< without to_deg: stop here if no avalanche [deg]
  double margin_deg = 1.0;        ///< keep tilting this much after the avalanche is confirmed [deg]
  double avalanche_energy = 1e-3; ///< threshold of Ek per grain / (m g D)
  double avalanche_hold_deg = 0.2;///< the agitation must stay above it this long [deg]
  std::int64_t frame_every = 500; ///< a full frame every this many steps (and the last step)
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
  std::string option;     ///< the option given (without dashes); empty for a derived value
  std::string parameter;  ///< the run parameter it sets
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
InheritedOptions inherit_options(const io::Values& run, const TiltOptions& asked, const std::set<std::string>& given,
                                 std::optional<double> start_deg, const std::string& file);

/// A static pile to tilt: the last frame of a "pile" file, or a frame of a run to branch
/// from (read_branch).
struct PileInput {
  std::string name;
  Box box;
  Grains grains;
  Contacts contacts;  ///< the frame's contacts: their forces warm-start the first step
  io::Values parameters;
  std::vector<io::Provenance> provenance;
  /// Set when the start is a frame of a run: the run's step and tilt at that frame.
  struct Branch {
    std::int64_t step = 0;
    double tilt_deg = 0.0;
  };
  std::optional<Branch> branch;
};
/// Reads a pile file; an Error naming the file if it is not a pile or has no frame.
PileInput read_pile(const io::h5::File& f);
/// A branch of a tilt run: the last of its frames at or below `at_deg` degrees, with its
/// grains (positions, velocities, rotations) and contact forces, to tilt again from there
/// with other options (a tighter solver, frames every step, another rate). The forces
/// warm-start the first step as a pile's do; a frame's force is its step's impulse over
/// h, so a branch with the run's own options repeats the run's next steps up to the
/// rounding of impulse = force x h. An Error names the file if it is not a run or has no
/// such frame.
PileInput read_branch(const io::h5::File& f, double at_deg);

/// The engine state that warm-starts a first step from a frame's contact forces
/// (impulse = force x `time_step`), sorted by pair as cd::Engine::set_state wants: how a
/// tilt starts from a pile's equilibrium or from a branch's frame.
cd::EngineState warm_start_state(const Contacts& contacts, double time_step);

/// The side file of a run to `output` while it is not complete.
std::string partial_path(const std::string& output);
/// The partial run of `output` as a pile input: box, grains in their checkpointed
/// state, the run's parameters (the pile's and the tilt's) and provenance. Used to build
/// the options of a resumed run the same way as for a fresh one.
PileInput read_partial(const std::string& output);

struct TiltProgress {
  std::int64_t step = 0;
  double angle_deg = 0.0;
  double agitation = 0.0;        ///< Ek per grain / (m g D)
  bool avalanche = false;        ///< confirmed
  double avalanche_deg = 0.0;
  std::int64_t last_step = -1;   ///< the step the run will end at, -1 if not known yet
  std::int64_t cap_step = 0;     ///< the latest it can end at
};

struct TiltHooks {
  /// Called after every step (may be empty). An exception thrown here ends the run
  /// abruptly, as a crash would (the tests use it).
  std::function<void(const TiltProgress&)> progress;
  /// Polled after every step and before every solver sweep (may be empty): true writes a
  /// checkpoint of everything done up to the last completed step and returns (Ctrl-C,
  /// SIGTERM), within a second of turning true however long a step takes.
  std::function<bool()> stop;
  /// Called with true before the first step and with false once what is left is writing
  /// output that ending at once loses nothing of (may be empty): the final file, copied
  /// from OUTPUT.partial once that holds the whole run, or a run to standard output. In
  /// between the run only ends through stop(), so that a second signal (a scheduler
  /// signals the tool and its parent make, which forwards its own) cannot cut the
  /// checkpoint being written. tilt-cd defers its signals to stop() meanwhile.
  std::function<void(bool)> deferring;
};

struct TiltOutcome {
  std::int64_t first_step = 0;   ///< step the run started (or resumed) from
  std::int64_t steps = 0;        ///< last step done
  double final_angle_deg = 0.0;
  bool avalanche = false;
  double avalanche_deg = 0.0;
  bool interrupted = false;
  std::string stop_reason;       ///< "avalanche", "to", "max_angle" or "interrupted"
  std::int64_t unconverged_steps = 0;
  /// settings_warnings, then run_warnings, of the finished run (also in /results)
  std::vector<std::string> warnings;
};

/// The run-time warnings of a run (docs/method.md, "Warnings"): what tells a user that the
/// numbers of a run are not to be trusted as they stand. Each is one sentence without the
/// tool name; none when the run is sound.
///  - more than 1 % of the steps hit the sweep cap (forces not converged in those steps);
///  - the largest overlap exceeds 1e-3 D (the step lets grains move too far: --time-step).
/// `steps` counts every step of the run, `unconverged` those at the cap, `max_overlap_m`
/// the largest overlap seen, `diameter_m` the mean diameter, `contact_stiffness` the
/// settings' k [N/m^2] (0: rigid contacts; with k > 0 an overlap is the compliance f / k).
std::vector<std::string> run_warnings(std::int64_t steps, std::int64_t unconverged, double max_overlap_m,
                                      double diameter_m, double contact_stiffness = 0.0);

/// The warnings a run's settings earn before it starts (docs/method.md, "Warnings"), from
/// the stability map (docs/performance.md, "Where the methods fail"); one sentence each,
/// none for sound settings:
///  - h sqrt(g/D) above 0.02 (the map's runs overlapped beyond 1e-3 D from 0.04 on);
///  - a tolerance of 1e-2 or looser (the map's runs overlapped or moved the avalanche).
/// `diameter_m` is the mean diameter.
std::vector<std::string> settings_warnings(const cd::Settings& s, double diameter_m);

/// Refuses (before any work) an output run_tilt would refuse: an existing OUTPUT or
/// OUTPUT.partial without `force`, a missing folder, standard output on a terminal.
void check_output(const std::string& output, bool force);

/// Tilts `pile` and writes the run to `output` (a path, or "-" for standard output,
/// which has no checkpoints). Refuses an existing output or partial unless `force`.
TiltOutcome run_tilt(const PileInput& pile, const TiltOptions& o, const std::string& output, bool force,
                     const io::Provenance& prov, const TiltHooks& hooks = {});

/// Continues the run of OUTPUT.partial. The options must give the same parameters as
/// the partial run (an Error names the first that differs).
TiltOutcome resume_tilt(const TiltOptions& o, const std::string& output, bool force,
                        const TiltHooks& hooks = {});

}  // namespace cdpile::sim
