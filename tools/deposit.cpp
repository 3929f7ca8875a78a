// deposit: a static pile of disks, made by letting random grains fall and settle with the
// Contact Dynamics engine (docs/method.md, "Deposit").
#include "cdpile/sim/deposit.hpp"
#include "cdpile/cli/command.hpp"
#include "cdpile/cli/friction_options.hpp"
#include "cdpile/cli/progress.hpp"
#include "cdpile/io/files.hpp"
#include "cdpile/sim/tilt_options.hpp"

#include <cstdio>
#include <iostream>

using namespace cdpile;

static void usage(cli::Usage& u) {
  u.synopsis = "a static pile: random disks fall and settle under gravity (Contact Dynamics)";
  u.description = {
      "Places --grains disks at random without overlap in a loose column just above the floor of a "
      "box --width mean diameters wide, lets them fall and settle under gravity with the Contact "
      "Dynamics engine (Moreau-Jean, non-smooth Gauss-Seidel; docs/method.md), and writes the "
      "static "
      "pile: grains, the contacts with the forces of the last step, every parameter and the "
      "results "
      "bed height, packing fraction and coordination number. The same --seed gives the same pile, "
      "to the bit, on any platform.",
      "Diameters are uniform in [Dmin, Dmax] with Dmax/Dmin = --ratio and mean --diameter. Masses "
      "and inertias are per unit thickness (2D): m = rho pi r^2, I = m r^2 / 2. The floor is rough "
      "by default: one layer of grains drawn from the same distribution, glued to it side by side "
      "(species 1 in the file, after the free grains); --smooth-floor leaves the bare plane.",
      "At rest: for --rest-steps consecutive steps the kinetic energy (translational plus "
      "rotational) per free grain is below --rest-energy m g D and no grain moves faster than "
      "--rest-speed sqrt(g D) (m the mean mass, D the mean diameter). If --max-steps is reached "
      "first the pile is written anyway with results/settled = 0 and a warning.",
      "Parameters: grains, floor_grains, diameter_mean_m, diameter_ratio, diameter_min_m, "
      "diameter_max_m, box_width_m, box_width_D, density_kg_m3, rough_floor, seed, rest_energy, "
      "rest_speed, rest_steps, settle_max_steps, and the solver's " +
          sim::recorded_keys(sim::ParameterGroup::settings) +
          ". "
          "Results: "
          "settled, settle_steps, settle_time_s, final_agitation, unconverged_steps, bed_height_m, "
          "bed_height_D, packing_fraction (with packing_slab_bottom_m, packing_slab_top_m), "
          "coordination_number (grain-grain contacts of free grains, rattlers with fewer than 2 "
          "excluded), coordination_number_all, max_overlap_m. Every settling step's observables "
          "are recorded too (docs/schema.md)."};
  u.output("output pile file ('-' for standard output)");
  u.group("Pile");
  u.integer("grains", 4000, "number of free grains", 1, 100000000);
  u.real("diameter", 1e-3, "mean grain diameter D", "m", 1e-9, 1e3);
  u.real("ratio", 1.5, "Dmax / Dmin (diameters uniform in [Dmin, Dmax])", "", 1.0, 100.0);
  u.real("width", 120.0, "box width", "D", 1.0, 1e7);
  u.real("density", 2600.0, "grain density (2D: mass per unit thickness is rho pi r^2)", "kg/m^3",
         1e-12, 1e12);
  cli::declare_friction(u, "grain-grain friction coefficient (also with glued floor grains)",
                        "grain-wall friction coefficient (floor plane and side walls)",
                        analysis::Friction{cd::Settings{}.mu_grain, cd::Settings{}.mu_wall});
  u.real("gravity", 9.81, "gravity", "m/s^2", 1e-12, 1e6);
  u.flag("smooth-floor", "no glued grains on the floor (a bare, frictional plane)");
  u.seed("seed of the random placement and diameters (std::mt19937_64)");
  u.group("Rest criterion");
  u.real("rest-energy", 1e-6, "kinetic energy per free grain below this times m g D", "", 1e-300,
         1.0);
  u.real("rest-speed", 1e-2, "largest grain speed below this times sqrt(g D)", "", 1e-300, 1e3);
  u.integer("rest-steps", 100, "both held for this many consecutive steps", 1, 1000000000);
  u.integer("max-steps", 200000, "give up settling after this many steps (reported)", 1,
            1000000000000);
  // The engine's options are declared in their rows (sim::run_parameters()), as tilt-cd's.
  u.declare("Solver", sim::declared_options());
  u.alias("mu-grain", "mu");
  u.example("The paper's pile", "deposit --grains 4000 --seed 1 -o pile.h5",
            "4000 grains in a box 120 D wide; prints the bed height, packing fraction and z");
  u.example("A small pile straight into a tilt",
            "deposit --grains 200 -o - | tilt-cd - --to 2 -o run.h5",
            "the pile goes through a pipe");
}

static int run(const cli::Args& a) {
  sim::DepositOptions o;
  o.grains = a.integer("grains");
  o.diameter = a.real("diameter");
  o.ratio = a.real("ratio");
  o.width = a.real("width");
  o.density = a.real("density");
  o.rough_floor = !a.flag("smooth-floor");
  o.seed = a.seed();
  o.rest_energy = a.real("rest-energy");
  o.rest_speed = a.real("rest-speed");
  o.rest_steps = a.integer("rest-steps");
  o.max_steps = a.integer("max-steps");
  o.settings = sim::settings_from_options(cli::option_values(a, sim::declared_options()),
                                          {o.diameter, sim::mean_mass(o), a.real("gravity")});
  o.settings.mu_grain = a.real("mu");
  o.settings.mu_wall = a.real("mu-wall");
  o.settings.gravity = a.real("gravity");
  sim::validate(o);
  io::Output out(a.output(), a.force(),
                 true);  // refuse a bad target (a terminal too) before the work

  cli::defer_interrupts();
  cli::Progress progress(a);
  auto show = [&](const sim::DepositProgress& p) {
    if (!progress.due()) return;
    char buf[4][64];
    std::snprintf(buf[0], sizeof buf[0], "%s: step %lld", cli::tool_name().c_str(),
                  static_cast<long long>(p.step));
    std::snprintf(buf[1], sizeof buf[1], "Ek/(N m g D) %.2e", p.agitation);
    std::snprintf(buf[2], sizeof buf[2], "at rest %lld/%lld", static_cast<long long>(p.quiet_steps),
                  static_cast<long long>(o.rest_steps));
    std::snprintf(buf[3], sizeof buf[3], "%.0f steps/s",
                  progress.rate(static_cast<double>(p.step)));
    progress.show({{buf[0], 0}, {buf[1], 2}, {buf[2], 1}, {buf[3], 3}});
  };
  const sim::Pile pile = sim::deposit(o, show, [] { return cli::interrupted(); });
  cli::end_deferral();  // writing the pile: a signal from here on ends the tool at once
  progress.finish();
  if (cli::interrupted()) {  // docs/cli.md: an interrupted tool leaves no output, exit 130 or 143
    std::cerr << cli::tool_name() << ": interrupted at step " << pile.steps << "; no pile written"
              << std::endl;
    return cli::interrupt_exit_code();
  }
  const double secs = progress.seconds();
  if (!pile.settled)
    cli::warn("not at rest after " + std::to_string(pile.steps) +
              " steps (--max-steps); written with settled = 0");
  sim::write_pile(out.create_hdf5(), pile, io::provenance_now(a.tool(), a.command_line(), ""));
  out.commit();
  auto r = [&](const char* k) { return io::as_real(pile.results, k, out.name()); };
  char line[400];
  std::snprintf(line, sizeof line,
                "%lld grains %s %lld steps (%.3g s simulated, %.1f s wall): bed height %.2f D, "
                "packing fraction %.4f, z %.3f (rattlers excluded), %lld unconverged steps",
                static_cast<long long>(o.grains), pile.settled ? "settled in" : "not at rest after",
                static_cast<long long>(pile.steps), pile.time, secs, r("bed_height_D"),
                r("packing_fraction"), r("coordination_number"),
                static_cast<long long>(io::as_int(pile.results, "unconverged_steps", out.name())));
  cli::info(line);
  return 0;
}

CDPILE_TOOL(usage, run)
