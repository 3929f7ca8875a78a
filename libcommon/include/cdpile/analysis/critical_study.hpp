/// critical: nu(theta), events, ensemble, envelope, nu_c and the avalanche angle of an
/// ensemble of runs (eqs 1-2, Figs 1-2), from their records (run_record.hpp) to a Product.
/// Definitions and defaults: docs/analysis.md.
#pragma once

#include "cdpile/analysis/run_record.hpp"

#include <optional>
#include <string>
#include <vector>

namespace cdpile::analysis {

/// Which nu(theta) series the ensemble mean, the envelope and the events use.
enum class SeriesSource {
  automatic,  ///< `steps` when every run records a per-step critical count by the rule asked
              ///< for (step_rule_mismatch), else `frames`
  steps,      ///< per-step critical count from the observables (column critical_grain/critical)
  frames,     ///< the frames' contacts with the eps rule (exact definition, sparser)
  sliding,    ///< per-step count of contacts the solver reports sliding
};
const char* source_name(SeriesSource s);

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

/// The product of critical --contacts: one table `contacts`, a row per counted contact of
/// every frame of `runs` read with per_contact (run, frame, theta, i, j, critical, sliding,
/// slip), with the rule and the slip speed of `opt` as parameters.
Product critical_contacts(const std::vector<RunRecord>& runs, const CriticalOptions& opt);

Product critical_study(const std::vector<RunRecord>& runs, const CriticalOptions& opt);

/// One line for people: theta_c and each reading of nu_c the product determines, at the
/// tables' precision (6 significant digits), and the readings it does not ("theta_c = 17.4
/// deg; nu_c = 0.206392 +- 0.00771836 (every state), nu_c_static = ...; nu_c_rest not
/// determined"). The results are the file's: a reading is determined exactly when the
/// product holds it.
std::string critical_readings(const Product& p);

/// The tables critical_study makes with these options, in order (so that a tool can refuse
/// an unknown --table before it reads anything).
std::vector<std::string> critical_table_names(const CriticalOptions& opt);

}  // namespace cdpile::analysis
