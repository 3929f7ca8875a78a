/// Where a tilt starts (docs/method.md, "Tilt" and "Checkpoints"): the last frame of a
/// pile, a frame of a run to branch from, or the checkpointed state of a partial run; and
/// the warm start from a frame's contact forces.
#pragma once

#include "cdpile/cd/engine.hpp"
#include "cdpile/io/h5.hpp"
#include "cdpile/io/schema.hpp"
#include "cdpile/model.hpp"
#include "cdpile/option.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace cdpile::sim {

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

/// The engine's settings of a tilt of `pile`: the values of declared_options()
/// (cli::option_values) with those in D or m g / D scaled by the pile's diameter_mean_m
/// (its grains' mean if absent), mean mass and gravity_m_s2, and the pile's gravity and
/// friction unless `mu` or `mu_wall` is given. tilt-cd starts a run with them; so does the
/// harness fuzz_tilt (docs/fuzzing.md).
cd::Settings pile_settings(const PileInput& pile, const OptionValues& values,
                           std::optional<double> mu, std::optional<double> mu_wall);

/// The partial run of `output` as a pile input: box, grains in their checkpointed
/// state, the run's parameters (the pile's and the tilt's) and provenance. Used to build
/// the options of a resumed run the same way as for a fresh one.
PileInput read_partial(const std::string& output);

}  // namespace cdpile::sim
