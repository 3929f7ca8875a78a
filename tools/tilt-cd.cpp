// tilt-cd: tilts a static pile until it avalanches, with the Contact Dynamics engine;
// records every step's observables and full frames; checkpoints and resumes
// (docs/method.md, "Tilt" and "Checkpoints").
#include "cdpile/analysis/critical.hpp"
#include "cdpile/cli/avalanche_options.hpp"
#include "cdpile/cli/command.hpp"
#include "cdpile/cli/friction_options.hpp"
#include "cdpile/cli/progress.hpp"
#include "cdpile/io/files.hpp"
#include "cdpile/sim/tilt.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <set>
#include <vector>

using namespace cdpile;

static void usage(cli::Usage& u) {
  u.synopsis =
      "tilt a pile until it avalanches (Contact Dynamics); observables per step, frames, "
      "checkpoints";
  u.description = {
      "Reads a pile made by deposit ('-' for standard input) and turns gravity in the box frame, "
      "g(theta) = g (sin theta, -cos theta), by --rate degrees per step from --from. Without --to "
      "it "
      "stops --margin degrees after the avalanche is confirmed (or at --max-angle); with --to it "
      "runs "
      "to that angle whatever happens. The first step is warm-started from the pile's contact "
      "forces.",
      "Every step records the observables of docs/schema.md: tilt_angle, kinetic_energy, "
      "rotational_energy, contacts, contacts_grain, sliding, sweeps, substeps, residual, "
      "residual_rms, "
      "law_residual, "
      "law_residual_rms, converged, max_overlap, "
      "and the critical-contact counts critical (all active contacts) and critical_grain (between "
      "two "
      "free grains), critical meaning |f_t| >= (1 - --eps) mu f_n. Full frames (grains and "
      "contacts "
      "with forces and solver status) are written at step 0, every --frame-every steps (or "
      "--frame-every-deg degrees) and at the last step.",
      "Avalanche: the agitation a = Ek / (Np m g D) (translational kinetic energy per free grain "
      "over "
      "m g D, m the mean mass and D the mean diameter of the free grains) reaches --avalanche-ek "
      "and stays at or above it for --avalanche-hold degrees of tilt; the avalanche angle "
      "results/avalanche_angle_deg is the tilt where that sustained interval began.",
      "Branches: with --branch-at the input is a run made by tilt-cd, and the new run starts from "
      "the state of its last frame at or below that tilt (positions, velocities, rotations, "
      "contact "
      "forces as the warm start), tilting on from the frame's tilt with the run's own options (its "
      "/parameters), except those given here: another solver tolerance, frames every step over an "
      "interesting window, another rate. Each option that differs from the run's is said on "
      "stderr; "
      "a frame interval not given keeps the run's interval in degrees. With nothing changed a "
      "branch "
      "repeats the run's next steps up to the rounding of impulse = force x h (with "
      "--damping-ratio only where the pile is at rest: a frame's forces hold the dashpot's part, "
      "which the run did not anchor at). "
      "The branch records branch_step and branch_tilt_deg in /parameters.",
      "Checkpoints: a run to a file is kept in OUTPUT.partial, a valid run file with a /checkpoint "
      "group, rewritten every --checkpoint-every steps by an atomic rename, so a kill at any "
      "moment "
      "(kill -9 included) leaves the last checkpoint intact. --resume continues it and gives the "
      "same "
      "file, bit for bit in every dataset, as a run never interrupted (the pile argument is then "
      "not "
      "read again). A resume takes the interrupted run's options; an option given with another "
      "value "
      "than the run's is a usage error naming it. Ctrl-C or SIGTERM, once or more (a scheduler "
      "signals "
      "the tool and its make), abandons the step under way, writes a checkpoint of every completed "
      "step "
      "and exits with 130 (SIGTERM: 143) within a second (docs/cluster.md). The "
      "finished run is renamed onto OUTPUT and the partial removed; --resume on a finished OUTPUT "
      "does nothing. Writing to standard output (-o -) has no checkpoints.",
      "Parameters: the pile's, then " + sim::recorded_keys(sim::ParameterGroup::tilt) +
          " and the solver's (" + sim::recorded_keys(sim::ParameterGroup::settings) +
          "). Results: "
          "steps, "
          "final_angle_deg, "
          "avalanche_detected, avalanche_angle_deg, avalanche_step, avalanche_confirmed_step, "
          "unconverged_steps, max_overlap_m, max_overlap_grown_m (beyond the pile's own overlaps), "
          "stop_reason (avalanche, to or max_angle), warnings and "
          "warning_messages.",
      "Warnings (on stderr, even with --quiet, and in /results): more than 1 % of the steps at the "
      "sweep "
      "cap, or overlaps grown beyond 1e-3 D in the run (docs/method.md, \"Warnings\")."};
  u.argument("pile",
             "pile file made by deposit, or with --branch-at a run made by tilt-cd ('-' for "
             "standard input)");
  u.output("output run file ('-' for standard output, without checkpoints)");
  // The run parameters' options are declared in their rows (sim::run_parameters()); each
  // u.declare puts its group's rows at that point of --help, the tool's own options around.
  const std::vector<OptionDeclaration> declared = sim::declared_options();
  u.declare("Tilt", declared);
  u.real_opt("branch-at",
             "the input is a run: start from its last frame at or below this tilt (--from is that "
             "frame's tilt)",
             "deg", -90.0, 90.0)
      .place_after("from");
  u.group("Avalanche");
  cli::declare_avalanche_rule(u, "threshold of the agitation Ek / (Np m g D)",
                              "the agitation must stay above the threshold this long");
  u.declare("Avalanche", declared);
  u.group("Recording");
  u.integer_opt("frame-every", "a full frame every this many steps (instead of --frame-every-deg)",
                1, 1000000000000, "steps");
  u.real("frame-every-deg", 0.5, "a full frame every this much tilt", "deg", 1e-12, 180.0);
  u.declare("Recording", declared);
  u.flag("resume", "continue the interrupted run of OUTPUT from OUTPUT.partial");
  u.group("Friction");
  cli::declare_friction(u, "grain-grain friction coefficient (default: the pile's mu_grain)",
                        "grain-wall friction coefficient (default: the pile's mu_wall)");
  u.declare("Solver", declared);
  u.alias("avalanche-energy", "avalanche-ek");  // critical's and localnu's name
  u.alias("mu-grain", "mu");
  u.example("The paper's run", "tilt-cd pile.h5 -o run.h5",
            "0.001 degree per step until the avalanche plus 1 degree; prints the avalanche angle");
  u.example("Through a pipe, to a fixed angle",
            "deposit --grains 200 -o - | tilt-cd - --to 2 -o run.h5",
            "the small pile is tilted to 2 degrees");
  u.example(
      "A branch with a tighter solver",
      "tilt-cd run.h5 --branch-at 6 --to 7 --tolerance 1e-6 --frame-every 10 -o tight.h5",
      "restarts from the run's frame at 6 degrees and tilts to 7 degrees, a frame every 10 steps");
  u.example("After a crash or Ctrl-C", "tilt-cd pile.h5 -o run.h5 --resume",
            "continues from run.h5.partial with the options of the first invocation");
}

// The options of the run, with the pile's values as defaults (friction, gravity, D).
// A branch's or a resume's are those given over the run's (inherited()), checked once
// merged: --threads alone is then valid on a run in strips.
static sim::TiltOptions options(const cli::Args& a, const sim::PileInput& pile) {
  sim::TiltOptions o;
  const OptionValues values = cli::option_values(a, sim::declared_options());
  o.settings = sim::pile_settings(pile, values, a.real_opt("mu"), a.real_opt("mu-wall"));
  sim::set_declared_options(o, values);
  if (pile.branch) o.from_deg = pile.branch->tilt_deg;  // its frame's tilt, not --from
  const analysis::AvalancheRule avalanche = cli::avalanche_rule(a);
  o.avalanche_energy = avalanche.threshold;
  o.avalanche_hold_deg = avalanche.hold;
  if (a.given("frame-every") && a.given("frame-every-deg"))
    throw UsageError("give --frame-every or --frame-every-deg, not both");
  o.frame_every = a.integer_opt("frame-every")
                      .value_or(std::max<std::int64_t>(
                          1, std::llround(a.real("frame-every-deg") / o.rate_deg)));
  if (!pile.branch && !a.flag("resume")) sim::validate(o);
  return o;
}

// A branch or a resume: the run's options, with those given on the command line over them.
static sim::InheritedOptions inherited(const cli::Args& a, const sim::PileInput& run,
                                       const sim::TiltOptions& asked,
                                       std::optional<double> start_deg) {
  std::set<std::string> given;
  for (const auto& [name, yes] : a.given_)
    if (yes) given.insert(name);
  return sim::inherit_options(run.parameters, asked, given, start_deg, run.name);
}

static std::string change_text(const cli::Args& a, const sim::OptionChange& c) {
  if (c.option.empty())  // derived from the options given (sim::inherit_options)
    return c.parameter + " " + c.value + " (the run's " + c.run_value + ": " + c.reason + ")";
  return "--" + c.option + " " + a.text(c.option) + ": " + c.parameter + " " + c.value +
         " instead of the run's " + c.run_value;
}

// The progress line: where the tilt is, and the time left at the present speed (which
// changes as the contacts do; before the avalanche, the time to the maximum angle, the
// latest the run can end).
static std::vector<cli::ProgressField> progress_fields(const sim::TiltProgress& p, double sps) {
  char buf[5][64];
  std::snprintf(buf[0], sizeof buf[0], "%s: %.3f deg", cli::tool_name().c_str(), p.angle_deg);
  std::snprintf(buf[1], sizeof buf[1], "step %lld", static_cast<long long>(p.step));
  std::snprintf(buf[2], sizeof buf[2], "%.0f steps/s", sps);
  std::snprintf(buf[3], sizeof buf[3], "Ek/(Np m g D) %.1e", p.agitation);
  if (p.last_step >= 0)
    std::snprintf(buf[4], sizeof buf[4], "%sest. %.0f s left",
                  p.avalanche ? "avalanche confirmed, " : "",
                  static_cast<double>(p.last_step - p.step) / sps);
  else
    std::snprintf(buf[4], sizeof buf[4], "est. at most %.0f s left",
                  static_cast<double>(p.cap_step - p.step) / sps);
  return {{buf[0], 0}, {buf[1], 2}, {buf[2], 4}, {buf[3], 3}, {buf[4], 1}};
}

// The settings' warnings are said before the run starts (a user can stop a long run at
// once) and are not repeated at the end; the run's file records them all. Returns how many.
static std::size_t warn_settings(const sim::TiltOptions& o, const sim::PileInput& p) {
  const auto w = sim::settings_warnings(o.settings, analysis::mean_diameter(p.grains));
  for (const auto& line : w) cli::warn(line);
  return w.size();
}

// Continues OUTPUT.partial with the interrupted run's options.
static sim::TiltOutcome resume(const cli::Args& a, const std::string& output,
                               const sim::TiltHooks& hooks, std::size_t& warned) {
  sim::PileInput partial = sim::read_partial(output);
  if (a.given("branch-at"))  // the run branched from is not read again: its tilt is in the partial
    partial.branch = sim::PileInput::Branch{
        0, io::as_real(partial.parameters, sim::parameter_key("from_deg"), partial.name)};
  const sim::InheritedOptions inh = inherited(a, partial, options(a, partial), std::nullopt);
  if (!inh.changes.empty()) {  // the partial is the run: another value would change it halfway
    const sim::OptionChange& c = inh.changes.front();
    throw UsageError(
        change_text(a, c) + " in the interrupted run " + partial.name +
        "; resume with its options (" +
        (c.option.empty() ? std::string("leave them out") : "leave --" + c.option + " out") + ")");
  }
  warned = warn_settings(inh.options, partial);
  return sim::resume_tilt(inh.options, output, a.force(), hooks);
}

// A new run from a pile, or a branch from a run's frame.
static sim::TiltOutcome start(const cli::Args& a, const std::string& output,
                              const sim::TiltHooks& hooks, std::size_t& warned) {
  sim::check_output(output, a.force());  // before standard input is read, and the run made
  const io::Input in(a.argument("pile"));
  const auto branch_at = a.real_opt("branch-at");
  const sim::PileInput pile =
      branch_at ? sim::read_branch(in.hdf5(), *branch_at) : sim::read_pile(in.hdf5());
  if (pile.branch) {
    char what[160];
    std::snprintf(what, sizeof what, ": branching from the frame of step %lld at %.6g deg",
                  static_cast<long long>(pile.branch->step), pile.branch->tilt_deg);
    cli::info(in.name() + what);
  }
  sim::TiltOptions o = options(a, pile);
  if (pile.branch) {
    const sim::InheritedOptions inh = inherited(a, pile, o, pile.branch->tilt_deg);
    for (const auto& c : inh.changes) cli::info(in.name() + ": branch: " + change_text(a, c));
    o = inh.options;
  }
  warned = warn_settings(o, pile);
  return sim::run_tilt(pile, o, output, a.force(),
                       io::provenance_now(a.tool(), a.command_line(), in.name()), hooks);
}

// What the run did, on stderr; an interrupted run's exit code (docs/cli.md).
static int report(const std::string& output, const sim::TiltOutcome& outcome, double secs,
                  std::size_t warned) {
  const double sps = static_cast<double>(outcome.steps - outcome.first_step) / std::max(secs, 1e-9);
  if (outcome.interrupted) {  // said even with --quiet (as deposit does): a log must say where a
                              // run stopped
    std::cerr << cli::tool_name() << ": interrupted at step " << outcome.steps << " ("
              << std::to_string(outcome.final_angle_deg) << " deg); "
              << (output == "-" ? std::string("the run so far was written")
                                : sim::partial_path(output) +
                                      " holds it; run again with --resume to continue")
              << std::endl;
    return cli::interrupt_exit_code();
  }
  char line[400];
  if (outcome.avalanche)
    std::snprintf(line, sizeof line, "avalanche at %.3f deg; stopped at %.3f deg (step %lld, %s)",
                  outcome.avalanche_deg, outcome.final_angle_deg,
                  static_cast<long long>(outcome.steps), outcome.stop_reason.c_str());
  else
    std::snprintf(line, sizeof line, "no avalanche detected; stopped at %.3f deg (step %lld, %s)",
                  outcome.final_angle_deg, static_cast<long long>(outcome.steps),
                  outcome.stop_reason.c_str());
  cli::info(std::string(line) + "; " + std::to_string(outcome.unconverged_steps) +
            " unconverged steps; " + std::to_string(static_cast<long long>(secs)) + " s wall, " +
            std::to_string(static_cast<long long>(sps)) + " steps/s");
  for (std::size_t k = warned; k < outcome.warnings.size(); ++k) cli::warn(outcome.warnings[k]);
  return 0;
}

static int run(const cli::Args& a) {
  const std::string output = a.output();
  if (output.empty())
    throw UsageError("no output file given (-o FILE, or -o - for standard output)");
  if (a.given("branch-at") && a.given("from"))
    throw UsageError("give --from or --branch-at, not both (a branch starts at its frame's tilt)");
  const bool resuming = a.flag("resume");
  if (resuming && output == "-")
    throw UsageError("--resume needs an output file (-o FILE), not standard output");
  if (resuming && sim::finished_run(output)) {
    cli::info(output + ": already complete; nothing to resume");
    return 0;
  }
  const bool has_partial = output != "-" && sim::has_partial(output);
  if (resuming && !has_partial)
    cli::info(sim::partial_path(output) + ": no partial run; starting from the pile");

  cli::Progress progress(a);
  std::int64_t first = -1;
  std::optional<sim::TiltProgress> latest;  // shown once more at the end, where the run stopped
  sim::TiltHooks hooks;
  hooks.stop = [] { return cli::interrupted(); };
  // Signals wait for the loop only while it runs and saves: reading the input or writing
  // the final copy, the tool ends at once (nothing is lost that a resume does not redo).
  hooks.deferring = [](bool on) { on ? cli::defer_interrupts() : cli::end_deferral(); };
  hooks.progress = [&](const sim::TiltProgress& p) {
    if (first < 0) first = p.step - 1;
    if (!progress.shown()) return;
    latest = p;
    if (progress.due())
      progress.show(progress_fields(p, progress.rate(static_cast<double>(p.step - first))));
  };
  std::size_t warned = 0;
  const sim::TiltOutcome outcome =
      resuming && has_partial ? resume(a, output, hooks, warned) : start(a, output, hooks, warned);
  if (latest)
    progress.show(
        progress_fields(*latest, progress.rate(static_cast<double>(latest->step - first))));
  progress.finish();
  return report(output, outcome, progress.seconds(), warned);
}

CDPILE_TOOL(usage, run)
