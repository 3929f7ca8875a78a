// clusterfit: eq (4) of Staron, Vilotte & Radjai 2002 fitted per theta window, the affine
// fits of A(theta) and alpha(theta), the cluster size r_c(theta) of eq (5) and its
// power-law divergence r_c ~ (theta_c - theta)^-beta (Fig 6).
#include "cdpile/analysis/clusterfit.hpp"
#include "cdpile/cli/analysis_options.hpp"
#include "cdpile/cli/command.hpp"
#include "cdpile/io/products.hpp"

#include <cmath>
#include <limits>

using namespace cdpile;

static void usage(cli::Usage& u) {
  u.synopsis =
      "fit nu_bar = nu_inf (1 + A r^alpha) for r <= L; r_c(theta); r_c ~ (theta_c - theta)^-beta";
  u.description = {
      "Reads the product of correlate (TSV or HDF5; '-' for standard input) and, with --nu, the "
      "product of critical (its ensemble nu(theta) and its nu_c).",
      "Eq (4): in each theta window of correlate, nu_bar(r) = nu_inf (1 + A r^alpha) is fitted "
      "over --r-min <= r <= L (--r-max, default 10 D) by Levenberg-Marquardt (Eigen's MINPACK "
      "lmder, analytic Jacobian), weighted by correlate's standard errors when every point has "
      "one, else unweighted; a window needs --min-points radii.",
      "nu_inf(theta) (--nu-inf): 'ensemble' = critical's ensemble mean nu over the window's "
      "theta bins (the paper's nu_inf, 'the ensemble nu of the pile'; interpolated when no bin "
      "centre falls in the window); 'pile' = the mean pile nu of the window's frames (from "
      "correlate); 'fit' = a free third parameter; 'auto' = ensemble with --nu, else pile. A "
      "given nu_inf's error is not propagated into A and alpha.",
      "Uncertainties are from the fit's covariance at the optimum, not a bootstrap: (J^T W J)^-1 "
      "for a weighted fit, multiplied by chi2/dof when that exceeds 1; (RSS/dof) (J^T J)^-1 for an "
      "unweighted one; none when dof = 0.",
      "Affine fits (table affine): A(theta) = c0 + c1 theta and alpha(theta) = c0 + c1 theta over "
      "the fitted windows (--affine-from/--affine-to), weighted by the windows' standard errors.",
      "Eq (5): r_c(theta) = [(nu_c/nu_inf - 1)/A]^(1/alpha) in D, from each window's A and alpha "
      "(--rc-from window) or from the affine fits at the window's theta (--rc-from affine); its se "
      "by linear propagation of cov(A, alpha) and of independent errors on nu_c and nu_inf. NA "
      "where undefined ((nu_c/nu_inf - 1)/A <= 0). nu_c is --nu-c (with --nu-c-se), else "
      "critical's "
      "nu_c and nu_c_se; without either r_c is not computed.",
      "Fig 6: ln r_c = ln C - beta ln(theta_c - theta) fitted over the windows with theta in "
      "[--power-from, --power-to] (default from 15 deg, the paper's range), weighted by "
      "se(r_c)/r_c. theta_c is fitted, kept above the largest theta (as theta_max + exp(s)), "
      "unless "
      "--theta-c gives it; beta and theta_c get standard errors from the covariance (the delta "
      "method for theta_c). It needs 4 windows (3 with --theta-c). A fitted theta_c that runs onto "
      "the last angle is a boundary solution: no beta, result power_degenerate = 1 and a note.",
      "Output: TSV on standard output by default (tables fits, model, affine; beta, theta_c_deg "
      "and their se as '# result' lines), or an HDF5 product with -o. A window that cannot be "
      "fitted has converged = 0 and NA values; with nothing to fit the tables are empty and a "
      "note says why: a documented empty result, never NaN."};
  u.argument("correlate", "correlate product (TSV or HDF5; '-' for standard input)");
  cli::declare_product_output(u, {"fits", "model", "affine"});
  u.group("Cluster law (eq 4)");
  u.text_opt("nu", "critical product (TSV or HDF5): ensemble nu(theta) for nu_inf, and nu_c");
  u.text("nu-inf", "auto", "nu_inf(theta) of eq (4)", {"auto", "ensemble", "pile", "fit"});
  u.real("r-min", 1.0, "smallest radius fitted", "D", 1e-9, 1e9);
  u.real("r-max", 10.0, "L: largest radius fitted", "D", 1e-9, 1e9);
  u.integer("min-points", 4, "radii needed to fit a window", 3, 1000000);
  u.real_opt("from", "fit windows from this tilt angle", "deg");
  u.real_opt("to", "fit windows up to this tilt angle", "deg");
  u.real_opt("affine-from", "affine fits from this tilt angle (default: every fitted window)",
             "deg");
  u.real_opt("affine-to", "affine fits up to this tilt angle", "deg");
  u.group("Cluster size (eq 5) and divergence (Fig 6)");
  u.real_opt("nu-c", "nu_c of eq (5) (default: the critical product's)", "", 1e-12, 0.999999);
  u.real("nu-c-se", 0.0, "standard error of --nu-c", "", 0.0, 1.0);
  u.text("rc-from", "window", "A and alpha of eq (5)", {"window", "affine"});
  u.real("power-from", 15.0, "power-law fit from this tilt angle", "deg", -360, 360);
  u.real_opt("power-to", "power-law fit up to this tilt angle", "deg");
  u.real_opt("theta-c", "theta_c of the power law (default: fitted)", "deg");
  u.example("The end of the pipeline",
            "localnu run*.h5 -o - | correlate - -o - | clusterfit - --nu critical.tsv",
            "nu_inf and nu_c from critical's product");
  u.example("beta with theta_c given",
            "clusterfit nubar.h5 --nu critical.h5 --theta-c 20 | grep '^# result beta'",
            "beta and beta_se");
}

static void run(const cli::Args& a) {
  cli::check_output(a);  // refuse a bad target before the work
  analysis::ClusterFitOptions opt;
  opt.r_min = a.real("r-min");
  opt.r_max = a.real("r-max");
  if (!(opt.r_max > opt.r_min)) throw UsageError("--r-max must be above --r-min");
  opt.min_points = static_cast<int>(a.integer("min-points"));
  const std::string& ni = a.text("nu-inf");
  opt.nu_inf = ni == "ensemble" ? analysis::NuInfSource::ensemble
               : ni == "pile"   ? analysis::NuInfSource::pile
               : ni == "fit"    ? analysis::NuInfSource::fit
                                : analysis::NuInfSource::automatic;
  if (opt.nu_inf == analysis::NuInfSource::ensemble && a.text("nu").empty())
    throw UsageError("--nu-inf ensemble needs the critical product (--nu FILE)");
  if (auto v = a.real_opt("from")) opt.theta.lo = *v;
  if (auto v = a.real_opt("to")) opt.theta.hi = *v;
  if (opt.theta.lo > opt.theta.hi) throw UsageError("--from must not be above --to");
  if (a.given("affine-from") || a.given("affine-to")) {
    analysis::ThetaRange r;
    if (auto v = a.real_opt("affine-from")) r.lo = *v;
    if (auto v = a.real_opt("affine-to")) r.hi = *v;
    if (r.lo > r.hi) throw UsageError("--affine-from must not be above --affine-to");
    opt.affine = r;
  }
  opt.nu_c = a.real_opt("nu-c");
  if (a.given("nu-c-se") && !opt.nu_c) throw UsageError("--nu-c-se needs --nu-c");
  opt.nu_c_se = a.real("nu-c-se");
  opt.rc_from = a.text("rc-from") == "affine" ? analysis::RcFrom::affine : analysis::RcFrom::window;
  opt.power.lo = a.real("power-from");
  if (auto v = a.real_opt("power-to")) opt.power.hi = *v;
  if (opt.power.lo >= opt.power.hi) throw UsageError("--power-from must be below --power-to");
  opt.theta_c = a.real_opt("theta-c");

  if (a.text("nu") == "-" && a.argument("correlate") == "-")
    throw UsageError("'-' (standard input) given twice");

  const io::Input in(a.argument("correlate"));
  io::ProductFile cor = io::read_product(in, "correlate");
  std::optional<io::ProductFile> crit;
  std::string inputs = in.name();
  // the history of every input: correlate's chain, and critical's with --nu
  std::vector<std::pair<std::string, std::vector<io::Provenance>>> histories{
      {in.name(), cor.provenance}};
  if (!a.text("nu").empty()) {
    const io::Input cin(a.text("nu"));
    crit = io::read_product(cin, "critical");
    inputs += " " + cin.name();
    histories.emplace_back(cin.name(), crit->provenance);
  }
  analysis::Product p;
  try {
    p = analysis::clusterfit(cor.product, crit ? &crit->product : nullptr, opt);
  } catch (const Error& e) {
    const std::string what = e.what();
    if (what.rfind(in.name() + ":", 0) == 0 ||
        (crit && what.rfind(crit->product.source + ":", 0) == 0))
      throw;
    throw Error(in.name(), "", what);
  }
  std::vector<io::Provenance> history = io::merge_histories(histories);
  history.push_back(io::provenance_now(a.tool(), a.command_line(), inputs));
  cli::emit_product(a, p, history);
}

CDPILE_TOOL(usage, run)
