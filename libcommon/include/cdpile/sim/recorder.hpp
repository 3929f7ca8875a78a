/// Where a tilt run's recorded data goes (docs/method.md, "Checkpoints"; tilt.hpp tells the
/// life of OUTPUT.partial): the steps and frames done since the last commit, and the two
/// recorders, a run to a file through OUTPUT.partial and a run to standard output. The
/// state to resume is the engine's and the loop's (LoopState), kept in the partial's
/// /checkpoint group through io/checkpoint.hpp.
#pragma once

#include "cdpile/cd/engine.hpp"
#include "cdpile/io/files.hpp"
#include "cdpile/io/h5.hpp"
#include "cdpile/io/schema.hpp"
#include "cdpile/model.hpp"
#include "cdpile/sim/avalanche.hpp"
#include "cdpile/sim/common.hpp"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace cdpile::sim {

/// The side file of a run to `output` while it is not complete.
std::string partial_path(const std::string& output);
/// Whether the run to `output` has a partial (an interrupted run to resume).
bool has_partial(const std::string& output);
/// Whether the run to `output` is complete: OUTPUT exists, and a resume has nothing to do.
/// A partial beside it, left by a kill between the final rename and the partial's
/// removal, is removed.
bool finished_run(const std::string& output);

/// Removes temporaries left by a process killed while writing a checkpoint
/// (.OUTPUT.partial.tmp-*) or the final file (.OUTPUT.tmp-*).
void remove_stale_temporaries(const std::string& output);

/// Everything besides the recorded data and the engine's state that the loop needs to
/// continue.
struct LoopState {
  AvalancheDetector detector;
  std::int64_t unconverged = 0;
  double max_overlap = 0.0;        ///< the largest overlap of any step [m]
  double max_overlap_grown = 0.0;  ///< the largest beyond the pile's own (sim/overlap.hpp) [m]
  /// CPU of the tilt so far [s], summed over the processes of a resumed run; recorded in
  /// the run's provenance when it ends (docs/schema.md, "Provenance").
  double cpu_s = 0.0;
};

/// The state a checkpoint restores: the grains, the engine's warm start and clock, the loop.
struct Restored {
  Grains grains;
  cd::EngineState engine;
  LoopState loop;
};
/// Writes the engine's and the loop's state as the file's /checkpoint.
void write_checkpoint(const io::h5::File& f, const cd::Engine& e, const LoopState& s);
/// Reads it back; `properties` are the run's grains. The detector's threshold and hold
/// are options, not state: the caller sets them.
Restored read_checkpoint(const io::h5::File& f, const Grains& properties);

/// Data done since the last commit.
struct Pending {
  io::Series rows = observables_series();
  std::vector<Frame> frames;
  void clear() {
    rows.clear();
    frames.clear();
  }
};

class Recorder {
 public:
  virtual ~Recorder() = default;
  /// A checkpoint: everything pending becomes durable, with the state to resume.
  virtual void commit(Pending& p, const cd::Engine& e, const LoopState& s) = 0;
  /// The run is complete: write the final output with these results.
  virtual void finish(Pending& p, const cd::Engine& e, const LoopState& s,
                      const io::Values& results) = 0;
  /// Ctrl-C: leave a valid file up to the last completed step.
  virtual void interrupt(Pending& p, const cd::Engine& e, const LoopState& s) = 0;
  /// Whether commit() makes the run durable (a checkpoint file) rather than only
  /// gathering it in memory for a final write.
  virtual bool checkpoints() const = 0;
};

/// A run to a file, through OUTPUT.partial (tilt.hpp).
class FileRecorder : public Recorder {
 public:
  FileRecorder(std::string output, bool force);

  /// Starts the partial: header, grains, frame 0 and the checkpoint of step 0.
  void start(const io::RunHeader& h, const Grains& g, Pending& p, const cd::Engine& e,
             const LoopState& s);
  /// The partial already holds everything up to `step` (a resumed run's checkpoint).
  void mark_committed(std::int64_t step) { committed_step_ = step; }

  bool checkpoints() const override { return true; }
  void commit(Pending& p, const cd::Engine& e, const LoopState& s) override;
  void finish(Pending& p, const cd::Engine& e, const LoopState& s,
              const io::Values& results) override;
  void interrupt(Pending& p, const cd::Engine& e, const LoopState& s) override { commit(p, e, s); }

 private:
  /// The end of every write of the partial: the pending data and the checkpoint go into
  /// the temporary `f`, which is closed and renamed over the partial, so that the partial
  /// on disk is always a complete, closed HDF5 file (tilt.hpp).
  void seal(io::h5::File& f, io::RunWriter& w, const std::string& tmp, Pending& p,
            const cd::Engine& e, const LoopState& s);

  std::string output_, partial_;
  bool force_;
  std::int64_t committed_step_ = -1;
};

/// A run to standard output: an in-memory file written out at the end.
class StreamRecorder : public Recorder {
 public:
  StreamRecorder(const io::RunHeader& h, const Grains& g);
  void commit(Pending& p, const cd::Engine& e, const LoopState& s) override;
  void finish(Pending& p, const cd::Engine& e, const LoopState& s,
              const io::Values& results) override;
  void interrupt(Pending& p, const cd::Engine& e, const LoopState& s) override;
  bool checkpoints() const override { return false; }

 private:
  io::Output out_;
  std::unique_ptr<io::RunWriter> writer_;
};

}  // namespace cdpile::sim
