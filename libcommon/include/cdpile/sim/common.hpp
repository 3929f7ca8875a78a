/// What the deposition and tilt protocols share: a portable random source, the engine
/// settings as file parameters, and the per-step observables (docs/schema.md,
/// "Standard observables"; docs/method.md).
#pragma once

#include "cdpile/cd/engine.hpp"
#include "cdpile/io/schema.hpp"
#include "cdpile/model.hpp"

#include <cstdint>
#include <random>
#include <string>
#include <variant>
#include <vector>

namespace cdpile::sim {

/// Uniform doubles from std::mt19937_64, whose output sequence the C++ standard fixes.
/// std::uniform_real_distribution is not used: its algorithm differs between standard
/// libraries, so the same seed would not give the same pile everywhere. Here a double
/// is the top 53 bits of one 64-bit draw times 2^-53, exact and portable.
class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}
  /// In [0, 1).
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  /// In [a, b).
  double uniform(double a, double b) { return a + (b - a) * uniform(); }

 private:
  std::mt19937_64 engine_;
};

/// The engine settings as parameters (names with unit suffixes, docs/schema.md), from the
/// table of run parameters (tilt_options.hpp, run_parameters()), as are the three below.
io::Values settings_parameters(const cd::Settings& s);
/// The settings files made before the solver seam hold implicitly: NSGS, a convergence
/// check every sweep, rigid contacts. Such files are read, resumed and branched as today's.
io::Values pre_seam_settings();
/// `v` with every pre-seam setting it lacks added.
io::Values with_pre_seam_settings(io::Values v);
/// The engine settings a run was made with, from its parameters (the inverse of
/// settings_parameters); throws cdpile::Error naming `file` if one is missing or bad.
cd::Settings settings_from_parameters(const io::Values& v, const std::string& file);

/// Counts of critical contacts in one contact set (analysis::is_critical, tolerance
/// eps): `all` over every active contact (walls and glued floor grains included, mu_wall
/// for a wall plane, mu_grain otherwise), `grain` over active contacts between two free
/// grains. These are the observables critical and critical_grain.
struct CriticalCounts {
  std::int64_t all = 0, grain = 0;
};
CriticalCounts count_critical(const Contacts& c, const std::vector<Species>& species,
                              double mu_grain, double mu_wall, double eps);

/// One standard observable, declared once: its column, its unit and how a step's value is
/// computed from the step's report and critical counts; a real or an integer column as the
/// function returns. observables_series and append_observables derive from the table, so
/// a new observable is a row of observables() and a row of docs/schema.md's table.
struct Observable {
  using Real = double (*)(const cd::StepReport&, const CriticalCounts&);
  using Integer = std::int64_t (*)(const cd::StepReport&, const CriticalCounts&);
  std::string name;
  std::string unit;  ///< "" for none (docs/schema.md)
  std::variant<Real, Integer> value;
};
/// Every standard observable (docs/schema.md, "Standard observables").
const std::vector<Observable>& observables();

/// An empty series with every standard column and its unit.
io::Series observables_series();
/// Appends one step's row (tilt angle converted to degrees).
void append_observables(io::Series& s, const cd::StepReport& r, const CriticalCounts& c);

/// Mean translational kinetic energy per free grain divided by m g D (m the mean mass of
/// the free grains, D their mean diameter): the dimensionless agitation used by the rest
/// criterion of deposit and the avalanche rule of tilt (docs/method.md).
class Agitation {
 public:
  Agitation(const Grains& g, double gravity);
  double operator()(double kinetic_energy) const { return kinetic_energy / scale_; }
  std::int64_t free_grains() const { return free_; }
  double diameter() const { return diameter_; }

 private:
  double scale_ = 1.0, diameter_ = 0.0;
  std::int64_t free_ = 0;
};

/// The frame of the engine's current state (grains and the last step's contacts).
Frame frame_of(const cd::Engine& e, double tilt_angle);

}  // namespace cdpile::sim
