// critical: the fraction nu of critical contacts in the pile as the pile tilts (eq 1),
// z and lambda (eq 2), rearrangement events (Fig 2), the ensemble mean over runs (inset
// of Fig 1a), the envelope of maxima and its limit nu_c (Fig 1c), the avalanche angle.
#include "cdpile/analysis/studies.hpp"
#include "cdpile/cli/analysis_options.hpp"
#include "cdpile/cli/avalanche_options.hpp"
#include "cdpile/cli/command.hpp"
#include "cdpile/io/checkpoint.hpp"
#include "cdpile/io/products.hpp"
#include "cdpile/reading/inputs.hpp"

#include <cmath>

using namespace cdpile;

static void usage(cli::Usage& u) {
  u.synopsis =
      "nu = Nc/N, z, Ek, lambda per step and per frame; events; ensemble; envelope and nu_c";
  u.description = {
      "Reads one or more tilt runs, or their summaries (summarise; the same products, "
      "docs/analysis.md \"Summaries\"), the ensemble being the list of files, and writes, per step "
      "(from /observables) and per frame (from the contacts and grains), the tilt angle theta, "
      "the number N of active contacts, the number Nc of critical ones, nu = Nc/N (eq 1 of "
      "Staron, Vilotte & Radjai 2002), the coordination z, the mean translational kinetic energy "
      "Ek per free grain (J/m; per step from the observable kinetic_energy, per frame from the "
      "grains' velocities and masses) with ek_norm = Ek/(m g D), and lambda = sqrt(2/(z nu)) D "
      "(eq 2, in units of D).",
      "Critical: f_n > 0 and |f_t| >= (1 - eps) mu f_n. The default eps = 1e-3 is ten times the "
      "solver's relative tolerance (1e-4): a contact the solver leaves sliding is exactly on the "
      "cone, a sticking one can sit inside it by about the tolerance. The solver's own sliding "
      "status is reported alongside (nu_sliding). N counts active grain-grain contacts; a "
      "contact with a wall or with a grain glued to the floor is a wall contact, counted only "
      "with --walls. mu is the run's mu_grain (mu_wall for walls) unless --mu is given.",
      "z = 2N/Np': Np' counts the free grains with at least 2 counted contacts (rattlers "
      "excluded, --rattlers include for all free grains); z_all = 2N/Np is reported too and is "
      "the one used per step.",
      "Events (Fig 2): from a local maximum of the per-step contact count N to the next local "
      "minimum; a turning point is confirmed once N has moved back by --event-hysteresis "
      "contacts. loss = Delta N/N; nu_before is the series' nu at or just before the maximum.",
      "Ensemble (inset of Fig 1a): per run the mean of nu in bins of --grid degrees, then the "
      "mean and standard error over runs (NA with one run). Envelope (Fig 1c): per run the "
      "maximum of nu in windows of --envelope-window degrees, averaged over runs and placed at "
      "the mean theta of the maxima; fitted by nu_c - B exp(-theta/tau) (Levenberg-Marquardt, "
      "weighted by the standard errors when every window has one; errors from the covariance "
      "scaled by chi2/dof when above 1). nu_c is reported with its standard error, and only "
      "when the envelope saturates: tau shorter than the fitted range and 0 < nu_c <= 1 "
      "(result envelope_saturates; otherwise a note says why there is no nu_c).",
      "The series behind the ensemble, envelope and events (--series): 'steps' uses the per-step "
      "critical count recorded by the simulator (observable critical_grain, critical with "
      "--walls), counted with the run's own rule (its parameters critical_eps, mu_grain, mu_wall); "
      "'frames' the frames' contacts with the rule asked for; 'sliding' the per-step sliding "
      "count. 'auto' takes steps when every run records them with the rule asked for (same eps "
      "and mu, mu_wall with --walls, no --floor-grains grain without --walls), else frames, with a "
      "note naming the difference; the per-step Nc, nu and lambda of such a run are then NA. "
      "--series steps with another rule is a usage error.",
      "Static bound (McNamara & Herrmann 2004): a static packing of rigid frictional disks has at "
      "most B = 2M - 3N critical contacts, M the active contacts of the N load-bearing free grains "
      "(walls and glued grains included, whatever --walls says; rattlers, free grains with fewer "
      "than 2 active contacts, removed repeatedly). Per frame: contacts_load_bearing (M), "
      "grains_load_bearing (N), critical_load_bearing (Nc among the M, by --eps), static_bound (B) "
      "and above_static_bound (1 when Nc > B: the frame is moving or its forces unconverged). "
      "When nu_c is reported, each run's maximum in each fitted envelope window is judged at the "
      "run's last frame at or before it in the same window; if any is above its bound, a warning "
      "(stderr and a '# note: warning:' line) says how many, and how many frames are above theirs.",
      "Static and moving states: a step is static when it converged (observable converged), its "
      "grains are at rest by deposit's rest criterion ((Ek + Erot) per free grain below "
      "--rest-energy m g D, every grain slower than --rest-speed sqrt(g D)) and no free grain is "
      "without an active contact (in flight); a frame by the same rule from its grains and "
      "contacts and its step's convergence. Column static in the steps and frames tables (NA when "
      "a run lacks an observable the rule needs). nu(theta), the envelope and nu_c are read twice: "
      "over every state (nu_c, today's reading) and over static states only (nu_c_static, "
      "columns *_static of the ensemble and envelope tables); the paper's reading, nu at the "
      "avalanche, is nu_theta_c: per run the mean nu of its static states in the last "
      "--envelope-window degrees before theta_c, then mean and standard error over runs. A "
      "fourth reading keeps the pile's parts at rest while others move: per frame N_rest and "
      "Nc_rest count the contacts whose two bodies are slower than --rest-speed sqrt(g D) (a "
      "wall is at rest) and which do not slip (--slip-speed), nu_rest = Nc_rest/N_rest, and "
      "nu_c_rest is the limit of its envelope "
      "(columns *_rest).",
      "Per frame also: z_paper, the paper's coordination (active contacts of the free grains, "
      "walls and glued grains included, per free grain, rattlers included), the contacts that "
      "slip (tangential relative velocity above --slip-speed sqrt(g D): motion, where critical "
      "is force) and the critical ones among them. Per window of --mobilisation-window degrees "
      "of the loading phase, pooled over runs: the distribution of |f_t|/(mu f_n) of the counted "
      "contacts (table mobilisation, 20 bins on [0, 1]) and nu, the slipping fraction and the "
      "fraction of critical contacts that slip (table windows), over all frames and static ones.",
      "theta_c of a run: the first step where Ek/(m g D) (m the mean grain mass) reaches "
      "--avalanche-ek and stays there for --avalanche-hold degrees or to the end of the run; "
      "the ensemble theta_c is the mean over runs with its standard error. The simulator's own "
      "avalanche_angle_deg is reported alongside (theta_c_recorded). By default each run "
      "enters the ensemble and envelope only up to its theta_c (--no-cut keeps everything).",
      "Output: TSV on standard output (tables runs, steps, frames, events, ensemble, envelope, "
      "mobilisation, windows, "
      "each a block with a '# table:' line, separated by two blank lines for gnuplot's index; "
      "--table picks some), or an HDF5 product with -o FILE (-o - for a pipe; a name ending in "
      ".tsv writes TSV). Undefined values (nu with N = 0, lambda with Nc = 0, a standard error "
      "from one run) are NA, never NaN. docs/tools/critical.md and docs/analysis.md say more."};
  u.argument("runs",
             "tilt run files (HDF5; '-' for standard input), or their summaries (summarise); a "
             "run tilt-cd is still computing: OUTPUT.partial, or OUTPUT while only the partial "
             "exists (up to its last checkpoint)",
             true, true);
  cli::declare_product_output(u, analysis::critical_table_names(analysis::CriticalOptions{}));
  u.flag("no-steps", "leave the per-step table out");
  u.text_opt("contacts",
             "also write every counted contact of every frame to this file, a product of one "
             "table (run, frame, theta, i, j, critical, sliding, slip; TSV for a name ending in "
             ".tsv, else HDF5): a contact's state by the rule and --slip-speed, for scripts");
  cli::declare_critical_rule(u, "grain-grain friction coefficient (default: the run's mu_grain)");
  u.text("rattlers", "exclude", "rattler convention of z", {"exclude", "include"});
  u.group("Series, ensemble and envelope");
  u.text("series", "auto", "nu(theta) series of the ensemble, envelope and events",
         {"auto", "steps", "frames", "sliding"});
  u.real("grid", 0.1, "bin width of the ensemble mean", "deg", 1e-6, 90);
  u.real("envelope-window", 0.5, "window of the maxima of the envelope", "deg", 1e-6, 90);
  u.real_opt("envelope-from",
             "fit the envelope from this angle (default: windows where every run contributes)",
             "deg");
  u.real_opt("envelope-to", "fit the envelope up to this angle", "deg");
  u.group("Static states, slip and mobilisation");
  u.real("rest-energy", 1e-6, "a state is at rest below this (Ek + Erot) per free grain, in m g D",
         "", 0, 1e300);
  u.real("rest-speed", 1e-2, "... and with every grain slower than this, in sqrt(g D)", "", 0,
         1e300);
  u.real("slip-speed", analysis::default_slip_speed,
         "a contact slips above this tangential relative velocity, in sqrt(g D)", "", 0, 1e300);
  u.real("mobilisation-window", 2.0, "tilt windows of the mobilisation and windows tables", "deg",
         1e-3, 90);
  u.group("Events and avalanche");
  u.integer("event-hysteresis", 1, "contacts by which N must move back to confirm a turning point",
            1, 1000000);
  u.integer("event-min-drop", 1, "keep events losing at least this many contacts", 1, 1000000000);
  cli::declare_avalanche_rule(u);
  u.flag("no-cut", "keep data after each run's theta_c in the ensemble and envelope");
  u.example("One run, the per-frame table for gnuplot",
            "critical run.h5 --table frames > frames.tsv",
            "columns run, frame, step, theta, N, Nc, nu, ... with a commented header");
  u.example("An ensemble of 15 runs as an HDF5 product", "critical runs/run*.h5 -o critical.h5",
            "tables under /tables, nu_c and theta_c under /results");
  u.example("nu_c and its error", "critical runs/run*.h5 --no-steps | grep '^# result nu_c'",
            "the envelope's limit, with nu_c_se");
}

static void run(const cli::Args& a) {
  cli::check_output(a);  // refuse a bad target before the work
  analysis::CriticalOptions opt;
  opt.rule = cli::critical_rule(a);
  opt.rattlers = a.text("rattlers") == "exclude" ? analysis::RattlerRule::exclude
                                                 : analysis::RattlerRule::include;
  const std::string& series = a.text("series");
  opt.source = series == "steps"     ? analysis::SeriesSource::steps
               : series == "frames"  ? analysis::SeriesSource::frames
               : series == "sliding" ? analysis::SeriesSource::sliding
                                     : analysis::SeriesSource::automatic;
  opt.grid_step = a.real("grid");
  opt.envelope_window = a.real("envelope-window");
  if (a.given("envelope-from") || a.given("envelope-to")) {
    analysis::ThetaRange r;
    if (auto v = a.real_opt("envelope-from")) r.lo = *v;
    if (auto v = a.real_opt("envelope-to")) r.hi = *v;
    if (r.lo >= r.hi) throw UsageError("--envelope-from must be below --envelope-to");
    opt.envelope_fit = r;
  }
  opt.rest.energy = a.real("rest-energy");
  opt.rest.speed = a.real("rest-speed");
  opt.slip_speed = a.real("slip-speed");
  opt.mobilisation_window = a.real("mobilisation-window");
  opt.events.hysteresis = a.integer("event-hysteresis");
  opt.events.min_drop = a.integer("event-min-drop");
  opt.avalanche = cli::avalanche_rule(a);
  opt.cut_at_avalanche = !a.flag("no-cut");
  opt.step_table = !a.flag("no-steps");

  // an unknown --table is refused by the parser; one left out by --no-steps here, before any run is
  // read
  cli::refuse_table_if(a, "steps", !opt.step_table, "with --no-steps");
  const bool per_contact = a.given("contacts");
  if (per_contact) {  // a bad target refused before the work, as -o's
    cli::refuse_output_named_twice(a, "contacts");
    const std::string& path = a.text("contacts");
    if (path == "-" && a.output().empty())
      throw UsageError("--contacts - and the product both on standard output; give -o FILE");
    io::Output check(path, a.force(),
                     io::resolve_format(path, io::Format::automatic) == io::Format::hdf5);
  }

  std::vector<analysis::RunRecord> runs;
  std::vector<std::pair<std::string, std::vector<io::Provenance>>> histories;  // of every run
  // A partial run's note is said once every run has been read and analysed: a file that
  // is refused gets its one line, not a note before it.
  std::vector<std::string> notes;
  std::string inputs;
  cli::refuse_repeated_inputs(a.arguments("runs"));
  std::optional<analysis::Product> first_summary;  // the engine every summary must share
  const reading::CriticalReading reading{cli::friction_choice(a), opt, per_contact};
  for (const std::string& path : a.arguments("runs")) {
    io::Input in(io::run_or_partial(path));  // a run tilt-cd is still computing: its partial
    inputs += (inputs.empty() ? "" : " ") + in.name();
    reading::CriticalInput r = reading::read_critical_input(in, reading, first_summary);
    if (!r.note.empty()) notes.push_back(std::move(r.note));
    histories.emplace_back(in.name(), std::move(r.history));
    cli::info(in.name() + ": " + (r.summary ? "a summary, " : "") +
              std::to_string(r.run.steps.step.size()) + " steps, " +
              std::to_string(r.run.frames.size()) + " frames");
    runs.push_back(std::move(r.run));
  }
  analysis::Product p = analysis::critical_study(runs, opt);
  for (const std::string& note : notes) cli::warn(note);
  for (const std::string& w : analysis::product_warnings(p)) cli::warn(w);
  std::vector<io::Provenance> history = io::merge_histories(histories);
  cli::info(analysis::critical_readings(p));
  history.push_back(io::provenance_now(a.tool(), a.command_line(), inputs));
  cli::emit_product(a, p, history);
  if (per_contact)
    io::emit(analysis::critical_contacts(runs, opt), history, a.text("contacts"), a.force(),
             io::Format::automatic);
}

CDPILE_TOOL(usage, run)
