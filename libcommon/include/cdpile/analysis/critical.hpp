/// Critical contacts and the state of the pile (Staron, Vilotte & Radjai 2002, eqs 1-2).
///
/// A contact is *active* when f_n > 0. It is *critical* when the friction is fully
/// mobilised to a tolerance eps:
///
///     f_n > 0  and  |f_t| >= (1 - eps) mu f_n                                   (Coulomb
///     threshold)
///
/// nu = Nc / N over the contacts that count (eq 1 with V the whole pile),
/// z = 2 N / Np (coordination number, with a stated rattler convention) and
/// lambda = sqrt(2 / (z nu)) D, the mean distance between critical contacts (eq 2).
///
/// Which contacts count: active grain-grain contacts. A wall contact is one whose second
/// body is a wall plane (j < 0) or, when `floor_grains_are_walls`, a grain glued to the
/// floor (Species::floor); wall contacts count only with `include_walls`.
///
/// These kernels take plain arrays or the model types, never files: contact data from
/// another code (io/contact_table.hpp) goes through the same code as our runs.
#pragma once

#include "cdpile/model.hpp"

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace cdpile::analysis {

/// The default tolerance eps of the critical test. The NSGS local solver puts a sliding
/// contact on the cone to round-off, while a sticking contact can sit inside it by up to
/// about the solver tolerance (1e-4 relative); 1e-3 is ten times that, so sliding
/// contacts are always critical and sticking ones only when within 0.1 % of the cone.
inline constexpr double default_eps = 1e-3;

/// The choices that say which contacts count and which are critical.
struct CriticalRule {
  double eps = default_eps;            ///< tolerance of the Coulomb test, in [0, 1)
  bool include_walls = false;          ///< count contacts with walls (and glued floor grains)
  bool floor_grains_are_walls = true;  ///< a contact with a glued floor grain is a wall contact
};

/// Friction coefficients: grain-grain (also used with glued floor grains) and grain-wall.
struct Friction {
  double grain = 0.5;
  double wall = 0.5;
};

/// Whether a contact with forces (fn, ft) and friction mu is critical (Coulomb threshold
/// to the tolerance eps). False when fn <= 0 (not active).
inline bool is_critical(double fn, double ft, double mu, double eps) {
  return fn > 0.0 && (ft < 0.0 ? -ft : ft) >= (1.0 - eps) * mu * fn;
}

/// Checks a rule and friction coefficients; throws cdpile::Error with a one-line reason
/// (mu <= 0 or not finite, eps outside [0, 1)).
void validate(const CriticalRule& rule, const Friction& mu);

/// The contacts of one instant that count, in the order of the source table.
struct ContactSet {
  std::vector<std::size_t> row;        ///< row in the source Contacts table
  std::vector<std::int32_t> i, j;      ///< bodies (j < 0: wall)
  std::vector<Vec2> point;             ///< contact points [m]
  std::vector<std::uint8_t> critical;  ///< 1 if critical by the rule
  std::vector<std::uint8_t> sliding;   ///< 1 if the solver's status is `slide`
  std::vector<double> mobilisation;    ///< |f_t| / (mu f_n), in [0, 1] up to round-off
  /// The source gave a solver status (a run, or a contact table with a `status` column);
  /// without one, `sliding` is all 0 and means "unknown", not "none slides".
  bool has_status = true;

  std::size_t size() const { return point.size(); }
  std::size_t critical_count() const;
  std::size_t sliding_count() const;
};

/// Selects the contacts that count and classifies them. `species` may be empty (no glued
/// grains, e.g. a contact table). Throws cdpile::Error if a force is not finite or the
/// rule is invalid.
ContactSet select_contacts(const Contacts& c, std::span<const Species> species, const Friction& mu,
                           const CriticalRule& rule);

/// How the coordination number treats rattlers (grains that carry no load).
enum class RattlerRule {
  exclude,  ///< z = 2 N / Np', Np' = free grains with >= 2 counted contacts (default)
  include,  ///< z = 2 N / Np, Np = all free grains
};

/// The state of the whole pile at one instant. Undefined quantities are empty optionals
/// (nu when N = 0; lambda when Nc = 0, where it is infinite; z when Np = 0).
struct PileState {
  std::int64_t contacts = 0;         ///< N, counted active contacts
  std::int64_t critical = 0;         ///< Nc
  std::int64_t sliding = 0;          ///< solver status `slide` among the counted contacts
  std::int64_t grains = 0;           ///< Np, free grains
  std::int64_t loaded_grains = 0;    ///< free grains with >= 2 counted contacts
  std::optional<double> nu;          ///< Nc / N (eq 1)
  std::optional<double> nu_sliding;  ///< sliding / N, the solver's own view
  std::optional<double> z;           ///< by the chosen rattler rule
  std::optional<double> z_all;       ///< 2 N / Np, rattlers included
  std::optional<double> lambda;      ///< sqrt(2 / (z nu)) D [m] (eq 2), z by the rule
};

/// Computes the pile state of a selected contact set. `free_grains` is the number of
/// free (not glued) grains, `diameter` the mean diameter D [m]; grain ids in the set are
/// used to find rattlers (ids >= grain_count or < 0 are ignored for that).
PileState pile_state(const ContactSet& set, std::span<const Species> species,
                     std::int64_t free_grains, double diameter, RattlerRule rattlers);

/// The static bound on critical contacts (McNamara & Herrmann 2004, PRE 70, 061303;
/// docs/analysis.md, "Static bound"). The admissible forces of a static packing of rigid
/// frictional disks form a convex set; when it is a single point, each of the 2M force
/// unknowns is fixed by one of the 3N equilibrium equations or by a contact held at the
/// Coulomb threshold, so a static packing has at most
///
///     Nc <= B = 2M - 3N
///
/// critical contacts. M and N are over the load-bearing part of the pile: a free grain bears
/// load when it has >= 2 active contacts, found by removing grains with fewer repeatedly
/// (removing a rattler removes its contacts, which can make a neighbour one). Walls and
/// grains glued to the floor are fixed bodies: no unknowns of their own, but their active
/// contacts with load-bearing grains count in M. A frame with Nc > B is not a static state:
/// the pile is moving there, or its forces are unconverged.
struct StaticBound {
  std::int64_t contacts = 0;  ///< M, active contacts of load-bearing grains (walls included)
  std::int64_t grains = 0;    ///< N, load-bearing free grains
  std::int64_t critical = 0;  ///< Nc, critical contacts among the M
  std::int64_t bound() const { return 2 * contacts - 3 * grains; }  ///< B = 2M - 3N
  bool above() const { return critical > bound(); }                 ///< Nc > B: not static
};

/// The static bound of one instant. Every active contact is considered, whatever rule
/// says about walls (a wall's reaction is an unknown of the grain's equilibrium); critical
/// by is_critical with `eps`, mu_wall against a wall plane and mu_grain otherwise (glued
/// grains too, as select_contacts). `species` may be empty (every grain free). Throws
/// cdpile::Error if a force is not finite, or mu or eps is invalid.
StaticBound static_bound(const Contacts& c, std::span<const Species> species, const Friction& mu,
                         double eps);

/// How a frame's grains move (docs/analysis.md, "Static and moving states"): the mean
/// (translational + rotational) kinetic energy per free grain [J/m], the largest speed of a
/// free grain [m/s] (both empty without velocities), and the free grains without an active
/// contact (walls and glued grains count as contacts): under gravity, grains in flight.
/// It also counts the paper's coordination ("the mean number of contacts of a particle"):
/// the active contacts of every free grain, with grains, glued grains and walls, summed over
/// the free grains and divided by their number, rattlers included.
struct FrameMotion {
  std::optional<double> agitation, max_speed;
  std::int64_t grains_without_contact = 0;
  std::optional<double> contacts_per_grain;  ///< z as the paper reads it; empty without free grains
};
FrameMotion frame_motion(const Grains& g, const Contacts& c);

/// The tangential relative velocity |u_t| [m/s] at each contact of `set` (rows of `c`):
/// u = (v_i + w_i x r_i) - (v_j + w_j x r_j) at the contact point, r from each centre, a
/// wall at rest; u_t its part normal to the contact normal. Zero for every contact when the
/// grains carry no velocities.
std::vector<double> slip_speeds(const Contacts& c, const ContactSet& set, const Grains& g);

/// The contacts of `set` at rest and the critical ones among them: both bodies slower than
/// `rest_speed` [m/s] (a wall is at rest) and the contact not slipping, |u_t| <= `slip_speed`
/// [m/s] (`u_t` from slip_speeds). Two slow grains can still slide on each other at up to
/// twice the rest speed, far above the slip speed: such a contact is motion, not a contact
/// at rest, and is left out (docs/analysis.md, "Static and moving states").
struct RestCount {
  std::int64_t contacts = 0, critical = 0;
};
RestCount contacts_at_rest(const Contacts& c, const ContactSet& set, const Grains& g,
                           const std::vector<double>& u_t, double rest_speed, double slip_speed);

/// Counts of the contacts of `set` per bin of the mobilisation |f_t| / (mu f_n) on [0, 1]
/// in `bins` equal bins (a value at or above 1, a critical sliding contact, goes in the last).
std::vector<std::int64_t> mobilisation_histogram(const ContactSet& set, std::size_t bins);

/// lambda = sqrt(2 / (z nu)) D (eq 2); empty if z nu <= 0.
std::optional<double> critical_spacing(double z, double nu, double diameter);

/// The mean diameter D of the free grains (all grains if none is marked free) [m].
double mean_diameter(const Grains& g);
/// The mean mass of the free grains [kg/m].
double mean_mass(const Grains& g);
/// Number of free (not glued) grains.
std::int64_t free_grain_count(const Grains& g);
/// Ek: the mean translational kinetic energy per free grain, sum of m v^2 / 2 over the free
/// grains / their number [J/m]. Empty without free grains or without velocities.
std::optional<double> mean_kinetic_energy(const Grains& g);

}  // namespace cdpile::analysis
