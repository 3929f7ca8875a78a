// Makes a wide pile from K copies of a settled pile side by side, for the probes of large
// piles (docs/performance.md, "Large piles"): depositing 64 000 grains costs hours of CPU,
// while K copies of the paper's 4000-grain pile only need the grains along the K - 1
// seams to settle. The copies keep the depth of the original (about 34 D for the paper's
// pile), so the cost per step compares with the deposited piles of bench_engine, which
// also grow in width only.
//
// Copy k is shifted by k times the box width; the side walls between copies are removed
// (the contacts with them are dropped from the warm start), so the grains that leaned on
// them now lean on the next copy's grains, which touch them at most (both were inside
// their boxes: no overlap). The tiled pile then settles at zero tilt with the engine and
// the rest criterion of the original deposit (its rest_energy, rest_speed and rest_steps
// parameters), at most MAX_STEPS steps, and is written as a pile file: the original's
// parameters with grains, floor_grains and box_width_{m,D} of the tiled pile plus
// tiled_copies; results as deposit measures them (settle_steps counts the settling of
// the seams only).
//
// A tiled pile measures cost, not strength: tilted, 4 copies of the paper's pile gave way
// first along their seams and avalanched at 9.7 degrees against the single pile's 15.05
// (docs/performance.md, "Threads"), so its theta_c is not a wide deposit's.
//
// Usage: tile_pile PILE K MAX_STEPS OUTPUT
#include "cdpile/cd/engine.hpp"
#include "cdpile/error.hpp"
#include "cdpile/io/files.hpp"
#include "cdpile/io/h5.hpp"
#include "cdpile/sim/common.hpp"
#include "cdpile/sim/deposit.hpp"
#include "cdpile/sim/tilt.hpp"

#include <cmath>
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>
#include <utility>

namespace cd = cdpile::cd;
namespace io = cdpile::io;
namespace sim = cdpile::sim;
using cdpile::Contacts;

int main(int argc, char** argv) {
  if (argc != 5) {
    std::cerr << "usage: tile_pile PILE K MAX_STEPS OUTPUT\n";
    return 2;
  }
  const std::string input = argv[1], output = argv[4];
  try {
    const int k_copies = std::stoi(argv[2]);
    const long max_steps = std::stol(argv[3]);
    if (k_copies < 1 || max_steps < 0)
      throw cdpile::UsageError("K must be >= 1 and MAX_STEPS >= 0");
    io::Output out(output, false);  // refuses an existing file before any work

    sim::PileInput pile;
    {
      io::Input in(input);
      pile = sim::read_pile(in.hdf5());
    }
    const cd::Settings settings = sim::settings_from_parameters(pile.parameters, input);
    sim::Tiling tiling = sim::tile_side_by_side(pile.box, pile.grains, pile.contacts, k_copies);
    sim::Pile tiled;
    tiled.box = tiling.box;
    tiled.grains = std::move(tiling.grains);
    const Contacts warm = std::move(tiling.contacts);

    cd::Engine engine(tiled.box, tiled.grains, settings);
    engine.set_state(sim::warm_start_state(warm, settings.time_step));
    const sim::Agitation agitation(tiled.grains, settings.gravity);
    const double rest_energy = io::as_real(pile.parameters, "rest_energy", input);
    const double rest_speed = io::as_real(pile.parameters, "rest_speed", input) *
                              std::sqrt(settings.gravity * agitation.diameter());
    const std::int64_t rest_steps = io::as_int(pile.parameters, "rest_steps", input);
    tiled.series = sim::observables_series();
    std::int64_t quiet = 0, unconverged = 0;
    double a = 0.0, overlap = 0.0;
    for (long k = 1; k <= max_steps && quiet < rest_steps; ++k) {
      const cd::StepReport r = engine.step(0.0);
      const Contacts c = engine.contacts();
      sim::append_observables(
          tiled.series, r,
          sim::count_critical(c, tiled.grains.species, settings.mu_grain, settings.mu_wall, 1e-3));
      unconverged += r.converged ? 0 : 1;
      overlap = std::max(overlap, r.max_overlap);
      a = agitation(r.kinetic_energy + r.rotational_energy);
      quiet = (a < rest_energy && r.max_speed < rest_speed) ? quiet + 1 : 0;
      tiled.steps = r.step;
      tiled.time = r.time;
    }
    tiled.settled = quiet >= rest_steps;
    tiled.grains = engine.grains();
    tiled.contacts = engine.contacts();

    tiled.parameters = pile.parameters;
    const std::int64_t floor = io::as_int(pile.parameters, "floor_grains", input);
    tiled.parameters["grains"] = k_copies * io::as_int(pile.parameters, "grains", input);
    tiled.parameters["floor_grains"] = k_copies * floor;
    tiled.parameters["box_width_m"] = tiled.box.width;
    tiled.parameters["box_width_D"] = k_copies * io::as_real(pile.parameters, "box_width_D", input);
    tiled.parameters["tiled_copies"] = std::int64_t{k_copies};
    const sim::PileMeasures m = sim::measure_pile(tiled.box, tiled.grains, tiled.contacts);
    tiled.results = {{"settled", std::int64_t{tiled.settled ? 1 : 0}},
                     {"settle_steps", tiled.steps},
                     {"settle_time_s", tiled.time},
                     {"final_agitation", a},
                     {"unconverged_steps", unconverged},
                     {"bed_height_m", m.bed_height},
                     {"bed_height_D", m.bed_height / agitation.diameter()},
                     {"packing_fraction", m.packing_fraction},
                     {"coordination_number", m.z},
                     {"coordination_number_all", m.z_all},
                     {"max_overlap_m", overlap}};
    std::string command_line;
    for (int i = 0; i < argc; ++i) command_line += (i ? " " : "") + std::string(argv[i]);
    sim::write_pile(out.create_hdf5(), tiled, io::provenance_now("tile_pile", command_line, input));
    out.commit();
    std::printf(
        "%s: %zu grains, %d copies, settled %s after %lld steps (%lld at the sweep cap), "
        "phi %.4f, z %.3f, largest overlap %.2e m\n",
        output.c_str(), tiled.grains.size(), k_copies, tiled.settled ? "yes" : "NO",
        static_cast<long long>(tiled.steps), static_cast<long long>(unconverged),
        m.packing_fraction, m.z, overlap);
  } catch (const std::exception& e) {
    std::cerr << "tile_pile: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
