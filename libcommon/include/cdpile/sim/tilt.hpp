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

#include "cdpile/io/schema.hpp"
#include "cdpile/sim/recorder.hpp"
#include "cdpile/sim/tilt_input.hpp"
#include "cdpile/sim/tilt_options.hpp"
#include "cdpile/sim/warnings.hpp"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace cdpile::sim {

struct TiltProgress {
  std::int64_t step = 0;
  double angle_deg = 0.0;
  double agitation = 0.0;  ///< Ek per grain / (m g D)
  bool avalanche = false;  ///< confirmed
  double avalanche_deg = 0.0;
  std::int64_t last_step = -1;  ///< the step the run will end at, -1 if not known yet
  std::int64_t cap_step = 0;    ///< the latest it can end at
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
  std::int64_t first_step = 0;  ///< step the run started (or resumed) from
  std::int64_t steps = 0;       ///< last step done
  double final_angle_deg = 0.0;
  bool avalanche = false;
  double avalanche_deg = 0.0;
  bool interrupted = false;
  std::string stop_reason;  ///< "avalanche", "to", "max_angle" or "interrupted"
  std::int64_t unconverged_steps = 0;
  /// settings_warnings, then run_warnings, of the finished run (also in /results)
  std::vector<std::string> warnings;
};

/// Refuses (before any work) an output run_tilt would refuse: an existing OUTPUT or
/// OUTPUT.partial without `force`, a missing folder, standard output on a terminal.
void check_output(const std::string& output, bool force);

/// Tilts `pile` and writes the run to `output` (a path, or "-" for standard output,
/// which has no checkpoints). Refuses an existing output or partial unless `force`.
TiltOutcome run_tilt(const PileInput& pile, const TiltOptions& o, const std::string& output,
                     bool force, const io::Provenance& prov, const TiltHooks& hooks = {});

/// Continues the run of OUTPUT.partial. The options must give the same parameters as
/// the partial run (an Error names the first that differs).
TiltOutcome resume_tilt(const TiltOptions& o, const std::string& output, bool force,
                        const TiltHooks& hooks = {});

}  // namespace cdpile::sim
