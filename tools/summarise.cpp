// summarise: a run reduced to its summary, every per-run quantity critical and localnu need
// (docs/analysis.md, "Summaries"), so that a study grows run by run on any machine and the
// run files need not be kept.
#include "cdpile/analysis/run_summary.hpp"
#include "cdpile/cli/analysis_options.hpp"
#include "cdpile/cli/avalanche_options.hpp"
#include "cdpile/cli/command.hpp"
#include "cdpile/io/checkpoint.hpp"
#include "cdpile/io/products.hpp"
#include "cdpile/reading/inputs.hpp"

using namespace cdpile;

static void usage(cli::Usage& u) {
  u.synopsis = "a run reduced to its summary: what critical and localnu need of it";
  u.description = {
      "Reads one finished tilt run and writes its summary: the per-step observables and the "
      "per-frame records critical reads (pile state, static bound, motion, mobilisation), "
      "localnu's per-frame rows, sums of nu_i(r) and pdf counts of this run, localnu's default "
      "map and the maps at --map-theta, the run's own parameters (engine, protocol, seed) and "
      "its history (the commit that made it). critical and localnu read summaries in place of "
      "runs and make the same products (docs/analysis.md, \"Summaries\"); correlate and "
      "clusterfit follow unchanged. A summary is a few hundred kB where its run is tens of MB, "
      "so a study's summaries can be kept in git and a study grows run by run over machines "
      "(docs/cluster.md).",
      "The summary is made with the settings given here (the critical rule, friction, rattler "
      "rule, slip and rest speeds; localnu's radii, pdfs and map grid; the avalanche rule that "
      "ends localnu's loading phase), recorded as its reading_* parameters: critical and "
      "localnu refuse a summary made with another value than they are asked for, naming it. "
      "critical refuses an ensemble of summaries whose runs were made with other engine or "
      "protocol settings (run_* parameters, the seed apart), naming the first that differs.",
      "Output: HDF5 with -o FILE (-o - for a pipe), every bit: a summary is data for the tools, "
      "not a table for people (critical, localnu or h5dump read it)."};
  u.argument("run", "a finished tilt run (HDF5; '-' for standard input)");
  u.output("the summary (HDF5; '-' for standard output, for a pipe)");
  cli::declare_critical_rule(u, "grain-grain friction coefficient (default: the run's mu_grain)");
  u.text("rattlers", "exclude", "rattler convention of z", {"exclude", "include"});
  u.real("rest-speed", 1e-2, "a state is at rest with every grain slower than this, in sqrt(g D)",
         "", 0, 1e300);
  u.real("slip-speed", analysis::default_slip_speed,
         "a contact slips above this tangential relative velocity, in sqrt(g D)", "", 0, 1e300);
  u.group("Local state");
  u.real_list("radii", "1:1:20", "radii r of the neighbourhoods (a list, or FIRST:STEP:LAST)", "D",
              1e-6, 1e6);
  u.real("pdf-radius", 6.0, "radius of the local state of the pdfs", "D", 1e-6, 1e6);
  u.integer("pdf-bins", 50, "bins of the pdfs over [0, 1]", 1, 100000);
  cli::declare_avalanche_rule(u);
  u.real("map-radius", 6.0, "radius of the local state at the grid nodes", "D", 1e-6, 1e6);
  u.real("map-spacing", 1.0, "spacing of the grid nodes", "D", 1e-6, 1e6);
  u.real_list("map-theta", "", "keep the maps (Fig 5) of the frames nearest these tilt angles",
              "deg", -90, 90);
  u.example("A run's summary", "summarise run-1.h5 -o run-1.summary.h5",
            "then: critical run-*.summary.h5, localnu run-*.summary.h5 | correlate - ...");
  u.example("With the maps of Fig 5", "summarise run-1.h5 --map-theta 5,16 -o run-1.summary.h5",
            "localnu run-1.summary.h5 --map-theta 5 --nu-c 0.08 --table map");
}

static void run(const cli::Args& a) {
  if (a.output().empty()) throw UsageError("give -o FILE: a summary is HDF5, not a table to read");
  io::Output check(a.output(), a.force(), true);  // refuse a bad target before the work
  reading::SummaryReading opt;
  opt.rule = cli::critical_rule(a);
  opt.mu = cli::friction_choice(a);
  opt.rattlers = a.text("rattlers") == "exclude" ? analysis::RattlerRule::exclude
                                                 : analysis::RattlerRule::include;
  opt.rest_speed = a.real("rest-speed");
  opt.slip_speed = a.real("slip-speed");
  opt.avalanche = cli::avalanche_rule(a);
  opt.localnu.radii = a.real_list("radii");
  for (std::size_t k = 1; k < opt.localnu.radii.size(); ++k)
    if (!(opt.localnu.radii[k] > opt.localnu.radii[k - 1]))
      throw UsageError("--radii must be strictly increasing");
  opt.localnu.pdf_radius = a.real("pdf-radius");
  opt.localnu.pdf_bins = static_cast<std::size_t>(a.integer("pdf-bins"));
  opt.localnu.map_radius = a.real("map-radius");
  opt.localnu.map_spacing = a.real("map-spacing");
  opt.map_thetas = a.real_list("map-theta");

  io::Input in(a.argument("run"));
  const io::RunReader rr(in.hdf5());
  if (!io::partial_run_note(rr).empty())
    throw Error(in.name(), "", "a run still being computed: summarise it once it has finished");
  analysis::Product s = reading::summarise_run(in, opt);
  cli::info(in.name() + ": " + std::to_string(s.table("steps").rows()) + " steps, " +
            std::to_string(s.table("frames").rows()) + " frames, " +
            std::to_string(opt.map_thetas.size()) + " maps");
  std::vector<io::Provenance> history = rr.header().provenance;
  history.push_back(io::provenance_now(a.tool(), a.command_line(), in.name()));
  io::emit(s, history, a.output(), a.force(), io::Format::hdf5);
}

CDPILE_TOOL(usage, run)
