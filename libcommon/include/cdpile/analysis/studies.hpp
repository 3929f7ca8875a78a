/// The four analyses behind the tools critical, localnu, correlate and clusterfit, from
/// plain data to a Product (tables + results). The tools only read files, fill these
/// inputs and write the product; everything here is testable without files.
/// Definitions and defaults: docs/analysis.md.
#pragma once

#include "cdpile/analysis/critical.hpp"
#include "cdpile/analysis/local_state.hpp"
#include "cdpile/analysis/series.hpp"
#include "cdpile/analysis/table.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <utility>
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

// =================================================================================
// critical: nu(theta), events, ensemble, envelope, avalanche angle (eqs 1-2, Figs 1-2)

/// Which nu(theta) series the ensemble mean, the envelope and the events use.
enum class SeriesSource {
  automatic,  ///< `steps` when every run records a per-step critical count by the rule asked
              ///< for (step_rule_mismatch), else `frames`
  steps,      ///< per-step critical count from the observables (column critical_grain/critical)
  frames,     ///< the frames' contacts with the eps rule (exact definition, sparser)
  sliding,    ///< per-step count of contacts the solver reports sliding
};
const char* source_name(SeriesSource s);

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

struct CriticalOptions {
  CriticalRule rule;
  RestRule rest;
  double slip_speed = default_slip_speed;  ///< [sqrt(g D)]
  double mobilisation_window = 2.0;        ///< [deg] windows of the mobilisation table
  RattlerRule rattlers = RattlerRule::exclude;
  EventRule events;
  AvalancheRule avalanche;
  bool cut_at_avalanche = true;            ///< ensemble and envelope use each run up to its theta_c
  double grid_step = 0.1;                  ///< [deg] bins of the ensemble mean
  double envelope_window = 0.5;            ///< [deg] windows of the envelope of maxima
  std::optional<ThetaRange> envelope_fit;  ///< default: windows where every run contributes
  SeriesSource source = SeriesSource::automatic;
  bool step_table = true;  ///< include the per-step table
};

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

/// How a recorded per-step count departs from the rule asked for.
struct StepRuleMismatch {
  bool unknown = false;  ///< the run does not record its rule (e.g. no critical_eps)
  std::string why;       ///< one line: "eps 0.2 asked, 0.001 recorded"
};

/// Whether a per-step count recorded with `rec` counts what `rule` with friction `mu`
/// asks for: empty when it does. The simulator's critical_grain counts the contacts between
/// two free grains at the Coulomb threshold with (critical_eps, mu_grain); its critical
/// (read with walls) all contacts, mu_wall against a wall plane. So without walls,
/// --floor-grains grain departs from it too.
std::optional<StepRuleMismatch> step_rule_mismatch(const RecordedRule& rec,
                                                   const CriticalRule& rule, const Friction& mu);

/// For an explicit --series steps, before the run is read: a UsageError when run `name`
/// recorded its per-step count with another rule. (A run that records a count but not its
/// rule is a data error of critical_study: the run is read by then.)
void require_step_rule(const std::string& name, const RecordedRule& rec, const CriticalRule& rule,
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

/// The product of critical --contacts: one table `contacts`, a row per counted contact of
/// every frame of `runs` read with per_contact (run, frame, theta, i, j, critical, sliding,
/// slip), with the rule and the slip speed of `opt` as parameters.
Product critical_contacts(const std::vector<RunRecord>& runs, const CriticalOptions& opt);

Product critical_study(const std::vector<RunRecord>& runs, const CriticalOptions& opt);

/// Notes of a product that are warnings start with this; a tool also says them on stderr.
inline constexpr const char* warning_prefix = "warning: ";

/// The warnings among a product's notes, without the prefix.
std::vector<std::string> product_warnings(const Product& p);

/// One line for people: theta_c and each reading of nu_c the product determines, at the
/// tables' precision (6 significant digits), and the readings it does not ("theta_c = 17.4
/// deg; nu_c = 0.206392 +- 0.00771836 (every state), nu_c_static = ...; nu_c_rest not
/// determined"). The results are the file's: a reading is determined exactly when the
/// product holds it.
std::string critical_readings(const Product& p);

/// The tables critical_study makes with these options, in order (so that a tool can refuse
/// an unknown --table before it reads anything).
std::vector<std::string> critical_table_names(const CriticalOptions& opt);

/// theta_c of a run by the rule [deg]: empty when the run never passes it, or when its
/// kinetic energy, gravity, grain mass or diameter is unknown.
std::optional<double> avalanche_angle(const RunRecord& r, const AvalancheRule& rule);

// =================================================================================
// localnu: nu_i(r) around every contact, pdfs P_c, P_nc, the nu field (Figs 3, 5)

struct LocalNuOptions {
  std::vector<double> radii;  ///< [D], ascending; default 1..20
  bool exclude_self = false;
  EdgeRule edge = EdgeRule::keep;
  double pdf_radius = 6.0;  ///< [D]
  std::size_t pdf_bins = 50;
  std::optional<ThetaRange> pdf_theta;  ///< default: the loading phase of each run
  double map_radius = 6.0;              ///< [D]
  double map_spacing = 1.0;             ///< [D]
  double nu_c = 0.08;                   ///< threshold of the map (Fig 5)
  bool per_contact = false;             ///< table of nu_i(r) of every contact of the map frame
};

LocalNuOptions default_localnu_options();

class LocalNuStudy {
 public:
  explicit LocalNuStudy(LocalNuOptions opt);
  /// Adds one frame: its contacts that count (from select_contacts), the run's mean
  /// diameter D [m], whether it is in the loading phase (pdf pooling by default) and
  /// whether it is the frame to map. Returns the frame's local states (for callers that
  /// want more).
  void add_frame(std::int64_t run, const std::string& run_name, std::int64_t frame,
                 std::int64_t step, std::optional<double> theta, double diameter,
                 const ContactSet& set, bool loading, bool map_this);
  /// The length unit of the inputs' coordinates and diameters ("m" for runs; a contact
  /// table's declared unit; "" when unknown or when the inputs differ): columns get it as
  /// their unit ("?" when unknown), and the map's results are named with the `_m` suffix
  /// only in metres (else without a suffix, beside the parameter `length_unit`).
  void set_length_unit(const std::string& unit) { length_unit_ = unit; }
  /// A note added to the product (e.g. duplicate rows merged in an input).
  void add_note(const std::string& note) { extra_notes_.push_back(note); }
  /// Adds run number `run` from its summary (analysis/run_summary.hpp): its frames' rows,
  /// its sums and its pdf counts, as add_frame added them when the summary was made with
  /// these options (the caller checks that: require_reading).
  void add_summary(std::int64_t run, const Product& summary);
  /// The map (table `map` and its map_* values, from a summary) of input `run`, thresholded
  /// at the options' nu_c: what add_frame makes of the frame to map.
  void set_map(std::int64_t run, Table map, Values info);
  const LocalNuOptions& options() const { return opt_; }
  Product product() const;
  std::size_t frames() const { return frames_; }

 private:
  LocalNuOptions opt_;
  std::string length_unit_ = "m";
  std::vector<std::string> extra_notes_;
  std::vector<double> query_;       // radii of the query [D]: radii + pdf radius, sorted
  std::vector<std::size_t> out_k_;  // index in query_ of each output radius
  std::size_t pdf_k_ = 0;
  std::size_t frames_ = 0;
  Table frames_t_, states_t_, contacts_t_, map_t_;
  Histogram pc_, pnc_;
  std::int64_t pdf_frames_ = 0;
  bool mapped_ = false;
  Values map_info_;
};

// =================================================================================
// correlate: nu_bar(theta, r) per frame and pooled in theta windows (eq 3, Fig 4)

struct CorrelateOptions {
  double window = 1.0;        ///< [deg]
  double window_start = 0.0;  ///< [deg] windows are [start + k w, start + (k+1) w)
  ThetaRange theta;           ///< frames used
  bool frame_table = true;
};

Product correlate(const Product& localnu, const CorrelateOptions& opt);

// =================================================================================
// clusterfit: eq (4) per theta window, affine A(theta), alpha(theta), r_c (eq 5), and
// the divergence r_c ~ (theta_c - theta)^-beta (Fig 6)

enum class NuInfSource {
  automatic,  ///< `ensemble` when a critical product is given, else `pile`
  ensemble,   ///< critical's ensemble mean nu(theta) over the window (the paper's definition)
  pile,       ///< the mean pile nu of the window's frames (from correlate)
  fit,        ///< a free parameter of the fit
};
const char* nu_inf_name(NuInfSource s);

enum class RcFrom { window, affine };

struct ClusterFitOptions {
  double r_min = 1.0;   ///< [D]
  double r_max = 10.0;  ///< L [D]
  NuInfSource nu_inf = NuInfSource::automatic;
  std::optional<double> nu_c;        ///< overrides the critical product's nu_c
  double nu_c_se = 0.0;              ///< its standard error, with nu_c given
  ThetaRange theta;                  ///< windows fitted
  std::optional<ThetaRange> affine;  ///< default: every fitted window
  ThetaRange power{15.0, std::numeric_limits<double>::infinity()};  ///< windows of the power law
  std::optional<double> theta_c;                                    ///< given: not fitted
  RcFrom rc_from = RcFrom::window;
  int min_points = 4;  ///< radii needed to fit a window
};

Product clusterfit(const Product& correlate, const Product* critical, const ClusterFitOptions& opt);

}  // namespace cdpile::analysis
