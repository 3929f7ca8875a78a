// clusterfit: eq (4) fitted per theta window, the affine fits of A(theta) and
// alpha(theta), the cluster size r_c(theta) of eq (5), and its divergence
// r_c ~ (theta_c - theta)^-beta (Fig 6).
#include "cdpile/analysis/fit.hpp"
#include "cdpile/analysis/studies.hpp"

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

  Table& fits = p.add_table("fits", "eq (4) fitted in each theta window, and r_c (eq 5)");
  for (auto [n, u, k] : std::initializer_list<std::tuple<const char*, const char*, ColumnKind>>{
           {"theta", "deg", ColumnKind::real},
           {"theta_lo", "deg", ColumnKind::real},
           {"theta_hi", "deg", ColumnKind::real},
           {"points", "", ColumnKind::integer},
           {"weighted", "", ColumnKind::integer},
           {"nu_inf", "", ColumnKind::real},
           {"nu_inf_se", "", ColumnKind::real},
           {"A", "", ColumnKind::real},
           {"A_se", "", ColumnKind::real},
           {"alpha", "", ColumnKind::real},
           {"alpha_se", "", ColumnKind::real},
           {"chi2", "", ColumnKind::real},
           {"dof", "", ColumnKind::integer},
           {"converged", "", ColumnKind::integer},
           {"r_c", "D", ColumnKind::real},
           {"r_c_se", "D", ColumnKind::real},
           {"r_c_fit", "D", ColumnKind::real},
           {"in_power", "", ColumnKind::integer}})
    fits.add_column(n, u, k);
  Table& model = p.add_table("model", "nu_bar(r) of each window with the fitted eq (4)");
  for (auto [n, u, k] : std::initializer_list<std::tuple<const char*, const char*, ColumnKind>>{
           {"theta", "deg", ColumnKind::real},
           {"r", "D", ColumnKind::real},
           {"nu_bar", "", ColumnKind::real},
           {"se", "", ColumnKind::real},
           {"model", "", ColumnKind::real},
           {"in_fit", "", ColumnKind::integer}})
    model.add_column(n, u, k);

  struct Fitted {
    double theta, a, alpha, nu_inf;
    std::optional<double> a_se, alpha_se, nu_inf_se;
    Eigen::Matrix2d cov;
    bool has_cov = false;
    std::size_t row;
  };
  std::vector<Fitted> fitted;
  std::int64_t skipped = 0;

  for (const auto& [key, w] : windows) {
    const std::size_t row = fits.column("theta").num.size();
    std::vector<double> r, y, s;
    bool all_se = true;
    for (std::size_t k = 0; k < w.r.size(); ++k) {
      if (w.r[k] < opt.r_min || w.r[k] > opt.r_max) continue;
      r.push_back(w.r[k]);
      y.push_back(w.nu[k]);
      s.push_back(w.se[k]);
      all_se = all_se && std::isfinite(w.se[k]) && w.se[k] > 0;
    }
    std::optional<double> nu_inf, nu_inf_se;
    if (src == NuInfSource::ensemble) {
      if (auto e = ensemble_nu(*ens, w)) {
        nu_inf = e->first;
        nu_inf_se = e->second;
      }
    } else if (src == NuInfSource::pile) {
      nu_inf = w.nu_pile;
      nu_inf_se = w.nu_pile_se;
    }
    const bool in_range = !w.theta || opt.theta.contains(*w.theta);
    std::optional<ClusterLawFit> f;
    if (in_range && static_cast<int>(r.size()) >= opt.min_points &&
        (src == NuInfSource::fit || (nu_inf && *nu_inf > 0))) {
      try {
        f = fit_cluster_law(r, y, all_se ? std::span<const double>(s) : std::span<const double>(),
                            src == NuInfSource::fit ? std::nullopt : nu_inf);
      } catch (const Error&) {
        f.reset();
      }
    }
    if (!f || !f->fit.converged) ++skipped;
    const bool ok = f && f->fit.converged;
    if (ok && src == NuInfSource::fit) {
      nu_inf = f->nu_inf_fitted();
      nu_inf_se = f->fit.se(2);
    }
    fits.column("theta").add(w.theta);
    fits.column("theta_lo").add(w.lo);
    fits.column("theta_hi").add(w.hi);
    fits.column("points").add_int(static_cast<std::int64_t>(r.size()));
    fits.column("weighted").add_int(all_se && !r.empty());
    fits.column("nu_inf").add(nu_inf);
    fits.column("nu_inf_se").add(nu_inf_se);
    fits.column("A").add(ok ? std::optional<double>(f->a()) : std::nullopt);
    fits.column("A_se").add(ok ? f->fit.se(0) : std::nullopt);
    fits.column("alpha").add(ok ? std::optional<double>(f->alpha()) : std::nullopt);
    fits.column("alpha_se").add(ok ? f->fit.se(1) : std::nullopt);
    fits.column("chi2").add(ok ? std::optional<double>(f->fit.chi2) : std::nullopt);
    fits.column("dof").add(ok ? static_cast<double>(f->fit.dof) : nan);
    fits.column("converged").add_int(ok);
    if (ok) {
      Fitted ft;
      ft.theta = w.theta.value_or(nan);
      ft.a = f->a();
      ft.alpha = f->alpha();
      ft.nu_inf = *nu_inf;
      ft.a_se = f->fit.se(0);
      ft.alpha_se = f->fit.se(1);
      ft.nu_inf_se = nu_inf_se;
      if (f->fit.cov.rows() >= 2) {
        ft.cov = f->fit.cov.topLeftCorner<2, 2>();
        ft.has_cov = true;
      }
      ft.row = row;
      fitted.push_back(ft);
    }
    // the model curve over every radius of the window (eq 4: nu_inf beyond L)
    for (std::size_t k = 0; k < w.r.size(); ++k) {
      model.column("theta").add(w.theta);
      model.column("r").add(w.r[k]);
      model.column("nu_bar").add(w.nu[k]);
      model.column("se").add(std::isfinite(w.se[k]) ? std::optional<double>(w.se[k])
                                                    : std::nullopt);
      const bool in = w.r[k] >= opt.r_min && w.r[k] <= opt.r_max;
      std::optional<double> m;
      if (ok)
        m = w.r[k] <= opt.r_max ? *nu_inf * (1.0 + f->a() * std::pow(w.r[k], f->alpha())) : *nu_inf;
      model.column("model").add(m);
      model.column("in_fit").add_int(in);
    }
  }
  p.results["windows"] = static_cast<std::int64_t>(windows.size());
  p.results["windows_fitted"] = static_cast<std::int64_t>(fitted.size());
  if (fitted.empty()) p.omit("no window could be fitted (too few radii, nu_inf = 0, or no data)");

  // Affine fits of A and alpha in theta.
  Table& aff =
      p.add_table("affine", "affine fits in theta: A = c0 + c1 theta, alpha = c0 + c1 theta");
  aff.add_column("param", "", ColumnKind::text);
  for (const char* n : {"c0", "c0_se", "c1", "c1_se", "chi2"})
    aff.add_column(n, n[1] == '1' ? "deg-1" : "");
  aff.add_column("dof", "", ColumnKind::integer);
  aff.add_column("points", "", ColumnKind::integer);
  std::optional<FitResult> fit_a, fit_alpha;
  {
    std::vector<double> th, a, as, al, als;
    bool a_w = true, al_w = true;
    for (const Fitted& f : fitted) {
      if (!std::isfinite(f.theta)) continue;
      if (opt.affine && !opt.affine->contains(f.theta)) continue;
      th.push_back(f.theta);
      a.push_back(f.a);
      al.push_back(f.alpha);
      as.push_back(f.a_se.value_or(0.0));
      als.push_back(f.alpha_se.value_or(0.0));
      a_w = a_w && f.a_se && *f.a_se > 0;
      al_w = al_w && f.alpha_se && *f.alpha_se > 0;
    }
    auto affine = [&](const char* name, const std::vector<double>& v, const std::vector<double>& sv,
                      bool weighted) -> std::optional<FitResult> {
      if (th.size() < 2) return std::nullopt;
      try {
        FitResult r =
            fit_affine(th, v, weighted ? std::span<const double>(sv) : std::span<const double>());
        aff.column("param").add_text(name);
        aff.column("c0").add(r.p[0]);
        aff.column("c0_se").add(r.se(0));
        aff.column("c1").add(r.p[1]);
        aff.column("c1_se").add(r.se(1));
        aff.column("chi2").add(r.chi2);
        aff.column("dof").add_int(r.dof);
        aff.column("points").add_int(r.points);
        return r;
      } catch (const Error&) {
        return std::nullopt;
      }
    };
    fit_a = affine("A", a, as, a_w);
    fit_alpha = affine("alpha", al, als, al_w);
    if (!fit_a || !fit_alpha)
      p.omit("affine fits not done: fewer than 2 fitted windows with theta");
  }

  // r_c (eq 5) per window.
  Column& rc_col = fits.column("r_c");
  Column& rcse_col = fits.column("r_c_se");
  const std::size_t nrows = fits.column("theta").num.size();
  rc_col.num.assign(nrows, nan);
  rcse_col.num.assign(nrows, nan);
  fits.column("r_c_fit").num.assign(nrows, nan);
  fits.column("in_power").num.assign(nrows, 0.0);
  if (!nu_c)
    p.omit("r_c not computed: no nu_c (give " + field("nu_c") + ", or " + field("nu") +
           " with a critical product that has one)");
  std::vector<double> pth, prc, pse;
  std::vector<std::size_t> prow;
  bool p_w = true;
  if (nu_c) {
    for (const Fitted& f : fitted) {
      std::optional<ClusterSize> cs;
      if (opt.rc_from == RcFrom::window) {
        cs = cluster_size(*nu_c, f.nu_inf, f.a, f.alpha, f.has_cov ? &f.cov : nullptr, nu_c_se,
                          f.nu_inf_se.value_or(0.0));
      } else if (fit_a && fit_alpha && std::isfinite(f.theta)) {
        const double a = fit_a->p[0] + fit_a->p[1] * f.theta;
        const double al = fit_alpha->p[0] + fit_alpha->p[1] * f.theta;
        Eigen::Matrix2d c = Eigen::Matrix2d::Zero();
        const Eigen::Vector2d g(1.0, f.theta);
        if (fit_a->cov.rows() == 2) c(0, 0) = g.dot(fit_a->cov * g);
        if (fit_alpha->cov.rows() == 2) c(1, 1) = g.dot(fit_alpha->cov * g);
        cs = cluster_size(*nu_c, f.nu_inf, a, al, &c, nu_c_se, f.nu_inf_se.value_or(0.0));
      }
      if (!cs) continue;
      rc_col.num[f.row] = cs->r_c;
      if (cs->se) rcse_col.num[f.row] = *cs->se;
      if (std::isfinite(f.theta) && opt.power.contains(f.theta)) {
        pth.push_back(f.theta);
        prc.push_back(cs->r_c);
        pse.push_back(cs->se.value_or(0.0));
        p_w = p_w && cs->se && *cs->se > 0;
        prow.push_back(f.row);
      }
    }
  }
  const std::size_t need = opt.theta_c ? 3 : 4;
  if (pth.size() >= need) {
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
        for (std::size_t k = 0; k < prow.size(); ++k) {
          fits.column("in_power").num[prow[k]] = 1.0;
          fits.column("r_c_fit").num[prow[k]] =
              std::exp(d.log_c) * std::pow(d.theta_c - pth[k], -d.beta);
        }
      } else if (!d.fit.converged) {
        p.omit("power-law fit did not converge: " + d.fit.status);
      }
    } catch (const Error& e) {
      p.omit(std::string("power-law fit failed: ") + e.what());
    }
  } else if (nu_c) {
    p.omit("power-law fit not done: " + std::to_string(pth.size()) +
           " windows with r_c in the power range, need " + std::to_string(need));
  }
  return p;
}

}  // namespace cdpile::analysis
