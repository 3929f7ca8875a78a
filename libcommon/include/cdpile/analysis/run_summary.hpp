/// A run's summary (docs/analysis.md, "Summaries"): every per-run quantity the ensemble
/// products need, so that critical, localnu and after them correlate and clusterfit make
/// from summaries the products they make from the runs, and a study grows run by run on
/// any machine (docs/cluster.md). A summary is a Product of kind "summary":
///
///   tables   steps            the RunRecord's per-step observables (critical)
///            frames           its FrameRecords: pile state, static bound, motion, mobilisation
///            localnu_frames   localnu's per-frame rows of this run (table frames)
///            localnu_states   its per-frame sums of nu_i(r) over critical contacts (states)
///            localnu_pdf      its pdf counts (count_c, count_nc per bin)
///            localnu_map      the map localnu makes of this run by default (last loading frame)
///            map1, map2, ...  the maps at the tilt angles asked for (Fig 5)
///   parameters  reading_*     the settings the per-run quantities were computed with
///               run_*         the run's own /parameters (engine, protocol, seed)
///               run_name      the run's file name as given
///   results  the run's scalars (free grains, D, mass, g, recorded avalanche and rule),
///            localnu's counts and the maps' geometry (map1_*, ...)
///
/// A reading with other settings than the summary's is refused with the difference named
/// (require_reading), and so is an ensemble of summaries whose runs were made by other
/// engine settings (engine_difference).
#pragma once

#include "cdpile/analysis/studies.hpp"

#include <optional>
#include <string>
#include <vector>

namespace cdpile::analysis {

inline constexpr const char* summary_kind = "summary";

/// The version of what a summary holds and how it was computed (frame_record, the local
/// states, the tables' columns): raised with any change that would make a run give other
/// numbers than its summary, so that a summary made before is refused, not replayed
/// (reading_definitions).
inline constexpr std::int64_t summary_definitions = 1;

/// The settings critical reads a run's frames with: they enter every FrameRecord.
Values critical_reading(const CriticalRule& rule, const Friction& mu, RattlerRule rattlers,
                        double slip_speed, double rest_speed);

/// The settings localnu reads a run with: the local states, the pdfs' loading phase, the
/// map grid. `theta_c` given ends every loading phase there; else `avalanche` decides.
Values localnu_reading(const LocalNuOptions& opt, const CriticalRule& rule, const Friction& mu,
                       const AvalancheRule& avalanche, std::optional<double> theta_c,
                       std::optional<double> diameter);

/// The friction a summary's frames were read with (its reading_mu_grain, reading_mu_wall).
Friction summary_friction(const Product& summary);

/// Throws cdpile::Error naming the summary and the first setting of `asked` that differs
/// from the one it was made with, as the option it stands for (reading_eps: --eps): "S:
/// /parameters: made with --eps 0.001, asked 0.01: ...".
void require_reading(const Product& summary, const Values& asked);

/// The first engine or protocol setting (run_* parameter, the seed apart) in which summary
/// `b` differs from `a`, as "run_contact_stiffness_N_m2 1e6 in A, 1e7 in B"; empty if none.
std::optional<std::string> engine_difference(const Product& a, const Product& b);

/// One run's summary: `run`'s steps and frames (read with `critical`), the localnu
/// product `localnu` of this run alone (input 0, read with `localnu_settings`), the maps
/// `maps` (each a localnu product of this run mapped at `map_thetas[k]`), and the run's
/// own parameters `run_parameters`.
Product make_summary(const RunRecord& run, const Values& critical, const Product& localnu,
                     const Values& localnu_settings, const std::vector<double>& map_thetas,
                     const std::vector<Product>& maps, const Values& run_parameters);

/// The RunRecord a summary holds, as read_run_record read it (no per-contact states).
RunRecord summary_run_record(const Product& summary);

/// Throws cdpile::Error naming `name` when summary `s` was made by other engine or
/// protocol settings than `first` (engine_difference).
void require_same_engine(const Product& first, const Product& s, const std::string& name);

/// The map stored for `theta` [deg] (one of the angles the summary was made with), as
/// localnu's table `map` and its map_* results; empty if the summary has none there.
/// `theta` empty: localnu's default map (the last frame of the loading phase).
std::optional<std::pair<Table, Values>> summary_map(const Product& summary,
                                                    std::optional<double> theta);

}  // namespace cdpile::analysis
