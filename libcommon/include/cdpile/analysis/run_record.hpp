/// What a run is to the analyses: its per-step series and its frames' records (the inputs
/// of critical_study, built by io from a run, a summary or a contact table), the friction
/// and rules they were read with, and what every study shares (tilt ranges, the rest rule,
/// warnings). Definitions: docs/analysis.md.
#pragma once

#include "cdpile/analysis/critical.hpp"
#include "cdpile/analysis/series.hpp"
#include "cdpile/analysis/table.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace cdpile::analysis {

/// A closed range of tilt angles [deg]; the default covers everything.
struct ThetaRange {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool contains(double t) const { return t >= lo && t <= hi; }
  bool bounded() const {
    return lo > -std::numeric_limits<double>::infinity() ||
           hi < std::numeric_limits<double>::infinity();
  }
};

/// Records the ends of a range as the parameters `<prefix>_lo_deg` and `<prefix>_hi_deg`,
/// leaving out an open end: an HDF5 product holds no infinity (its reader refuses one).
inline void record_range(Values& v, const std::string& prefix, const ThetaRange& r) {
  if (std::isfinite(r.lo)) v[prefix + "_lo_deg"] = r.lo;
  if (std::isfinite(r.hi)) v[prefix + "_hi_deg"] = r.hi;
}

/// When a state of the pile is static (docs/analysis.md, "Static and moving states"): its
/// step converged, it is at rest by deposit's rest criterion (the same thresholds), and no
/// free grain is in flight (without an active contact). Only such states are states a
/// static pile can be in; the others are moving, or their forces are not the step's
/// solution.
struct RestRule {
  double energy = 1e-6;  ///< (Ek + Erot) per free grain below this, in m g D
  double speed = 1e-2;   ///< largest grain speed below this, in sqrt(g D)
};

/// The tangential relative velocity above which a contact slips (is in motion), in
/// sqrt(g D). Default 1e-4: at the paper's rate (0.1 s per degree) a contact slipping that
/// fast slides 1e-3 D per degree of tilt, while a sticking contact of a converged step
/// (residual 1e-4 of g h = 1e-2 sqrt(g D)) has a tangential velocity of about 1e-6.
inline constexpr double default_slip_speed = 1e-4;

/// Bins of the distribution of the mobilisation |f_t| / (mu f_n) of the counted contacts:
/// [0, 1] in 20 bins (the last closed, holding the critical contacts with eps <= 0.05).
inline constexpr std::size_t mobilisation_bins = 20;

/// The rule behind a run's recorded per-step critical count (observable critical_grain,
/// or critical with walls): the simulator's own eps and friction, from the run's
/// /parameters critical_eps, mu_grain and mu_wall. Empty: not recorded.
struct RecordedRule {
  std::optional<double> eps, mu_grain, mu_wall;
};

/// Friction coefficients the user gave (the command line's --mu and --mu-wall); an empty
/// one comes from the run.
struct FrictionChoice {
  std::optional<double> grain, wall;
};

/// mu of an analysis, decided in this one place for every tool: mu_grain is `given.grain`
/// if given, else the run's recorded mu_grain, else an error naming `file` and what is
/// missing ("FILE: /parameters: no mu_grain; give --mu"). mu_wall is `given.wall` if given,
/// else the run's mu_wall unless `given.grain` was given, else mu_grain. `run` is null for
/// an input without parameters (a contact table): then `given.grain` is required. Both
/// must be > 0 (mu = 0 makes every active contact critical): a value given is refused as a
/// usage error naming its field, a recorded one as an error naming the file.
Friction choose_friction(const FrictionChoice& given, const RecordedRule* run,
                         const std::string& file);

/// The rule a view of a run (to-xdmf, to-lammps) flags its critical contacts by, decided in
/// this one place: eps `given`, else the run's recorded critical_eps, else default_eps; the
/// walls as asked. Validated against mu.
CriticalRule view_rule(std::optional<double> given, bool include_walls, const RecordedRule& run,
                       const Friction& mu);

/// Per-step observables of one run, as recorded. Optional series are empty when absent.
struct RunSteps {
  std::vector<std::int64_t> step;
  std::vector<double> theta;              ///< [deg]
  std::vector<std::int64_t> contacts;     ///< N, counted as the rule says
  std::vector<std::int64_t> critical;     ///< Nc per step, if the run records it
  std::vector<std::int64_t> sliding;      ///< contacts with solver status slide, if recorded
  std::vector<double> kinetic_energy;     ///< translational, summed over grains [J/m]
  std::vector<double> rotational_energy;  ///< summed over grains [J/m], if recorded
  std::vector<std::int64_t> converged;    ///< 1 if the step met its criterion, if recorded
  std::vector<double> max_speed;          ///< largest grain speed [m/s], if recorded
  std::vector<std::int64_t> grains_without_contact;  ///< free grains in flight, if recorded
  /// What the solver did, if recorded: sweeps and iterations summed over the step's
  /// sub-steps, and the sub-steps (1: unsplit; docs/method.md, "Sub-steps"). Not read by
  /// any rule; kept so that a summary tells whether its run's steps were split or capped.
  std::vector<std::int64_t> sweeps, substeps;
};

/// Every counted contact of one frame (critical --contacts), in the order of the frame's
/// contacts: its bodies, critical by the rule, the solver's status `slide` (empty without a
/// status), and whether it slips, |u_t| above the slip speed (empty when FrameRecord::
/// slipping is: no velocities, or no g or D). So that a script reads a contact's state from
/// the tool instead of applying the rules again.
struct FrameContacts {
  std::vector<std::int32_t> i, j;
  std::vector<std::uint8_t> critical;
  std::optional<std::vector<std::uint8_t>> sliding, slip;
};

struct FrameRecord {
  std::int64_t frame = 0, step = 0;
  double theta = 0.0;  ///< [deg]
  PileState state;
  std::optional<double> kinetic_energy;  ///< Ek, mean per free grain (mean_kinetic_energy) [J/m]
  std::optional<StaticBound> bound{};    ///< Nc against 2M - 3N (static_bound); empty: unknown
  /// (Ek + Erot) per free grain [J/m] and the largest free-grain speed [m/s]; empty without
  /// velocities (a contact table)
  std::optional<double> agitation{}, max_speed{};
  std::int64_t grains_without_contact{};  ///< free grains with no active contact, walls included
  std::optional<double> z_paper{};        ///< contacts per free grain, walls included (FrameMotion)
  /// counted contacts with |u_t| above the slip speed, and the critical ones among them;
  /// empty without velocities or without g and D
  std::optional<std::int64_t> slipping{}, critical_slipping{};
  /// counted contacts whose bodies (grains, or a wall at rest) are both slower than the rest
  /// speed, and the critical ones among them: the pile's static parts while others move;
  /// empty without velocities or without g and D
  std::optional<std::int64_t> contacts_at_rest{}, critical_at_rest{};
  /// counted contacts per bin of |f_t| / (mu f_n) (mobilisation_bins); empty: not computed
  std::vector<std::int64_t> mobilisation{};
  std::optional<FrameContacts> contacts{};  ///< kept only when asked (frame_record)
};

struct RunRecord {
  std::string name;
  std::int64_t free_grains = 0;
  double diameter = 0.0;                     ///< mean diameter D [m]
  double mean_mass = 0.0;                    ///< [kg/m]
  double gravity = 0.0;                      ///< [m/s^2]; 0 if unknown (then no avalanche angle)
  std::optional<double> recorded_avalanche;  ///< [deg] the simulator's own detection
  Friction mu;                               ///< the friction the frames were classified with
  RecordedRule recorded_rule;  ///< the rule of steps.critical; used only when it is the asked one
  RunSteps steps;
  std::vector<FrameRecord> frames;
};

/// One frame of a run as `critical` reads it: the pile state (eqs 1-2) of the counted
/// contacts `set` (select_contacts of `c`), the static bound (with `eps`), how the grains
/// `g` move, the contacts slipping faster than `slip_speed` sqrt(g D), those at rest (both
/// bodies slower than `rest_speed` sqrt(g D), not slipping) and the histogram of the
/// mobilisation (docs/analysis.md). `run` gives the free grains, D, g and mu; without g or
/// D nothing is counted as slipping or at rest. frame, step and theta are the caller's.
/// With `per_contact`, the record keeps every counted contact's state too (contacts).
/// Throws cdpile::Error as static_bound (a force not finite, mu or eps invalid).
FrameRecord frame_record(const Contacts& c, const Grains& g, const ContactSet& set,
                         const RunRecord& run, double eps, RattlerRule rattlers,
                         double slip_speed = default_slip_speed,
                         double rest_speed = RestRule{}.speed, bool per_contact = false);

/// theta_c of a run by the rule [deg]: empty when the run never passes it, or when its
/// kinetic energy, gravity, grain mass or diameter is unknown.
std::optional<double> avalanche_angle(const RunRecord& r, const AvalancheRule& rule);

/// Notes of a product that are warnings start with this; a tool also says them on stderr.
inline constexpr const char* warning_prefix = "warning: ";

/// The warnings among a product's notes, without the prefix.
std::vector<std::string> product_warnings(const Product& p);

}  // namespace cdpile::analysis
