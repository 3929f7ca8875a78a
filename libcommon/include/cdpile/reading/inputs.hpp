/// From files to the inputs of the analysis studies (analysis/studies.hpp): a tilt run
/// (the schema of docs/schema.md) read by io and classified by analysis into a RunRecord for
/// `critical`, and a run or a plain contact table (io/contact_table.hpp) fed frame by frame
/// into a LocalNuStudy for `localnu`. This layer joins the two (docs/architecture.md): io
/// reads, analysis decides. The tools only parse options and call these; every error names
/// the file, the place in it, and the frame.
#pragma once

#include "cdpile/analysis/studies.hpp"
#include "cdpile/io/contact_table.hpp"
#include "cdpile/io/files.hpp"
#include "cdpile/io/products.hpp"
#include "cdpile/io/schema.hpp"

#include <cstdint>
#include <optional>
#include <string>

namespace cdpile::reading {

/// The rule a run recorded its per-step critical counts with: /parameters critical_eps,
/// mu_grain, mu_wall (each empty when absent).
analysis::RecordedRule recorded_rule(const io::RunHeader& header, const std::string& file);

/// mu of an analysis of a run: analysis::choose_friction on the run's recorded mu_grain and
/// mu_wall.
analysis::Friction run_friction(const io::RunHeader& header, const analysis::FrictionChoice& given,
                                const std::string& file);

/// The contacts that count in frame k of a run, classified by the rule (select_contacts).
/// The frame's grain state is read and checked too.
analysis::ContactSet frame_contact_set(const io::RunReader& rr, std::size_t k,
                                       const analysis::Friction& mu,
                                       const analysis::CriticalRule& rule, const std::string& file);

/// A run without its frames: per-step observables (steps_from_series; error if a run has
/// none), the mean diameter, mean mass, gravity and the simulator's own avalanche angle.
analysis::RunRecord read_run_steps(const io::RunReader& rr, const std::string& file,
                                   const analysis::CriticalRule& rule);

/// A run as `critical` reads it: read_run_steps and every frame read and classified by
/// `rule` and `mu`, then analysis::frame_record (the pile state, the static bound, how the
/// grains move, the slipping contacts, those at rest, the mobilisation). Every frame is
/// read whole, so a non-finite grain state is an error naming its dataset; an error of the
/// analysis names the frame. With `per_contact`, each frame record keeps its contacts'
/// states (analysis::FrameContacts, for critical --contacts).
analysis::RunRecord read_run_record(const io::RunReader& rr, const std::string& file,
                                    const analysis::Friction& mu,
                                    const analysis::CriticalRule& rule,
                                    analysis::RattlerRule rattlers,
                                    double slip_speed = analysis::default_slip_speed,
                                    double rest_speed = analysis::RestRule{}.speed,
                                    bool per_contact = false);

/// Whether an input is a run's summary (a product of kind "summary", HDF5 or TSV;
/// analysis/run_summary.hpp).
bool is_summary(const io::Input& in);

/// The summary an input holds, with its history; an error naming the file if it is
/// another kind of file.
io::ProductFile read_summary(const io::Input& in);

/// The friction of an analysis of a summary: analysis::choose_friction on the run's
/// recorded mu_grain and mu_wall, which the summary keeps.
analysis::Friction summary_run_friction(const analysis::Product& summary,
                                        const analysis::FrictionChoice& given);

/// A run as `critical` reads it, from its summary: the summary must have been made with
/// the same rule, friction, rattler rule, slip and rest speeds (analysis::require_reading),
/// else an error names the first that differs.
analysis::RunRecord read_summary_record(const analysis::Product& summary,
                                        const analysis::Friction& mu,
                                        const analysis::CriticalRule& rule,
                                        analysis::RattlerRule rattlers,
                                        double slip_speed = analysis::default_slip_speed,
                                        double rest_speed = analysis::RestRule{}.speed);

/// How `summarise` reads a run: critical's settings (the rule, friction, rattlers, slip and
/// rest speeds) and localnu's (options and reading), and the angles of the maps to keep.
struct SummaryReading {
  analysis::CriticalRule rule;
  analysis::FrictionChoice mu;
  analysis::RattlerRule rattlers = analysis::RattlerRule::exclude;
  double slip_speed = analysis::default_slip_speed;  ///< [sqrt(g D)]
  double rest_speed = analysis::RestRule{}.speed;    ///< [sqrt(g D)]
  analysis::AvalancheRule avalanche;                 ///< the end of localnu's loading phase
  analysis::LocalNuOptions localnu = analysis::default_localnu_options();
  std::vector<double> map_thetas;  ///< [deg]
};

/// A run's summary (analysis/run_summary.hpp): read_run_record of the run, the localnu
/// product of the run alone (and one per map angle), and the run's parameters. The
/// summary keeps the run's name as `in` gives it.
analysis::Product summarise_run(const io::Input& in, const SummaryReading& opt);

/// How `critical` reads its inputs: its options that enter the RunRecord.
struct CriticalReading {
  analysis::FrictionChoice mu;
  analysis::CriticalOptions options;  ///< its rule, rattlers, slip and rest speeds, series
  bool per_contact = false;           ///< keep every contact's state (critical --contacts)
};

/// One input of `critical`, read.
struct CriticalInput {
  analysis::RunRecord run;
  std::vector<io::Provenance> history;
  std::string note;      ///< a partial run's note (io::partial_run_note), else empty
  bool summary = false;  ///< read from a run's summary
};

/// Reads input `in` of `critical`: a run (or a partial one) by read_run_record, or a run's
/// summary by read_summary_record, whose engine must be `first_summary`'s (set by the first
/// summary read: analysis::require_same_engine). --series steps with another rule than the
/// run's is refused before the frames are read; `per_contact` with a summary is a
/// UsageError (a summary keeps no contacts).
CriticalInput read_critical_input(const io::Input& in, const CriticalReading& o,
                                  std::optional<analysis::Product>& first_summary);

/// How `localnu` reads its inputs.
struct LocalNuReading {
  analysis::FrictionChoice mu;
  analysis::CriticalRule rule;
  /// Mean diameter D: required for a contact table (in the table's length unit); for a
  /// run it overrides the mean diameter of the free grains.
  std::optional<double> diameter;
  /// The loading phase of a run is theta <= theta_c, theta_c by this rule (as `critical`),
  /// else the simulator's recorded avalanche angle, else every frame.
  analysis::AvalancheRule avalanche;
  /// Given: the loading phase is theta <= theta_c for every input (frames without theta
  /// count as loading).
  std::optional<double> theta_c;
  /// The frame to map (Fig 5), in input number `map_run` (0-based): the frame whose id is
  /// `map_frame`, else the one nearest `map_theta`, else the last frame of the loading phase.
  std::int64_t map_run = 0;
  std::optional<std::int64_t> map_frame;
  std::optional<double> map_theta;
  /// A contact given twice in a table: an error, or merged (counted once, with a note).
  io::Duplicates duplicates = io::Duplicates::error;
};

/// What one input contributed.
struct LocalNuInputInfo {
  std::size_t frames = 0;
  std::size_t loading_frames = 0;
  std::optional<double> theta_c;  ///< [deg] the end of the loading phase used
  std::string theta_c_from;       ///< "option", "rule", "recorded" or "none"
  std::optional<std::int64_t> mapped_frame;
  bool table = false;       ///< a contact table (not a run)
  std::string length_unit;  ///< "m" for a run; a table's declared unit, or "" (unknown)
  std::size_t merged = 0;   ///< rows of a table merged as repeats
  /// For a summary, its parameters (no tables): the engine an ensemble's summaries share
  /// (analysis::require_same_engine).
  std::optional<analysis::Product> summary;
};

/// Adds every frame of input `in` (a run file, a run's summary or a contact table) as run
/// number `run`. A summary must have been made with the reading's settings (analysis::
/// require_reading) and holds the maps of the angles it was made with only.
/// A contact table without `mu.grain` or `diameter` is a UsageError (they are required
/// options for a table).
LocalNuInputInfo add_localnu_input(analysis::LocalNuStudy& study, const io::Input& in,
                                   std::int64_t run, const LocalNuReading& opt);

}  // namespace cdpile::reading
