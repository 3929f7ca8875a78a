/// The deposition protocol (docs/method.md, "Deposit"): random non-overlapping grains in
/// a loose column just above the floor fall and settle under gravity with the engine
/// until at rest; the static pile is written as a "pile" file (docs/schema.md).
#pragma once

#include "cdpile/cd/engine.hpp"
#include "cdpile/io/schema.hpp"
#include "cdpile/model.hpp"

#include <cstdint>
#include <functional>

namespace cdpile::sim {

struct DepositOptions {
  std::int64_t grains = 4000;  ///< free grains (the glued floor layer comes on top)
  double diameter = 1e-3;      ///< mean diameter D [m]
  double ratio = 1.5;          ///< Dmax / Dmin, diameters uniform in [Dmin, Dmax]
  double width = 120.0;        ///< box width [D]
  double density = 2600.0;     ///< [kg/m^3]
  bool rough_floor = true;     ///< one layer of glued grains on the floor
  std::uint64_t seed = 1;
  cd::Settings settings;  ///< engine settings (alert distance already in m)
  /// Rest criterion: (Ek + Erot) per free grain / (m g D) below `rest_energy` and the
  /// largest grain speed below `rest_speed` sqrt(g D), both for `rest_steps` steps.
  double rest_energy = 1e-6;
  double rest_speed = 1e-2;
  std::int64_t rest_steps = 100;
  std::int64_t max_steps = 200000;  ///< cap; reaching it is reported (results/settled = 0)
};

/// Checks the options; throws cdpile::UsageError naming the bad one.
void validate(const DepositOptions& o);
/// The mean mass per unit thickness [kg/m] of the options' disks, diameters uniform in
/// [Dmin, Dmax]: the m of m g / D, the unit of the solver's --stiffness.
double mean_mass(const DepositOptions& o);

/// The initial configuration: the box, the free grains (ids 0..N-1) in rows above the
/// floor, then the glued floor grains (rough floor only). Deterministic in the seed.
struct Placement {
  Box box;
  Grains grains;
  double column_top = 0.0;  ///< highest grain top at the start [m]
};
Placement place_grains(const DepositOptions& o);

/// What the settling did, and the static pile.
struct Pile {
  Box box;
  Grains grains;
  Contacts contacts;  ///< of the last step (forces = impulses / h)
  io::Series series;  ///< the observables of every settling step
  std::int64_t steps = 0;
  double time = 0.0;
  bool settled = false;
  io::Values parameters, results;
};

/// Progress of the settling, for a terminal display: step, agitation, steps at rest.
struct DepositProgress {
  std::int64_t step = 0;
  double agitation = 0.0;
  std::int64_t quiet_steps = 0;
};

/// Places and settles the grains (docs/method.md gives the rest criterion).
/// `progress` (may be empty) is called after every step; `stop` (may be empty) is
/// polled after every step and ends the settling early (the pile is then not settled).
Pile deposit(const DepositOptions& o,
             const std::function<void(const DepositProgress&)>& progress = {},
             const std::function<bool()>& stop = {});

/// K copies of a pile side by side, for piles too large to deposit (benchmarks/tile_pile.cpp,
/// docs/performance.md "Large piles"): copy k is shifted by k box widths, and the side
/// walls between copies are removed with the contacts that touched them, so a grain that
/// leaned on such a wall now meets the next copy's grains (at most touching them: both
/// were inside their boxes). Grain ids of copy k are offset by k N. The seams are not
/// settled: run the engine on the result.
struct Tiling {
  Box box;
  Grains grains;
  Contacts contacts;
};
Tiling tile_side_by_side(const Box& box, const Grains& g, const Contacts& c, int copies);

/// Static measures of a pile (docs/method.md, "Pile measures").
struct PileMeasures {
  double bed_height = 0.0;        ///< mean over columns of width D of the highest grain top [m]
  double packing_fraction = 0.0;  ///< disk area / slab area in the bulk slab
  double slab_bottom = 0.0, slab_top = 0.0;  ///< the slab used [m]
  double z = 0.0;                            ///< coordination, grain-grain, rattlers excluded
  double z_all = 0.0;                        ///< 2 N / Np over all free grains
};
PileMeasures measure_pile(const Box& box, const Grains& g, const Contacts& c);

/// Writes a pile file: one frame (the final state and contacts), the settling
/// observables, parameters, results and the provenance.
void write_pile(io::h5::File& f, const Pile& p, const io::Provenance& prov);

}  // namespace cdpile::sim
