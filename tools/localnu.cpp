// localnu: the local state nu_i(r) around every contact (eq 1 of Staron, Vilotte & Radjai
// 2002 on a disk of radius r), its sums over critical contacts per frame (for eq 3), the
// pdfs P_c and P_nc of nu_i(6D) (Fig 3) and the nu field on a grid (Fig 5).
#include "cdpile/analysis/run_summary.hpp"
#include "cdpile/analysis/studies.hpp"
#include "cdpile/cli/analysis_options.hpp"
#include "cdpile/cli/avalanche_options.hpp"
#include "cdpile/cli/command.hpp"
#include "cdpile/io/products.hpp"
#include "cdpile/reading/inputs.hpp"

#include <algorithm>
#include <optional>

using namespace cdpile;

static void usage(cli::Usage& u) {
  u.synopsis = "local state nu_i(r) around every contact; pdfs P_c, P_nc; the nu field map";
  u.description = {
      "Reads tilt runs (HDF5, docs/schema.md) or plain contact tables (TSV/CSV with a header: "
      "x, y, fn, ft, optional i, j, wall, frame, theta, status, other columns ignored; "
      "docs/analysis.md, 'Contact table'; from-lammps writes one from LAMMPS or LIGGGHTS dumps), "
      "each input one run of the ensemble, and writes the localnu product that correlate reads. "
      "A run's summary (summarise) stands for its run and gives the same product: its frames, "
      "sums and pdf counts as they were made, and of maps those it keeps (its default and "
      "its --map-theta angles); it is refused when made with other settings than asked for "
      "(docs/analysis.md, 'Summaries'). "
      "A contact given twice in a table's frame is an error naming both lines (--duplicates "
      "merge counts it once). Lengths are in m for runs; for a table in the unit its '# "
      "length_unit:' line declares, else unknown (labelled '?', the map's results without their "
      "_m suffix). Without a status column the per-contact 'sliding' is NA.",
      "Local state (eq 1 on a disk V of radius r centred on contact i's point): nu_i(r) = "
      "(critical contacts whose contact point lies within r of i's point) / (contacts within r), "
      "'within' meaning distance <= r, contact i itself included unless --exclude-self. r is in "
      "units of the mean diameter D of the run's free grains (--diameter for a table, in the "
      "table's length unit). Neighbours come from one CGAL Kd_tree query of the largest radius "
      "per contact, which gives every radius at once.",
      "Critical: f_n > 0 and |f_t| >= (1 - eps) mu f_n, as in critical (default eps 1e-3, ten "
      "times the solver's relative tolerance). Only contacts that count are centres and "
      "neighbours: active (f_n > 0) grain-grain contacts, wall contacts with --walls. mu is the "
      "run's mu_grain (mu_wall for walls) unless --mu is given; a contact table needs --mu.",
      "Edge rule (--edge): 'keep' takes the part of the disk inside the pile as the "
      "neighbourhood; 'exclude' leaves nu_i(r) undefined when r exceeds the distance from i to "
      "the pile outline (the contact points' bounding box sides and a free surface made of the "
      "highest contact point in columns 1 D wide).",
      "Per frame and radius (table states): n = critical contacts with a defined nu_i(r), the "
      "sum and sum of squares of their nu_i(r), nu_bar = sum/n (eq 3) and se = sd/sqrt(n) "
      "(contacts treated as independent; correlate pools frames and runs).",
      "Pdfs (Fig 3, table pdf): nu_i(--pdf-radius) of critical (P_c) and non-critical (P_nc) "
      "contacts in --pdf-bins equal bins of [0, 1] ([k/B, (k+1)/B), 1 in the last), pooled over "
      "runs and over the loading phase: theta <= theta_c of each run, theta_c by the avalanche "
      "rule of critical (--avalanche-ek, --avalanche-hold), else the simulator's recorded "
      "avalanche angle, else every frame; --theta-c sets it for all inputs, --pdf-from/--pdf-to "
      "pool a theta range instead. An empty pdf is NA.",
      "Map (Fig 5, table map): at one frame, nu at the nodes of a grid of spacing --map-spacing "
      "over the contact points' bounding box = critical / contacts within --map-radius of the "
      "node (NA where there is none), and above = 1 where nu >= nu_c. nu_c is --nu-c, or the "
      "nu_c of a critical product given with --nu. The frame: --map-frame, else the one nearest "
      "--map-theta, else the last frame of the loading phase, of input --map-run. x, y and x_D, "
      "y_D give the node in m and in D; after 'localnu run.h5 --table map > map.tsv', gnuplot's "
      "'plot \"map.tsv\" u 5:6:9 w image' shows it, "
      "and to-xdmf on the HDF5 product gives ParaView the field. --per-contact adds nu_i(r) of "
      "every contact of that frame.",
      "Output: TSV on standard output by default (tables frames, states, pdf, map, contacts), an "
      "HDF5 product with -o FILE (-o - for a pipe into correlate). Frames without contacts or "
      "without critical contacts give NA, never NaN."};
  u.argument("inputs",
             "tilt runs (HDF5), their summaries, or contact tables (TSV/CSV); '-' for standard "
             "input",
             true, true);
  cli::declare_product_output(u, {"frames", "states", "pdf", "map", "contacts"});
  cli::declare_critical_rule(
      u, "grain-grain friction coefficient (default: the run's mu_grain; required for a table)");
  u.group("Local state");
  u.real_list("radii", "1:1:20", "radii r of the neighbourhoods (a list, or FIRST:STEP:LAST)", "D",
              1e-6, 1e6);
  u.flag("exclude-self", "leave contact i out of its own neighbourhood");
  u.text("edge", "keep", "neighbourhoods crossing the pile's outline", {"keep", "exclude"});
  u.real_opt(
      "diameter",
      "mean diameter D (required for a contact table, in its length unit; overrides a run's)", "",
      1e-300, 1e300);
  u.text("duplicates", "error",
         "a contact given twice in a table's frame (same ids, or same point without ids): "
         "an error naming both lines, or merged into one (the rows must agree; a note counts them)",
         {"error", "merge"});
  u.group("Pdfs and loading phase");
  u.real("pdf-radius", 6.0, "radius of the local state of the pdfs", "D", 1e-6, 1e6);
  u.integer("pdf-bins", 50, "bins of the pdfs over [0, 1]", 1, 100000);
  u.real_opt("pdf-from", "pool the pdfs from this tilt angle instead of over the loading phase",
             "deg");
  u.real_opt("pdf-to", "pool the pdfs up to this tilt angle", "deg");
  u.real_opt("theta-c", "end of the loading phase of every input (default: per run, as critical)",
             "deg");
  cli::declare_avalanche_rule(u);
  u.group("Map");
  u.real("map-radius", 6.0, "radius of the local state at the grid nodes", "D", 1e-6, 1e6);
  u.real("map-spacing", 1.0, "spacing of the grid nodes", "D", 1e-6, 1e6);
  u.real("nu-c", 0.08, "threshold of the map (the paper's nu_c; better: --nu or your own value)",
         "", 0.0, 1.0);
  u.text_opt("nu", "critical product (TSV or HDF5) whose nu_c is the threshold of the map");
  u.integer("map-run", 0, "input (0-based) of the mapped frame", 0, 1000000);
  u.integer_opt("map-frame", "frame id to map (default: the last of the loading phase)", 0,
                INT64_MAX);
  u.real_opt("map-theta", "map the frame nearest this tilt angle", "deg");
  u.flag("per-contact", "add the table 'contacts': nu_i(r) of every contact of the mapped frame");
  u.example("One run into correlate", "localnu run.h5 -o - | correlate - > nubar.tsv",
            "the localnu product passes as HDF5 through the pipe");
  u.example("The pdfs of Fig 3 over an ensemble", "localnu runs/run*.h5 --table pdf > pdf.tsv",
            "columns nu, P_c, P_nc for gnuplot");
  u.example("A contact table from another code",
            "localnu contacts.tsv --mu 0.5 --diameter 0.001 --table frames,states",
            "D and mu on the command line; see docs/analysis.md for a LAMMPS dump");
}

static void run(const cli::Args& a) {
  cli::check_output(a);  // refuse a bad target before the work
  analysis::LocalNuOptions opt = analysis::default_localnu_options();
  opt.radii = a.real_list("radii");
  opt.exclude_self = a.flag("exclude-self");
  opt.edge = a.text("edge") == "keep" ? analysis::EdgeRule::keep : analysis::EdgeRule::exclude;
  opt.pdf_radius = a.real("pdf-radius");
  opt.pdf_bins = static_cast<std::size_t>(a.integer("pdf-bins"));
  if (a.given("pdf-from") || a.given("pdf-to")) {
    analysis::ThetaRange r;
    if (auto v = a.real_opt("pdf-from")) r.lo = *v;
    if (auto v = a.real_opt("pdf-to")) r.hi = *v;
    if (r.lo >= r.hi) throw UsageError("--pdf-from must be below --pdf-to");
    opt.pdf_theta = r;
  }
  opt.map_radius = a.real("map-radius");
  opt.map_spacing = a.real("map-spacing");
  opt.per_contact = a.flag("per-contact");
  cli::refuse_table_if(a, "contacts", !opt.per_contact, "without --per-contact");
  for (std::size_t k = 1; k < opt.radii.size(); ++k)
    if (!(opt.radii[k] > opt.radii[k - 1])) throw UsageError("--radii must be strictly increasing");
  if (a.given("map-frame") && a.given("map-theta"))
    throw UsageError("--map-frame and --map-theta exclude each other");
  if (a.given("nu") && a.given("nu-c")) throw UsageError("--nu and --nu-c exclude each other");

  reading::LocalNuReading rd;
  rd.mu = cli::friction_choice(a);
  rd.rule = cli::critical_rule(a);
  rd.diameter = a.real_opt("diameter");
  rd.avalanche = cli::avalanche_rule(a);
  rd.theta_c = a.real_opt("theta-c");
  rd.map_run = a.integer("map-run");
  rd.map_frame = a.integer_opt("map-frame");
  rd.map_theta = a.real_opt("map-theta");
  rd.duplicates = a.text("duplicates") == "merge" ? io::Duplicates::merge : io::Duplicates::error;

  const std::vector<std::string>& paths = a.arguments("inputs");
  if (rd.map_run >= static_cast<std::int64_t>(paths.size()))
    throw UsageError("--map-run " + std::to_string(rd.map_run) + ": there are " +
                     std::to_string(paths.size()) + " inputs");
  cli::refuse_repeated_inputs(paths);
  if (std::count(paths.begin(), paths.end(), "-") + (a.text("nu") == "-") > 1)
    throw UsageError("'-' (standard input) given twice");

  opt.nu_c = a.real("nu-c");
  std::string nu_c_from = "option";
  std::optional<io::ProductFile> crit;  // with --nu, an input too: its history is kept
  if (!a.text("nu").empty()) {
    crit = io::read_product(io::Input(a.text("nu")), "critical");
    const auto v = crit->product.result("nu_c");
    if (!v)
      throw Error(crit->product.source, "",
                  "the critical product has no nu_c (its envelope was not fitted); give --nu-c");
    opt.nu_c = *v;
    nu_c_from = crit->product.source;
  }

  analysis::LocalNuStudy study(opt);
  std::vector<std::pair<std::string, std::vector<io::Provenance>>> histories;  // of every input
  std::string inputs;
  analysis::Values per_input;
  std::optional<std::string> length_unit;          // common to every input, "" if unknown or mixed
  std::optional<analysis::Product> first_summary;  // the engine every summary must share
  for (std::size_t k = 0; k < paths.size(); ++k) {
    io::Input in(paths[k]);
    inputs += (inputs.empty() ? "" : " ") + in.name();
    const reading::LocalNuInputInfo info =
        reading::add_localnu_input(study, in, static_cast<std::int64_t>(k), rd);
    if (info.summary && !first_summary)
      first_summary = info.summary;
    else if (info.summary)
      analysis::require_same_engine(*first_summary, *info.summary, in.name());
    // a contact table has no history, but it is one of the inputs the others are told from
    histories.emplace_back(in.name(), in.is_hdf5() ? io::read_header(in.hdf5()).provenance
                                                   : std::vector<io::Provenance>{});
    length_unit =
        !length_unit || *length_unit == info.length_unit ? info.length_unit : std::string();
    if (info.merged > 0) {
      const std::string note =
          in.name() + ": " + std::to_string(info.merged) +
          " repeated contact rows merged (--duplicates merge), each contact counted once";
      study.add_note(note);
      cli::info(note);
    }
    const std::string key = "run" + std::to_string(k) + "_";
    per_input[key + "theta_c_deg"] =
        info.theta_c ? analysis::Value(*info.theta_c) : analysis::Value(std::string("NA"));
    per_input[key + "theta_c_from"] = info.theta_c_from;
    cli::info(in.name() + ": " + std::to_string(info.frames) + " frames (" +
              std::to_string(info.loading_frames) + " in the loading phase" +
              (info.theta_c ? ", theta_c " + io::format_number(*info.theta_c, 6) + " deg from " +
                                  info.theta_c_from
                            : "") +
              ")");
  }
  if (crit) {
    inputs += " " + crit->product.source;
    histories.emplace_back(crit->product.source, crit->provenance);
  }
  study.set_length_unit(length_unit.value_or("m"));
  analysis::Product p = study.product();
  p.parameters["eps"] = rd.rule.eps;
  p.parameters["walls"] = std::int64_t{rd.rule.include_walls};
  p.parameters["map_nu_c_from"] = nu_c_from;
  if (rd.mu.grain) p.parameters["mu"] = *rd.mu.grain;
  if (rd.diameter) p.parameters["diameter"] = *rd.diameter;
  for (auto& [key, v] : per_input) p.results[key] = v;
  std::vector<io::Provenance> history = io::merge_histories(histories);
  history.push_back(io::provenance_now(a.tool(), a.command_line(), inputs));
  cli::emit_product(a, p, history);
}

CDPILE_TOOL(usage, run)
