// correlate: nu_bar(theta, r), the mean local state around critical contacts (eq 3 of
// Staron, Vilotte & Radjai 2002), per frame and pooled in theta windows over frames and
// runs (Fig 4a, 4b).
#include "cdpile/analysis/correlate.hpp"
#include "cdpile/cli/analysis_options.hpp"
#include "cdpile/cli/command.hpp"
#include "cdpile/io/products.hpp"

using namespace cdpile;

static void usage(cli::Usage& u) {
  u.synopsis =
      "nu_bar(theta, r): the mean local state around critical contacts, per frame and per theta "
      "window";
  u.description = {
      "Reads the product of localnu (TSV or HDF5; '-' for standard input) and writes nu_bar(theta, "
      "r) = the mean of nu_i(theta, r) over the critical contacts (eq 3), for every radius r of "
      "localnu (in D, by default 1 D to 20 D).",
      "Table frames: nu_bar(r) of each frame, se = sd/sqrt(n) over its n critical contacts "
      "(treated as independent: an underestimate, neighbouring contacts are correlated), and "
      "nu_pile, the frame's nu = Nc/N.",
      "Table windows: frames pooled in theta windows [start + k w, start + (k+1) w) with w = "
      "--window and start = --window-start. nu_bar pools every critical contact of the window's "
      "frames of every run (sum of nu_i over sum of n). Its se is the cluster-robust standard "
      "error of that pooled mean, se^2 = C/(C-1) sum_c (S_c - nu_bar N_c)^2 / (sum_c N_c)^2, with "
      "the runs as the C clusters when >= 2 runs contribute (se_over = runs), else the frames "
      "(se_over = frames; frames of one run are correlated in time, so this is optimistic), else "
      "the contacts of the single frame (se_over = contacts). theta of a window is the mean theta "
      "of its frames; nu_pile is the mean pile nu of its frames, nu_pile_se over runs (>= 2) or "
      "frames.",
      "Frames without a tilt angle (a contact table without a theta column) form one window with "
      "theta NA when no frame has one; otherwise they are left out and counted in the result "
      "frames_without_theta. --from/--to restrict the frames used. A window or frame without "
      "critical contacts has nu_bar NA, never NaN.",
      "Output: TSV on standard output by default (for gnuplot and awk), an HDF5 product with -o "
      "FILE (-o - for a pipe into clusterfit)."};
  u.argument("localnu", "localnu product (TSV or HDF5; '-' for standard input)");
  cli::declare_product_output(u, {"frames", "windows"});
  u.flag("no-frames", "leave the per-frame table out");
  u.group("Windows");
  u.real("window", 1.0, "width w of the theta windows", "deg", 1e-9, 360);
  u.real("window-start", 0.0, "start of the first window", "deg", -360, 360);
  u.real_opt("from", "use frames from this tilt angle", "deg");
  u.real_opt("to", "use frames up to this tilt angle", "deg");
  u.example("nu_bar against r at every degree, for gnuplot",
            "correlate localnu.h5 --table windows > nubar.tsv",
            "columns theta, r, nu_bar, se, ... one block; plot with 'u 4:8:9 w yerr'");
  u.example("In a pipe", "localnu run.h5 -o - | correlate - -o - | clusterfit - --nu critical.tsv",
            "see docs/analysis.md, 'The pipeline'");
}

static void run(const cli::Args& a) {
  cli::check_output(a);  // refuse a bad target before the work
  analysis::CorrelateOptions opt;
  opt.window = a.real("window");
  opt.window_start = a.real("window-start");
  opt.frame_table = !a.flag("no-frames");
  if (auto v = a.real_opt("from")) opt.theta.lo = *v;
  if (auto v = a.real_opt("to")) opt.theta.hi = *v;
  if (opt.theta.lo > opt.theta.hi) throw UsageError("--from must not be above --to");
  cli::refuse_table_if(a, "frames", !opt.frame_table, "with --no-frames");

  const io::Input in(a.argument("localnu"));
  io::ProductFile f = io::read_product(in, "localnu");
  analysis::Product p;
  try {
    p = analysis::correlate(f.product, opt);
  } catch (const Error& e) {
    // errors of the product's content name the file
    if (std::string(e.what()).rfind(in.name() + ":", 0) == 0) throw;
    throw Error(in.name(), "", e.what());
  }
  f.provenance.push_back(io::provenance_now(a.tool(), a.command_line(), in.name()));
  cli::emit_product(a, p, f.provenance);
}

CDPILE_TOOL(usage, run)
