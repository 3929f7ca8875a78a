// clusterfit: eq (4) fitted per theta window, the affine fits of A(theta) and
// alpha(theta), the cluster size r_c(theta) of eq (5), and its divergence
// r_c ~ (theta_c - theta)^-beta (Fig 6).
#include "cdpile/analysis/fit.hpp"
#include "cdpile/analysis/clusterfit.hpp"

#include "cdpile/error.hpp"
#include "cdpile/fields.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace cdpile::analysis {

const char* nu_inf_name(NuInfSource s) {
  switch (s) {
    case NuInfSource::ensemble: return "ensemble";
    case NuInfSource::pile: return "pile";
    case NuInfSource::fit: return "fit";
    default: return "auto";
  }
}

namespace {
constexpr double nan = std::numeric_limits<double>::quiet_NaN();

struct Window {
  std::optional<double> theta, lo, hi;
  std::vector<double> r, nu, se;  // rows of the window, all radii
  std::optional<double> nu_pile, nu_pile_se;
};

// nu_inf from critical's ensemble table: the mean of the bins whose centre lies in
// [lo, hi), or a linear interpolation at theta when no bin does.
std::optional<std::pair<double, std::optional<double>>> ensemble_nu(const Table& ens,
                                                                    const Window& w) {
  const Column &th = ens.column("theta"), &nu = ens.column("nu"), &se = ens.column("nu_se");
  const std::size_t n = ens.rows();
  if (!w.theta) return std::nullopt;
  double sum = 0.0, sum_se2 = 0.0;
  int cnt = 0;
  bool all_se = true;
  if (w.lo && w.hi) {
    for (std::size_t k = 0; k < n; ++k) {
      auto t = th.get(k);
      auto v = nu.get(k);
      if (!t || !v || *t < *w.lo || *t >= *w.hi) continue;
      sum += *v;
      ++cnt;
      if (auto s = se.get(k))
        sum_se2 += *s * *s;
      else
        all_se = false;
    }
  }
  if (cnt > 0) {
    std::optional<double> s;
    if (all_se) s = std::sqrt(sum_se2) / cnt;
    return std::make_pair(sum / cnt, s);
  }
  // interpolate between the nearest bins around theta
  std::optional<std::size_t> below, above;
  for (std::size_t k = 0; k < n; ++k) {
    auto t = th.get(k);
    if (!t || !nu.get(k)) continue;
    if (*t <= *w.theta && (!below || *t > *th.get(*below))) below = k;
    if (*t >= *w.theta && (!above || *t < *th.get(*above))) above = k;
  }
  if (!below || !above) return std::nullopt;
  const double t0 = *th.get(*below), t1 = *th.get(*above);
  const double u = t1 > t0 ? (*w.theta - t0) / (t1 - t0) : 0.0;
  const double v = (1 - u) * *nu.get(*below) + u * *nu.get(*above);
  std::optional<double> s;
  if (se.get(*below) && se.get(*above)) s = (1 - u) * *se.get(*below) + u * *se.get(*above);
  return std::make_pair(v, s);
}

// One theta window's fit of eq (4), then its r_c (eq 5) and its place in the power law:
// a row of the table fits.
struct WindowFit {
  explicit WindowFit(const Window& window) : w(window) {}
  const Window& w;
  std::int64_t points = 0;  // radii in [r_min, L]
  bool weighted = false;
  std::optional<double> nu_inf, nu_inf_se;
  std::optional<ClusterLawFit> f;  // converged fits only
  std::optional<double> r_c, r_c_se, r_c_fit;
  bool in_power = false;
  std::optional<double> fitted(double v) const {
    return f ? std::optional<double>(v) : std::nullopt;
  }
};

using K = ColumnKind;
const ColumnSpec<WindowFit> fit_columns[] = {
    {"theta", "deg", K::real, [](const WindowFit& x) -> Cell { return x.w.theta; }},
    {"theta_lo", "deg", K::real, [](const WindowFit& x) -> Cell { return x.w.lo; }},
    {"theta_hi", "deg", K::real, [](const WindowFit& x) -> Cell { return x.w.hi; }},
    {"points", "", K::integer, [](const WindowFit& x) -> Cell { return x.points; }},
    {"weighted", "", K::integer,
     [](const WindowFit& x) -> Cell { return std::int64_t{x.weighted}; }},
    {"nu_inf", "", K::real, [](const WindowFit& x) -> Cell { return x.nu_inf; }},
    {"nu_inf_se", "", K::real, [](const WindowFit& x) -> Cell { return x.nu_inf_se; }},
    {"A", "", K::real,
     [](const WindowFit& x) -> Cell { return x.f ? x.fitted(x.f->a()) : std::nullopt; }},
    {"A_se", "", K::real,
     [](const WindowFit& x) -> Cell { return x.f ? x.f->fit.se(0) : std::nullopt; }},
    {"alpha", "", K::real,
     [](const WindowFit& x) -> Cell { return x.f ? x.fitted(x.f->alpha()) : std::nullopt; }},
    {"alpha_se", "", K::real,
     [](const WindowFit& x) -> Cell { return x.f ? x.f->fit.se(1) : std::nullopt; }},
    {"chi2", "", K::real,
     [](const WindowFit& x) -> Cell { return x.f ? x.fitted(x.f->fit.chi2) : std::nullopt; }},
    {"dof", "", K::integer,
     [](const WindowFit& x) -> Cell {
       return x.f ? x.fitted(static_cast<double>(x.f->fit.dof)) : std::nullopt;
     }},
    {"converged", "", K::integer,
     [](const WindowFit& x) -> Cell { return std::int64_t{x.f.has_value()}; }},
    {"r_c", "D", K::real, [](const WindowFit& x) -> Cell { return x.r_c; }},
    {"r_c_se", "D", K::real, [](const WindowFit& x) -> Cell { return x.r_c_se; }},
    {"r_c_fit", "D", K::real, [](const WindowFit& x) -> Cell { return x.r_c_fit; }},
    {"in_power", "", K::integer,
     [](const WindowFit& x) -> Cell { return std::int64_t{x.in_power}; }},
};

// nu_bar(r) of a window beside the fitted eq (4): a row of the table model
struct ModelRow {
  const WindowFit& fit;
  std::size_t k;    // the window's radius
  double r_min, L;  // the fitted range [D]
  double r() const { return fit.w.r[k]; }
};
const ColumnSpec<ModelRow> model_columns[] = {
    {"theta", "deg", K::real, [](const ModelRow& m) -> Cell { return m.fit.w.theta; }},
    {"r", "D", K::real, [](const ModelRow& m) -> Cell { return m.r(); }},
    {"nu_bar", "", K::real, [](const ModelRow& m) -> Cell { return m.fit.w.nu[m.k]; }},
    {"se", "", K::real, [](const ModelRow& m) -> Cell { return m.fit.w.se[m.k]; }},
    // eq (4), and nu_inf beyond L
    {"model", "", K::real,
     [](const ModelRow& m) -> Cell {
       if (!m.fit.f) return std::optional<double>();
       const double nu_inf = *m.fit.nu_inf;
       return m.r() <= m.L ? nu_inf * (1.0 + m.fit.f->a() * std::pow(m.r(), m.fit.f->alpha()))
                           : nu_inf;
     }},
    {"in_fit", "", K::integer,
     [](const ModelRow& m) -> Cell { return std::int64_t{m.r() >= m.r_min && m.r() <= m.L}; }},
};

// an affine fit of A or alpha in theta: a row of the table affine
struct AffineRow {
  const char* param;
  const FitResult& r;
};
const ColumnSpec<AffineRow> affine_columns[] = {
    {"param", "", K::text, [](const AffineRow& a) -> Cell { return std::string(a.param); }},
    {"c0", "", K::real, [](const AffineRow& a) -> Cell { return a.r.p[0]; }},
    {"c0_se", "", K::real, [](const AffineRow& a) -> Cell { return a.r.se(0); }},
    {"c1", "deg-1", K::real, [](const AffineRow& a) -> Cell { return a.r.p[1]; }},
    {"c1_se", "deg-1", K::real, [](const AffineRow& a) -> Cell { return a.r.se(1); }},
    {"chi2", "", K::real, [](const AffineRow& a) -> Cell { return a.r.chi2; }},
    {"dof", "", K::integer, [](const AffineRow& a) -> Cell { return std::int64_t{a.r.dof}; }},
    {"points", "", K::integer, [](const AffineRow& a) -> Cell { return std::int64_t{a.r.points}; }},
};

// Stage 1: eq (4) in each window, with nu_inf from its source (the fit's own for
// NuInfSource::fit); only converged fits are kept.
std::vector<WindowFit> fit_windows(const std::map<std::pair<double, double>, Window>& windows,
                                   const Table* ens, NuInfSource src,
                                   const ClusterFitOptions& opt) {
  std::vector<WindowFit> out;
  for (const auto& [key, w] : windows) {
    WindowFit wf(w);
    std::vector<double> r, y, s;
    bool all_se = true;
    for (std::size_t k = 0; k < w.r.size(); ++k) {
      if (w.r[k] < opt.r_min || w.r[k] > opt.r_max) continue;
      r.push_back(w.r[k]);
      y.push_back(w.nu[k]);
      s.push_back(w.se[k]);
      all_se = all_se && std::isfinite(w.se[k]) && w.se[k] > 0;
    }
    wf.points = static_cast<std::int64_t>(r.size());
    wf.weighted = all_se && !r.empty();
    if (src == NuInfSource::ensemble) {
      if (auto e = ensemble_nu(*ens, w)) {
        wf.nu_inf = e->first;
        wf.nu_inf_se = e->second;
      }
    } else if (src == NuInfSource::pile) {
      wf.nu_inf = w.nu_pile;
      wf.nu_inf_se = w.nu_pile_se;
    }
    const bool in_range = !w.theta || opt.theta.contains(*w.theta);
    if (in_range && static_cast<int>(r.size()) >= opt.min_points &&
        (src == NuInfSource::fit || (wf.nu_inf && *wf.nu_inf > 0))) {
      try {
        wf.f =
            fit_cluster_law(r, y, all_se ? std::span<const double>(s) : std::span<const double>(),
                            src == NuInfSource::fit ? std::nullopt : wf.nu_inf);
      } catch (const Error&) {
        wf.f.reset();
      }
    }
    if (wf.f && !wf.f->fit.converged) wf.f.reset();
    if (wf.f && src == NuInfSource::fit) {
      wf.nu_inf = wf.f->nu_inf_fitted();
      wf.nu_inf_se = wf.f->fit.se(2);
    }
    out.push_back(std::move(wf));
  }
  return out;
}

// Stage 2: the affine fits of A(theta) and alpha(theta) over the fitted windows with a
// theta (in opt.affine when given); none with fewer than 2 windows.
struct AffineFits {
  std::optional<FitResult> a, alpha;
};
AffineFits fit_affine_laws(const std::vector<WindowFit>& fits, const ClusterFitOptions& opt) {
  std::vector<double> th, a, as, al, als;
  bool a_w = true, al_w = true;
  for (const WindowFit& f : fits) {
    if (!f.f || !f.w.theta || !std::isfinite(*f.w.theta)) continue;
    const double theta = *f.w.theta;
    if (opt.affine && !opt.affine->contains(theta)) continue;
    const std::optional<double> a_se = f.f->fit.se(0), alpha_se = f.f->fit.se(1);
    th.push_back(theta);
    a.push_back(f.f->a());
    al.push_back(f.f->alpha());
    as.push_back(a_se.value_or(0.0));
    als.push_back(alpha_se.value_or(0.0));
    a_w = a_w && a_se && *a_se > 0;
    al_w = al_w && alpha_se && *alpha_se > 0;
  }
  auto affine = [&](const std::vector<double>& v, const std::vector<double>& sv,
                    bool weighted) -> std::optional<FitResult> {
    if (th.size() < 2) return std::nullopt;
    try {
      return fit_affine(th, v, weighted ? std::span<const double>(sv) : std::span<const double>());
    } catch (const Error&) {
      return std::nullopt;
    }
  };
  return {affine(a, as, a_w), affine(al, als, al_w)};
}

// Stage 3: r_c of each fitted window (eq 5), from its own A and alpha or from the affine
// laws at its theta.
void cluster_sizes(std::vector<WindowFit>& fits, double nu_c, double nu_c_se,
                   const AffineFits& laws, const ClusterFitOptions& opt) {
  for (WindowFit& f : fits) {
    if (!f.f) continue;
    const double theta = f.w.theta.value_or(nan);
    const double nu_inf_se = f.nu_inf_se.value_or(0.0);
    std::optional<ClusterSize> cs;
    if (opt.rc_from == RcFrom::window) {
      Eigen::Matrix2d cov;
      const bool has_cov = f.f->fit.cov.rows() >= 2;
      if (has_cov) cov = f.f->fit.cov.topLeftCorner<2, 2>();
      cs = cluster_size(nu_c, *f.nu_inf, f.f->a(), f.f->alpha(), has_cov ? &cov : nullptr, nu_c_se,
                        nu_inf_se);
    } else if (laws.a && laws.alpha && std::isfinite(theta)) {
      const double a = laws.a->p[0] + laws.a->p[1] * theta;
      const double al = laws.alpha->p[0] + laws.alpha->p[1] * theta;
      Eigen::Matrix2d c = Eigen::Matrix2d::Zero();
      const Eigen::Vector2d g(1.0, theta);
      if (laws.a->cov.rows() == 2) c(0, 0) = g.dot(laws.a->cov * g);
      if (laws.alpha->cov.rows() == 2) c(1, 1) = g.dot(laws.alpha->cov * g);
      cs = cluster_size(nu_c, *f.nu_inf, a, al, &c, nu_c_se, nu_inf_se);
    }
    if (!cs) continue;
    f.r_c = cs->r_c;
    f.r_c_se = cs->se;
  }
}

// Stage 4: r_c ~ (theta_c - theta)^-beta over the windows with r_c in the power range
// (Fig 6): its results and notes in p, r_c_fit and in_power in the windows.
void fit_power_law(Product& p, std::vector<WindowFit>& fits, bool have_nu_c,
                   const ClusterFitOptions& opt) {
  std::vector<double> pth, prc, pse;
  std::vector<WindowFit*> in;
  bool p_w = true;
  for (WindowFit& f : fits) {
    const double theta = f.w.theta.value_or(nan);
    if (!f.r_c || !std::isfinite(theta) || !opt.power.contains(theta)) continue;
    pth.push_back(theta);
    prc.push_back(*f.r_c);
    pse.push_back(f.r_c_se.value_or(0.0));
    p_w = p_w && f.r_c_se && *f.r_c_se > 0;
    in.push_back(&f);
  }
  const std::size_t need = opt.theta_c ? 3 : 4;
  if (pth.size() < need) {
    if (have_nu_c)
      p.omit("power-law fit not done: " + std::to_string(pth.size()) +
             " windows with r_c in the power range, need " + std::to_string(need));
    return;
  }
  try {
    DivergenceFit d = fit_divergence(
        pth, prc, p_w ? std::span<const double>(pse) : std::span<const double>(), opt.theta_c);
    // A fitted theta_c that runs onto the last angle of the range is a boundary solution,
    // not a divergence: r_c does not grow toward any theta_c in the data, and the fit
    // sends (theta_c - theta_max) to zero, with a meaningless beta and a vanishing error.
    const double theta_max = *std::max_element(pth.begin(), pth.end());
    const double theta_min = *std::min_element(pth.begin(), pth.end());
    const bool degenerate = d.fit.converged && d.theta_c_fitted &&
                            d.theta_c - theta_max <= 1e-6 * (theta_max - theta_min);
    if (degenerate) {
      p.results["power_degenerate"] = std::int64_t{1};
      p.omit(
          "power-law fit degenerate: the fitted theta_c ran onto the last angle of the "
          "power range (r_c does not grow toward a theta_c in these windows); no beta. "
          "Give " +
          field("theta_c") + ", or more runs or a wider " + field("power_from") + " range");
    } else if (d.fit.converged) {
      p.results["beta"] = d.beta;
      if (d.se_beta) p.results["beta_se"] = *d.se_beta;
      p.results["theta_c_deg"] = d.theta_c;
      if (d.se_theta_c) p.results["theta_c_se_deg"] = *d.se_theta_c;
      p.results["theta_c_fitted"] = std::int64_t{d.theta_c_fitted};
      p.results["log_c"] = d.log_c;
      if (d.se_log_c) p.results["log_c_se"] = *d.se_log_c;
      p.results["power_points"] = static_cast<std::int64_t>(pth.size());
      p.results["power_chi2"] = d.fit.chi2;
      p.results["power_dof"] = static_cast<std::int64_t>(d.fit.dof);
      p.results["power_weighted"] = std::int64_t{p_w};
      for (std::size_t k = 0; k < in.size(); ++k) {
        in[k]->in_power = true;
        in[k]->r_c_fit = std::exp(d.log_c) * std::pow(d.theta_c - pth[k], -d.beta);
      }
    } else {
      p.omit("power-law fit did not converge: " + d.fit.status);
    }
  } catch (const Error& e) {
    p.omit(std::string("power-law fit failed: ") + e.what());
  }
}
}  // namespace

Product clusterfit(const Product& cor, const Product* critical, const ClusterFitOptions& opt) {
  if (!(opt.r_min > 0.0) || !(opt.r_max > opt.r_min)) throw Error("need 0 < r_min < r_max (L)");
  if (opt.min_points < 3) throw Error("a window needs at least 3 points to fit");
  NuInfSource src = opt.nu_inf;
  if (src == NuInfSource::automatic) src = critical ? NuInfSource::ensemble : NuInfSource::pile;
  const Table* ens = nullptr;
  if (src == NuInfSource::ensemble) {
    if (!critical)
      throw Error(field("nu_inf") + " ensemble needs the critical product (" + field("nu") +
                  " FILE)");
    ens = &critical->table("ensemble");
  }
  std::optional<double> nu_c = opt.nu_c;
  double nu_c_se = opt.nu_c ? opt.nu_c_se : 0.0;
  if (!nu_c && critical) {
    nu_c = critical->result("nu_c");
    nu_c_se = critical->result("nu_c_se").value_or(0.0);
  }
  if (nu_c && !(*nu_c > 0.0 && *nu_c < 1.0)) throw Error("nu_c must be in (0, 1)");

  // Windows of the correlate product.
  const Table& wt = cor.table("windows");
  std::map<std::pair<double, double>, Window> windows;  // keyed by (lo, hi), or (0,0) without theta
  {
    const Column &th = wt.column("theta"), &lo = wt.column("theta_lo"), &hi = wt.column("theta_hi"),
                 &r = wt.column("r"), &nb = wt.column("nu_bar"), &se = wt.column("se");
    const Column* np = wt.find("nu_pile");
    const Column* nps = wt.find("nu_pile_se");
    for (std::size_t k = 0; k < wt.rows(); ++k) {
      const auto key = std::make_pair(lo.get(k).value_or(0.0), hi.get(k).value_or(0.0));
      Window& w = windows[key];
      w.theta = th.get(k);
      w.lo = lo.get(k);
      w.hi = hi.get(k);
      if (np) w.nu_pile = np->get(k);
      if (nps) w.nu_pile_se = nps->get(k);
      auto rv = r.get(k);
      auto v = nb.get(k);
      if (!rv || !v) continue;
      w.r.push_back(*rv);
      w.nu.push_back(*v);
      w.se.push_back(se.get(k).value_or(nan));
    }
  }

  Product p;
  p.kind = "clusterfit";
  p.parameters = {{"r_min_D", opt.r_min},
                  {"r_max_D", opt.r_max},
                  {"nu_inf", std::string(nu_inf_name(src))},
                  {"rc_from", std::string(opt.rc_from == RcFrom::window ? "window" : "affine")},
                  {"min_points", static_cast<std::int64_t>(opt.min_points)},
                  {"power_theta_lo_deg", opt.power.lo},
                  {"nu_c_source", std::string(opt.nu_c           ? "option"
                                              : critical && nu_c ? "critical"
                                                                 : "none")}};
  if (std::isfinite(opt.power.hi)) p.parameters["power_theta_hi_deg"] = opt.power.hi;
  if (opt.theta_c) p.parameters["theta_c_given_deg"] = *opt.theta_c;
  if (nu_c) {
    p.results["nu_c"] = *nu_c;
    if (nu_c_se > 0) p.results["nu_c_se"] = nu_c_se;
  }
  p.notes = {
      "eq (4): nu_bar(r) = nu_inf (1 + A r^alpha) for r_min <= r <= L = r_max_D, r in D; fitted "
      "per theta window by Levenberg-Marquardt (Eigen, MINPACK lmder), weighted by correlate's "
      "se when every point has one, else unweighted",
      "nu_inf: ensemble = critical's ensemble nu averaged over the window's bins (the paper's "
      "definition); pile = the mean pile nu of the window's frames; fit = free parameter. A "
      "given nu_inf's error is not propagated into A and alpha",
      "uncertainties: from the fit's covariance, (J^T W J)^-1 times max(1, chi2/dof) weighted, "
      "RSS/dof (J^T J)^-1 unweighted; no bootstrap",
      "eq (5): r_c = [(nu_c/nu_inf - 1)/A]^(1/alpha) in D; its se by linear propagation of "
      "cov(A, alpha) and of independent errors on nu_c and nu_inf; NA where undefined "
      "(nu_inf >= nu_c with A > 0, or no nu_c)",
      "affine: A(theta) = c0 + c1 theta and alpha(theta) likewise, weighted least squares",
      "power law: ln r_c = ln C - beta ln(theta_c - theta) over the power range, weighted by "
      "se(r_c)/r_c; theta_c fitted (as theta_max + exp(u)) unless given; se from the covariance "
      "(delta method for theta_c)"};

  Table& fits_t = declare_columns(
      p.add_table("fits", "eq (4) fitted in each theta window, and r_c (eq 5)"), fit_columns);
  Table& model_t = declare_columns(
      p.add_table("model", "nu_bar(r) of each window with the fitted eq (4)"), model_columns);
  Table& affine_t = declare_columns(
      p.add_table("affine", "affine fits in theta: A = c0 + c1 theta, alpha = c0 + c1 theta"),
      affine_columns);

  std::vector<WindowFit> fits = fit_windows(windows, ens, src, opt);
  const auto fitted =
      std::count_if(fits.begin(), fits.end(), [](const WindowFit& f) { return f.f.has_value(); });
  p.results["windows"] = static_cast<std::int64_t>(windows.size());
  p.results["windows_fitted"] = static_cast<std::int64_t>(fitted);
  if (fitted == 0) p.omit("no window could be fitted (too few radii, nu_inf = 0, or no data)");

  const AffineFits laws = fit_affine_laws(fits, opt);
  if (laws.a) add_row(affine_t, affine_columns, AffineRow{"A", *laws.a});
  if (laws.alpha) add_row(affine_t, affine_columns, AffineRow{"alpha", *laws.alpha});
  if (!laws.a || !laws.alpha)
    p.omit("affine fits not done: fewer than 2 fitted windows with theta");

  if (nu_c)
    cluster_sizes(fits, *nu_c, nu_c_se, laws, opt);
  else
    p.omit("r_c not computed: no nu_c (give " + field("nu_c") + ", or " + field("nu") +
           " with a critical product that has one)");
  fit_power_law(p, fits, nu_c.has_value(), opt);

  for (const WindowFit& f : fits) {
    add_row(fits_t, fit_columns, f);
    // the model curve over every radius of the window (eq 4: nu_inf beyond L)
    for (std::size_t k = 0; k < f.w.r.size(); ++k)
      add_row(model_t, model_columns, ModelRow{f, k, opt.r_min, opt.r_max});
  }
  return p;
}

}  // namespace cdpile::analysis
