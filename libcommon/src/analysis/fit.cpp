#include "cdpile/analysis/fit.hpp"

#include "cdpile/error.hpp"

#include <Eigen/Dense>
#include <unsupported/Eigen/NonLinearOptimization>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace cdpile::analysis {

std::optional<double> FitResult::se(int k) const {
  if (cov.rows() <= k || k < 0) return std::nullopt;
  const double v = cov(k, k);
  if (!(v >= 0.0) || !std::isfinite(v)) return std::nullopt;
  return std::sqrt(v);
}

namespace {

void check_data(std::span<const double> x, std::span<const double> y, std::span<const double> s,
                std::size_t params) {
  if (x.size() != y.size()) throw Error("fit: x and y differ in length");
  if (!s.empty() && s.size() != y.size()) throw Error("fit: errors and data differ in length");
  if (x.size() < params)
    throw Error("fit: " + std::to_string(x.size()) + " points for " + std::to_string(params) +
                " parameters");
  for (std::size_t k = 0; k < x.size(); ++k) {
    if (!std::isfinite(x[k]) || !std::isfinite(y[k])) throw Error("fit: data are not finite");
    if (!s.empty() && !(s[k] > 0.0 && std::isfinite(s[k])))
      throw Error("fit: standard errors must be finite and > 0");
  }
}

const char* lm_status(Eigen::LevenbergMarquardtSpace::Status s) {
  using namespace Eigen::LevenbergMarquardtSpace;
  switch (s) {
    case ImproperInputParameters: return "improper input parameters";
    case RelativeReductionTooSmall: return "relative reduction of chi2 below tolerance";
    case RelativeErrorTooSmall: return "relative change of parameters below tolerance";
    case RelativeErrorAndReductionTooSmall: return "chi2 and parameters converged";
    case CosinusTooSmall: return "gradient orthogonal to residuals";
    case TooManyFunctionEvaluation: return "too many function evaluations";
    case FtolTooSmall: return "chi2 at machine precision";
    case XtolTooSmall: return "parameters at machine precision";
    case GtolTooSmall: return "gradient at machine precision";
    default: return "not converged";
  }
}

// Residuals (f(x_i; p) - y_i) / s_i for MINPACK's lmder.
struct Residuals {
  using Scalar = double;
  enum { InputsAtCompileTime = Eigen::Dynamic, ValuesAtCompileTime = Eigen::Dynamic };
  using InputType = Eigen::VectorXd;
  using ValueType = Eigen::VectorXd;
  using JacobianType = Eigen::MatrixXd;

  const Model* m;
  std::span<const double> x, y, s;
  int n;
  int inputs() const { return n; }
  int values() const { return static_cast<int>(x.size()); }
  double w(std::size_t i) const { return s.empty() ? 1.0 : 1.0 / s[i]; }
  int operator()(const Eigen::VectorXd& p, Eigen::VectorXd& fvec) const {
    for (std::size_t i = 0; i < x.size(); ++i) {
      const double v = (m->f(x[i], p) - y[i]) * w(i);
      fvec[static_cast<Eigen::Index>(i)] = std::isfinite(v) ? v : 1e150;
    }
    return 0;
  }
  int df(const Eigen::VectorXd& p, Eigen::MatrixXd& fjac) const {
    Eigen::VectorXd g(n);
    for (std::size_t i = 0; i < x.size(); ++i) {
      m->grad(x[i], p, g);
      for (int k = 0; k < n; ++k) {
        const double v = g[k] * w(i);
        fjac(static_cast<Eigen::Index>(i), k) = std::isfinite(v) ? v : 0.0;
      }
    }
    return 0;
  }
};

// Fills the covariance and chi2 of a result from the weighted Jacobian at the optimum.
void finish(FitResult& r, const Model& m, std::span<const double> x, std::span<const double> y,
            std::span<const double> s) {
  const int n = static_cast<int>(r.p.size());
  const auto pts = static_cast<Eigen::Index>(x.size());
  Eigen::MatrixXd j(pts, n);
  Eigen::VectorXd g(n);
  double chi2 = 0.0;
  for (Eigen::Index i = 0; i < pts; ++i) {
    const auto u = static_cast<std::size_t>(i);
    const double w = s.empty() ? 1.0 : 1.0 / s[u];
    const double res = (m.f(x[u], r.p) - y[u]) * w;
    chi2 += res * res;
    m.grad(x[u], r.p, g);
    j.row(i) = g.transpose() * w;
  }
  r.chi2 = chi2;
  r.points = static_cast<int>(pts);
  r.dof = static_cast<int>(pts) - n;
  r.weighted = !s.empty();
  r.cov.resize(0, 0);
  if (!std::isfinite(chi2) || !r.p.allFinite()) {
    r.converged = false;
    return;
  }
  if (r.dof <= 0) return;
  // cov = (J^T J)^-1 from the SVD of J with its columns scaled to unit norm: better
  // conditioned than inverting J^T J, and the rank test does not depend on the units of
  // the parameters.
  Eigen::VectorXd scale(n);
  for (int k = 0; k < n; ++k) {
    const double c = j.col(k).norm();
    scale[k] = c > 0.0 ? c : 1.0;
  }
  const Eigen::MatrixXd js = j * scale.cwiseInverse().asDiagonal();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(js, Eigen::ComputeThinV);
  const Eigen::VectorXd sv = svd.singularValues();
  if (sv.size() < n || !(sv[n - 1] > 1e-12 * sv[0])) {
    r.status += "; singular normal matrix, no uncertainties";
    return;
  }
  const Eigen::MatrixXd v = svd.matrixV();
  const Eigen::MatrixXd inv_s = v * sv.cwiseAbs2().cwiseInverse().asDiagonal() * v.transpose();
  const double red = chi2 / r.dof;
  r.cov_scale = r.weighted ? std::max(1.0, red) : red;
  r.cov = scale.cwiseInverse().asDiagonal() * inv_s * scale.cwiseInverse().asDiagonal();
  r.cov *= r.cov_scale;
  if (!r.cov.allFinite()) r.cov.resize(0, 0);
}

}  // namespace

FitResult least_squares(const Model& m, std::span<const double> x, std::span<const double> y,
                        std::span<const double> sigma, const Eigen::VectorXd& p0) {
  const auto n = static_cast<std::size_t>(p0.size());
  check_data(x, y, sigma, n);
  if (!p0.allFinite()) throw Error("fit: starting point is not finite");
  Residuals fun{&m, x, y, sigma, static_cast<int>(n)};
  Eigen::LevenbergMarquardt<Residuals> lm(fun);
  lm.parameters.maxfev = 4000;
  lm.parameters.xtol = 1e-12;
  lm.parameters.ftol = 1e-12;
  FitResult r;
  r.p = p0;
  const Eigen::LevenbergMarquardtSpace::Status st = lm.minimize(r.p);
  using namespace Eigen::LevenbergMarquardtSpace;
  r.converged = st != ImproperInputParameters && st != TooManyFunctionEvaluation &&
                st != NotStarted && st != Running && st != UserAsked;
  r.status = lm_status(st);
  finish(r, m, x, y, sigma);
  return r;
}

FitResult linear_least_squares(const std::vector<std::function<double(double)>>& basis,
                               std::span<const double> x, std::span<const double> y,
                               std::span<const double> sigma) {
  const std::size_t n = basis.size();
  check_data(x, y, sigma, n);
  const auto pts = static_cast<Eigen::Index>(x.size());
  const auto nn = static_cast<Eigen::Index>(n);
  Eigen::MatrixXd a(pts, nn);
  Eigen::VectorXd b(pts);
  for (Eigen::Index i = 0; i < pts; ++i) {
    const auto u = static_cast<std::size_t>(i);
    const double w = sigma.empty() ? 1.0 : 1.0 / sigma[u];
    for (Eigen::Index k = 0; k < nn; ++k) a(i, k) = basis[static_cast<std::size_t>(k)](x[u]) * w;
    b[i] = y[u] * w;
  }
  FitResult r;
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  if (qr.rank() < nn) throw Error("fit: the data do not determine the linear parameters");
  r.p = qr.solve(b);
  r.converged = true;
  r.status = "linear least squares (QR)";
  Model m;
  m.f = [&](double xx, const Eigen::VectorXd& p) {
    double v = 0.0;
    for (std::size_t k = 0; k < n; ++k) v += p[static_cast<Eigen::Index>(k)] * basis[k](xx);
    return v;
  };
  m.grad = [&](double xx, const Eigen::VectorXd&, Eigen::Ref<Eigen::VectorXd> g) {
    for (std::size_t k = 0; k < n; ++k) g[static_cast<Eigen::Index>(k)] = basis[k](xx);
  };
  finish(r, m, x, y, sigma);
  return r;
}

// ---------------------------------------------------------------------------------

EnvelopeFit fit_envelope(std::span<const double> theta, std::span<const double> envelope,
                         std::span<const double> sigma) {
  check_data(theta, envelope, sigma, 3);
  Model m;
  m.f = [](double t, const Eigen::VectorXd& p) { return p[0] - p[1] * std::exp(-t / p[2]); };
  m.grad = [](double t, const Eigen::VectorXd& p, Eigen::Ref<Eigen::VectorXd> g) {
    const double e = std::exp(-t / p[2]);
    g[0] = 1.0;
    g[1] = -e;
    g[2] = -p[1] * e * t / (p[2] * p[2]);
  };
  // Start: for each tau of a logarithmic scan, (nu_c, B) by linear least squares; keep the
  // best. The scan spans 1/100 to 100 times the theta range.
  double tmin = theta[0], tmax = theta[0];
  for (double t : theta) {
    tmin = std::min(tmin, t);
    tmax = std::max(tmax, t);
  }
  const double span = std::max(tmax - tmin, 1e-6);
  Eigen::VectorXd best(3);
  double best_chi2 = std::numeric_limits<double>::infinity();
  for (int k = 0; k <= 80; ++k) {
    const double tau = span * std::pow(10.0, -2.0 + 4.0 * k / 80.0);
    std::vector<std::function<double(double)>> basis = {
        [](double) { return 1.0; }, [tau](double t) { return -std::exp(-t / tau); }};
    try {
      FitResult lin = linear_least_squares(basis, theta, envelope, sigma);
      if (lin.chi2 < best_chi2) {
        best_chi2 = lin.chi2;
        best << lin.p[0], lin.p[1], tau;
      }
    } catch (const Error&) {
      continue;  // exp(-t/tau) underflows to a constant for this tau
    }
  }
  if (!std::isfinite(best_chi2)) throw Error("fit: the envelope cannot be fitted");
  EnvelopeFit out;
  out.fit = least_squares(m, theta, envelope, sigma, best);
  return out;
}

ClusterLawFit fit_cluster_law(std::span<const double> r, std::span<const double> nu_bar,
                              std::span<const double> sigma, std::optional<double> nu_inf) {
  for (double v : r)
    if (!(v > 0.0)) throw Error("fit: radii must be > 0");
  ClusterLawFit out;
  if (nu_inf) {
    if (!(*nu_inf > 0.0) || !std::isfinite(*nu_inf)) throw Error("fit: nu_inf must be > 0");
    check_data(r, nu_bar, sigma, 2);
    std::vector<double> y(r.size()), s(sigma.size());
    for (std::size_t k = 0; k < r.size(); ++k) y[k] = nu_bar[k] / *nu_inf - 1.0;
    for (std::size_t k = 0; k < sigma.size(); ++k) s[k] = sigma[k] / *nu_inf;
    Model m;
    m.f = [](double x, const Eigen::VectorXd& p) { return p[0] * std::pow(x, p[1]); };
    m.grad = [](double x, const Eigen::VectorXd& p, Eigen::Ref<Eigen::VectorXd> g) {
      const double v = std::pow(x, p[1]);
      g[0] = v;
      g[1] = p[0] * v * std::log(x);
    };
    // Start from a straight line in log-log through the positive points.
    Eigen::VectorXd p0(2);
    p0 << 1.0, -1.5;
    std::vector<double> lx, ly;
    for (std::size_t k = 0; k < r.size(); ++k)
      if (y[k] > 0.0) {
        lx.push_back(std::log(r[k]));
        ly.push_back(std::log(y[k]));
      }
    if (lx.size() >= 2) {
      try {
        FitResult line = fit_affine(lx, ly, {});
        p0 << std::exp(line.p[0]), line.p[1];
      } catch (const Error&) {
      }
    }
    out.fit = least_squares(m, r, y, s, p0);
    return out;
  }
  check_data(r, nu_bar, sigma, 3);
  Model m;
  m.f = [](double x, const Eigen::VectorXd& p) { return p[2] * (1.0 + p[0] * std::pow(x, p[1])); };
  m.grad = [](double x, const Eigen::VectorXd& p, Eigen::Ref<Eigen::VectorXd> g) {
    const double v = std::pow(x, p[1]);
    g[0] = p[2] * v;
    g[1] = p[2] * p[0] * v * std::log(x);
    g[2] = 1.0 + p[0] * v;
  };
  // Start: nu_inf from the value at the largest radius, then the fixed-nu_inf fit.
  std::size_t kmax = 0;
  for (std::size_t k = 1; k < r.size(); ++k)
    if (r[k] > r[kmax]) kmax = k;
  double ninf0 = nu_bar[kmax] > 0.0 ? nu_bar[kmax] : 1e-3;
  Eigen::VectorXd p0(3);
  p0 << 1.0, -1.5, ninf0;
  try {
    ClusterLawFit start = fit_cluster_law(r, nu_bar, sigma, ninf0);
    if (start.fit.converged) p0 << start.a(), start.alpha(), ninf0;
  } catch (const Error&) {
  }
  out.fit = least_squares(m, r, nu_bar, sigma, p0);
  return out;
}

FitResult fit_affine(std::span<const double> x, std::span<const double> y,
                     std::span<const double> sigma) {
  return linear_least_squares({[](double) { return 1.0; }, [](double v) { return v; }}, x, y,
                              sigma);
}

std::optional<ClusterSize> cluster_size(double nu_c, double nu_inf, double a, double alpha,
                                        const Eigen::Matrix2d* cov, double se_nu_c,
                                        double se_nu_inf) {
  if (!(nu_inf > 0.0) || !std::isfinite(nu_c) || !std::isfinite(a) || !std::isfinite(alpha) ||
      alpha == 0.0 || a == 0.0)
    return std::nullopt;
  const double q = nu_c / nu_inf - 1.0;
  const double ratio = q / a;
  if (!(ratio > 0.0)) return std::nullopt;
  const double log_rc = std::log(ratio) / alpha;  // eq (5)
  const double rc = std::exp(log_rc);
  if (!std::isfinite(rc) || !(rc > 0.0)) return std::nullopt;
  ClusterSize out;
  out.r_c = rc;
  // Delta method on ln r_c = (ln q - ln A) / alpha.
  Eigen::Vector2d g(-1.0 / (alpha * a), -log_rc / alpha);
  double var = 0.0;
  bool have = false;
  if (cov) {
    var += g.dot(*cov * g);
    have = true;
  }
  const double d_nuc = 1.0 / (alpha * q * nu_inf);
  const double d_nuinf = -nu_c / (alpha * q * nu_inf * nu_inf);
  if (se_nu_c > 0.0) {
    var += d_nuc * d_nuc * se_nu_c * se_nu_c;
    have = true;
  }
  if (se_nu_inf > 0.0) {
    var += d_nuinf * d_nuinf * se_nu_inf * se_nu_inf;
    have = true;
  }
  if (have && var >= 0.0 && std::isfinite(var)) out.se = rc * std::sqrt(var);
  return out;
}

DivergenceFit fit_divergence(std::span<const double> theta, std::span<const double> r_c,
                             std::span<const double> sigma, std::optional<double> theta_c) {
  for (double v : r_c)
    if (!(v > 0.0)) throw Error("fit: cluster sizes must be > 0");
  std::vector<double> y(r_c.size()), s(sigma.size());
  for (std::size_t k = 0; k < r_c.size(); ++k) y[k] = std::log(r_c[k]);
  for (std::size_t k = 0; k < sigma.size(); ++k) s[k] = sigma[k] / r_c[k];
  double tmax = -std::numeric_limits<double>::infinity(), tmin = -tmax;
  for (double t : theta) {
    tmax = std::max(tmax, t);
    tmin = std::min(tmin, t);
  }
  DivergenceFit out;
  if (theta_c) {
    if (!(*theta_c > tmax)) throw Error("fit: theta_c must exceed every fitted theta");
    check_data(theta, y, s, 2);
    const double tc = *theta_c;
    std::vector<std::function<double(double)>> basis = {
        [](double) { return 1.0; }, [tc](double t) { return -std::log(tc - t); }};
    out.fit = linear_least_squares(basis, theta, y, s);
    out.theta_c = tc;
    out.log_c = out.fit.p[0];
    out.beta = out.fit.p[1];
    out.se_log_c = out.fit.se(0);
    out.se_beta = out.fit.se(1);
    return out;
  }
  check_data(theta, y, s, 3);
  // theta_c = tmax + exp(u) keeps theta_c above the data. Start from a scan of u.
  Model m;
  m.f = [tmax](double t, const Eigen::VectorXd& p) {
    return p[0] - p[1] * std::log(tmax + std::exp(p[2]) - t);
  };
  m.grad = [tmax](double t, const Eigen::VectorXd& p, Eigen::Ref<Eigen::VectorXd> g) {
    const double d = tmax + std::exp(p[2]) - t;
    g[0] = 1.0;
    g[1] = -std::log(d);
    g[2] = -p[1] * std::exp(p[2]) / d;
  };
  const double span = std::max(tmax - tmin, 1e-6);
  Eigen::VectorXd best(3);
  double best_chi2 = std::numeric_limits<double>::infinity();
  for (int k = 0; k <= 100; ++k) {
    const double gap = span * std::pow(10.0, -3.0 + 5.0 * k / 100.0);
    const double tc = tmax + gap;
    std::vector<std::function<double(double)>> basis = {
        [](double) { return 1.0; }, [tc](double t) { return -std::log(tc - t); }};
    try {
      FitResult lin = linear_least_squares(basis, theta, y, s);
      if (lin.chi2 < best_chi2) {
        best_chi2 = lin.chi2;
        best << lin.p[0], lin.p[1], std::log(gap);
      }
    } catch (const Error&) {
      continue;
    }
  }
  if (!std::isfinite(best_chi2)) throw Error("fit: the divergence cannot be fitted");
  out.fit = least_squares(m, theta, y, s, best);
  out.theta_c_fitted = true;
  out.log_c = out.fit.p[0];
  out.beta = out.fit.p[1];
  out.theta_c = tmax + std::exp(out.fit.p[2]);
  out.se_log_c = out.fit.se(0);
  out.se_beta = out.fit.se(1);
  if (auto su = out.fit.se(2)) out.se_theta_c = std::exp(out.fit.p[2]) * *su;  // delta method
  return out;
}

}  // namespace cdpile::analysis
