/// The /checkpoint group of a partial run (docs/method.md, "Checkpoints"): what a
/// protocol needs, besides the run's recorded data, to continue bit for bit. The group
/// holds the grains' state, the warm-start impulses by pair, the clock, and the
/// protocol's own counters as attributes (the tilt's avalanche detector, sim/recorder.hpp).
/// io knows the layout only; what the counters mean is the protocol's.
#pragma once

#include "cdpile/io/h5.hpp"
#include "cdpile/io/schema.hpp"
#include "cdpile/model.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace cdpile::io {

/// The group's path in a partial run.
inline constexpr const char* kCheckpointGroup = "/checkpoint";

/// One warm-start impulse [N s/m] of the last step, by pair (i, j).
struct CheckpointImpulse {
  std::int32_t i = 0, j = 0;
  double rn = 0.0, rt = 0.0;
};

struct Checkpoint {
  Grains grains;  ///< positions, velocities, orientations and angular velocities are stored
  std::vector<CheckpointImpulse> impulses;
  std::int64_t step = 0;
  double time = 0.0;
  /// The protocol's counters, written as attributes in this order (read back in the
  /// file's order of attributes).
  std::vector<std::pair<std::string, Value>> counters;
  std::string description;  ///< the group's description attribute

  /// A counter read back; an Error names `file` and the group if it is missing or of
  /// another type.
  /// Whether the partial has the counter (one written by an earlier version may not).
  bool has_counter(const std::string& name) const;
  std::int64_t counter_int(const std::string& name, const std::string& file) const;
  double counter_real(const std::string& name, const std::string& file) const;
};

/// Writes `c` as the file's /checkpoint, replacing the one there.
void write_checkpoint(const h5::File& f, const Checkpoint& c);

/// The checkpoint of `f`; `properties` are the run's grains (radii, masses, species), whose
/// state the checkpoint's replaces. An Error names the file if there is none ("not a
/// partial run") or it does not match them.
Checkpoint read_checkpoint(const h5::File& f, const Grains& properties);

/// What a tool that reads runs is given for a run tilt-cd may still be computing: `path`
/// itself if it exists, else PATH.partial if that exists (tilt-cd writes OUTPUT.partial
/// until the run is finished; docs/method.md, "Checkpoints"), else `path` (whose absence
/// the reader then reports). Reading a partial does not disturb tilt-cd: every checkpoint
/// replaces the partial by a rename, so a reader keeps the complete file it opened.
std::string run_or_partial(const std::string& path);

/// For a partial run (a file with /checkpoint), the one line a tool says about it on
/// stderr: what it holds (its frames up to the last checkpoint); empty otherwise.
std::string partial_run_note(const RunReader& run);

}  // namespace cdpile::io
