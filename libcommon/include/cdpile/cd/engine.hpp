/// The Contact Dynamics engine (Moreau-Jean time stepping with non-smooth Gauss-Seidel),
/// for rigid disks in a box of a floor and two side walls, under a gravity rotated by
/// the tilt angle. docs/method.md states the scheme, every default and its reason.
///
/// One step, in stages (docs/method.md, "The scheme"; LMGC90's `one_step`):
///   1. free velocity       v_free = v + h g(theta), g(theta) = g (sin theta, -cos theta)
///   2. detect              pairs within the alert distance in the predicted
///                          configuration q_m = q + (1 - theta_s) h v (cell grid, O(N))
///   3. frames              normal, tangent, lever arms and gap of each contact at q_m
///   4. Delassus diagonal   W_nn = sum 1/m, W_tt = sum (1/m + r^2/I) (disk blocks are diagonal)
///   5. warm start          impulses of the previous step, matched by the pair (i, j)
///   6. solve               the contact system (contact_system.hpp) by the solver of the
///                          settings (solver.hpp; NSGS: exact local solves until the criterion
///                          or the cap), then the law's residual, whatever the solver
///   7. update velocities   v = v_free + M^-1 H^T R (already held by the bodies, ELG style)
///   8. update positions    q = q_m + theta_s h v
///   9. store impulses      for the next warm start
/// theta_s is the theta-method parameter (Settings::theta). With sub-steps
/// (TimeStepping::max_substeps > 1) stages 1-9 run once per sub-step of h / 2^level, and a
/// step whose solve does not converge within TimeStepping::substep_after sweeps is redone
/// in two halves (docs/method.md, "Sub-steps").
#pragma once

#include "cdpile/cd/contact_system.hpp"
#include "cdpile/cd/detection.hpp"
#include "cdpile/cd/solver.hpp"
#include "cdpile/cd/team.hpp"
#include "cdpile/model.hpp"

#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace cdpile::cd {

struct DelassusProblem;  // delassus.hpp

/// How a step advances the pile: the time stepping and the contact law. SI units;
/// defaults are for a mean grain diameter D = 1e-3 m (docs/method.md gives the reason for
/// each). Nothing here is a solver choice (SolverSettings, solver.hpp).
/// Where each step's sub-steps start (TimeStepping::substep_start).
enum class SubstepStart { last, h };
const char* substep_start_name(SubstepStart s);
SubstepStart substep_start_from_name(const std::string& name);  ///< throws UsageError

struct TimeStepping {
  double time_step = 1e-4;       ///< h [s]; h sqrt(g/D) = 0.0099 for D = 1 mm
  double theta = 0.5;            ///< theta-method parameter, in [0.5, 1]
  double gravity = 9.81;         ///< |g| [m/s^2]
  double mu_grain = 0.5;         ///< grain-grain friction (glued floor grains included)
  double mu_wall = 0.5;          ///< grain-wall friction (floor plane and side walls)
  double alert_distance = 1e-4;  ///< contact candidates within this gap [m] (0.1 D)
  /// Contact stiffness k [N/m per metre of thickness, N/m^2] of the force-selection rule
  /// (docs/method.md, "Force selection"): the compliance 1/(k h^2) on the normal and
  /// tangential diagonal of W, anchored at the previous step's impulses. 0: rigid contacts.
  double contact_stiffness = 0.0;
  /// Damping ratio zeta of a contact dashpot beside the spring (docs/method.md, "The
  /// contact dashpot"): a viscous force -eta u on the end-of-step velocity, eta = 2 zeta
  /// sqrt(k m/2) with m the free grains' mean mass, so that zeta is the damping ratio of
  /// a contact between two grains of the mean mass (1: critical). The step's compliance
  /// becomes 1/(k h^2 + eta h) and the anchor of the next step the spring's part of the
  /// impulse alone. 0: none (the spring of (M1)-(M2) alone); needs contact_stiffness > 0.
  double contact_damping_ratio = 0.0;
  /// Adaptive sub-steps (docs/method.md, "Sub-steps"): a step whose solve has not met the
  /// criterion after `substep_after` sweeps is done again as two steps of h / 2 under the
  /// same gravity, each split again the same way, down to h / max_substeps, where the
  /// sweep cap applies. The compliance 1/(k h^2) of a sub-step is 4 times larger per
  /// halving (2 to 4 times with the dashpot's 1/(k h^2 + eta h)), so its problem is better conditioned and its warm start closer. 1: no
  /// sub-steps (a power of two).
  int max_substeps = 1;
  int substep_after = 100;  ///< sweeps before a step is split (when max_substeps > 1)
  /// The sub-steps a step starts with (docs/method.md, "Sub-steps"): `last`, the level the
  /// last step ended at, one level coarser once its sub-steps came easily (a rearrangement
  /// lasts many steps, and each failed attempt at h costs substep_after sweeps); `h`, the
  /// whole step every time, so that only the steps that do not converge at h are split and
  /// the pile is at h everywhere else.
  SubstepStart substep_start = SubstepStart::last;
};

/// The largest TimeStepping::max_substeps: h / 1024 is already 1e-7 s at the default h.
inline constexpr int max_substeps_limit = 1024;

/// Engine settings: the time stepping and the solver's (solver.hpp).
struct Settings : TimeStepping, SolverSettings {};

/// Checks a settings value range; throws cdpile::UsageError naming the bad field.
void validate(const TimeStepping& s);
void validate(const Settings& s);

/// What one step did. Energies per unit thickness [J/m].
struct StepReport {
  std::int64_t step = 0;    ///< index of the step just done (1 = first)
  double time = 0.0;        ///< time at the end of the step [s]
  double tilt_angle = 0.0;  ///< [rad]
  int sweeps = 0;           ///< NSGS sweeps done
  /// Convergence residual after the last sweep: the largest velocity correction
  /// max_a |W_aa dR_a| (max-norm over contacts and components) made by the last sweep,
  /// divided by max(g h, mean W_nn R_n over active contacts). Zero when no contact.
  double residual = 0.0;
  /// The same corrections' root mean square over the active contacts (the larger
  /// component of each), divided by the same scale: the 'quad' measure.
  double residual_rms = 0.0;
  bool converged = true;  ///< the criterion was met before the sweep cap (every sub-step)
  /// The (sub-)steps the step was done in: 1 unless it was split (TimeStepping::max_substeps).
  /// sweeps counts the sweeps of every attempt, split ones included; the residuals are the
  /// largest of the sub-steps'; the contacts and forces are those of the last sub-step.
  int substeps = 1;
  /// The (sub-)steps finished by the active-set Newton (SolverSettings::finish_after).
  int finishes = 0;
  /// The contact law's residual at the step's end (LawResidual, relative to g h):
  /// solver-independent, so steps of any solver and stopping rule compare.
  double law_residual = 0.0;
  double law_residual_rms = 0.0;
  int candidates = 0;              ///< contacts detected (within the alert distance)
  int contacts = 0;                ///< active contacts (R_n > 0), walls included
  int contacts_grain = 0;          ///< active contacts between two free grains
  int sliding = 0;                 ///< active contacts whose local solve ended on the cone
  double kinetic_energy = 0.0;     ///< translational, sum over free grains
  double rotational_energy = 0.0;  ///< sum over free grains
  double max_overlap = 0.0;        ///< largest overlap (-gap) at the predicted configuration [m]
  double max_speed = 0.0;          ///< largest grain speed |v| at the end of the step [m/s]
  /// Free grains with no active contact at the end of the step: under gravity such a grain
  /// is in flight, so a step with any is not a static state (docs/analysis.md).
  int grains_without_contact = 0;
};

/// Cumulated wall-clock time per stage [s], for benchmarks.
struct StepProfile {
  double detect = 0, frames = 0, delassus = 0, warm_start = 0, solve = 0, update_velocities = 0,
         update_positions = 0, store = 0;
  std::int64_t steps = 0, sweeps = 0, contact_updates = 0, substeps = 0;
  double total() const {
    return detect + frames + delassus + warm_start + solve + update_velocities + update_positions +
           store;
  }
};

/// One stored impulse of the previous step, for warm starting [N s/m].
struct StoredImpulse {
  std::int32_t i = 0, j = 0;  ///< the pair, as in Contacts (j < 0: a wall)
  double rn = 0.0, rt = 0.0;
};

/// The engine's restartable state besides the grains: clock and warm-start impulses.
/// An engine rebuilt from the same grains, settings and this state continues bit for bit.
struct EngineState {
  std::int64_t step = 0;
  double time = 0.0;
  std::vector<StoredImpulse> impulses;
  /// The next step starts as 2^substep_level sub-steps (docs/method.md, "Sub-steps"); 0
  /// without sub-steps.
  int substep_level = 0;
};

class Engine {
 public:
  /// Grains of Species::floor are fixed (glued); the others are free. Throws
  /// cdpile::Error on invalid grains (non-positive radius or mass, sizes differ).
  Engine(Box box, Grains grains, Settings settings);

  /// One Moreau-Jean step under gravity tilted by `tilt_angle` [rad]. Throws StepCancelled
  /// (contact_system.hpp) when the cancel predicate turns true during the solve, leaving
  /// grains() and state() as they were before the call.
  StepReport step(double tilt_angle);
  /// The predicate polled before every sweep (empty: never cancelled).
  void set_cancel(std::function<bool()> cancel) { system_.cancel = std::move(cancel); }

  const Grains& grains() const { return grains_; }
  const Box& box() const { return box_; }
  const Settings& settings() const { return settings_; }
  /// Contacts of the last step (forces = impulses / h), in (i, j) order, the open
  /// candidates included (status open, zero force).
  Contacts contacts() const;
  /// Time-independent checks of the last step's contact set.
  std::size_t contact_count() const { return system_.rows.size(); }

  /// The frictional contact problem the last step solved, in Delassus form (delassus.hpp),
  /// one contact per row of contacts() in the same order: u = W r + q with W = H M^-1 H^T
  /// (H the local frames, M the grains' masses and inertias, a glued grain or a wall
  /// contributing nothing) and q = H v_free + (max(0, gap/h), 0), the free local velocity
  /// with the gap term of the Signorini condition (method.md). Another solver can then take
  /// on exactly the problem NSGS met, from the same start or from local_impulses()
  /// (docs/performance.md, "Newton on the capped steps").
  DelassusProblem delassus_problem() const;
  /// The impulses (R_n, R_t) the last step ended with, per row of contacts() [N s/m].
  Eigen::VectorXd local_impulses() const;

  /// The team's Team::set_smallest_shared (tests: 0, so that small scenes use the threads);
  /// nothing without a team.
  void set_smallest_shared(std::size_t n) {
    if (team_) team_->set_smallest_shared(n);
  }

  /// Locks (or unlocks) a grain's rotation: infinite inertia (validation tests).
  void lock_rotation(std::size_t grain, bool locked = true);

  EngineState state() const;
  void set_state(const EngineState& s);

  const StepProfile& profile() const { return profile_; }
  void reset_profile() { profile_ = {}; }

 private:
  void detect(const Vec2& g);
  /// Throws cdpile::Error naming the first grain whose position or velocity is not finite.
  [[noreturn]] void refuse_non_finite_state() const;
  void assign_strips(double r_max);
  void compute_frames();
  void compute_delassus();
  void warm_start();
  void set_substep(double h);
  struct SubstepTally {
    int finest = 1;          // the most parts the step was split into
    int hardest_sweeps = 0;  // the most sweeps a completed (sub)step took
  };
  void advance(double hs, int parts, const Vec2& g, StepReport& report, SubstepTally& tally);
  SolveReport solve(const ContactSolver& solver);
  void check_solution() const;  // debug builds: the solver's invariants
  void update_velocities();
  void update_positions();
  void store_impulses();
  void measure(StepReport& report) const;

  Box box_;
  Grains grains_;
  Settings settings_;
  std::vector<double> inv_mass_, inv_inertia_;
  ContactSystem system_;                                // bodies and rows: what the solver works on
  std::shared_ptr<const ContactSolver> solver_;         // stateless: copies of an engine share it
  std::shared_ptr<const ContactSolver> budget_solver_;  // capped at substep_after sweeps
  std::shared_ptr<Team> team_;  // SolverSettings::threads > 1; copies of an engine share it
  double h_ = 0.0;                                      // the (sub)step being done [s]
  double stored_h_ = 0.0;                               // the (sub)step of the stored impulses [s]
  double damping_ = 0.0;       // the dashpot's eta [N s/m per metre of thickness]
  double spring_share_ = 1.0;   // of a (sub)step's impulse change, the spring's: k h / (k h + eta)
  double dashpot_share_ = 0.0;  // the dashpot's: eta / (k h + eta)
  int substep_level_ = 0;                               // EngineState::substep_level
  std::vector<Vec2> predicted_, velocity_begin_;
  std::vector<double> omega_begin_, margin_;
  ContactDetection detection_;  // stage 2's cell grid and per-thread scratch
  std::vector<std::uint64_t> stored_keys_;
  std::vector<double> stored_rn_, stored_rt_;
  // The grains and stored impulses at the start of a step split into sub-steps, kept before
  // its first sub-step changes them: a cancelled step puts them back (step)
  struct StepStart {
    Grains grains;
    std::vector<std::uint64_t> keys;
    std::vector<double> rn, rt;
    bool kept = false;
  };
  StepStart step_start_;
  std::int64_t step_ = 0;
  double time_ = 0.0;
  double last_tilt_angle_ = 0.0;
  StepProfile profile_;
};

/// Gravity in the box frame when the box is tilted by `tilt_angle` [rad]:
/// g (sin theta, -cos theta), so a positive tilt drives grains towards the right wall.
inline Vec2 tilted_gravity(double g, double tilt_angle) {
  return {g * std::sin(tilt_angle), -g * std::cos(tilt_angle)};
}

}  // namespace cdpile::cd
