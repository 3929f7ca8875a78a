/// The fits of the paper: the exponential approach of the envelope to nu_c (Fig 1c), the
/// cluster law nu_bar = nu_inf (1 + A r^alpha) (eq 4, Fig 4b), affine fits of A and alpha
/// in theta, the cluster size r_c (eq 5) and its power-law divergence (Fig 6).
///
/// Nonlinear least squares use Eigen's Levenberg-Marquardt (MINPACK's lmder, in
/// unsupported/Eigen/NonLinearOptimization) with analytic Jacobians.
///
/// Uncertainties come from the fit's covariance at the optimum:
///   weighted fit (every point has a standard error s_i > 0): C = (J^T W J)^-1, W = 1/s_i^2,
///     multiplied by chi^2/dof when that exceeds 1 (scatter larger than the errors say);
///   unweighted fit: C = (RSS/dof) (J^T J)^-1.
/// With dof = 0 (as many points as parameters) no uncertainty is given.
#pragma once

#include <Eigen/Core>

#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace cdpile::analysis {

struct FitResult {
  Eigen::VectorXd p;    ///< best parameters
  Eigen::MatrixXd cov;  ///< covariance (empty when dof = 0)
  double chi2 = 0.0;    ///< weighted sum of squared residuals (RSS if unweighted)
  int points = 0, dof = 0;
  bool weighted = false;
  bool converged = false;
  double cov_scale = 1.0;  ///< factor applied to (J^T W J)^-1
  std::string status;      ///< the solver's stopping reason
  /// Standard error of parameter k, empty when no covariance.
  std::optional<double> se(int k) const;
};

/// A model y = f(x; p) with its gradient in p.
struct Model {
  std::function<double(double x, const Eigen::VectorXd& p)> f;
  std::function<void(double x, const Eigen::VectorXd& p, Eigen::Ref<Eigen::VectorXd> grad)> grad;
};

/// Weighted (sigma non-empty, all > 0) or unweighted (sigma empty) nonlinear least squares
/// from p0. Throws cdpile::Error when there are fewer points than parameters or the data
/// are not finite; a fit that does not converge returns converged = false.
FitResult least_squares(const Model& m, std::span<const double> x, std::span<const double> y,
                        std::span<const double> sigma, const Eigen::VectorXd& p0);

/// Linear weighted least squares y = sum_k p_k g_k(x) (e.g. affine: g = {1, x}).
FitResult linear_least_squares(const std::vector<std::function<double(double)>>& basis,
                               std::span<const double> x, std::span<const double> y,
                               std::span<const double> sigma);

// ---------------------------------------------------------------------------------

/// Fig 1c: envelope(theta) = nu_c - B exp(-theta / tau). p = (nu_c, B, tau).
struct EnvelopeFit {
  FitResult fit;
  double nu_c() const { return fit.p[0]; }
  double b() const { return fit.p[1]; }
  double tau() const { return fit.p[2]; }
};
/// Starts from a scan of tau (the model is linear in nu_c and B for a fixed tau).
EnvelopeFit fit_envelope(std::span<const double> theta, std::span<const double> envelope,
                         std::span<const double> sigma);

/// Eq (4) for r <= L: nu_bar(r) = nu_inf (1 + A r^alpha), r in units of D.
/// With nu_inf given, p = (A, alpha) and the fit is on nu_bar/nu_inf - 1 with errors
/// se/nu_inf (nu_inf's own error is not propagated into A and alpha); with nu_inf free,
/// p = (A, alpha, nu_inf).
struct ClusterLawFit {
  FitResult fit;
  double a() const { return fit.p[0]; }
  double alpha() const { return fit.p[1]; }
  std::optional<double> nu_inf_fitted() const {
    return fit.p.size() > 2 ? std::optional<double>(fit.p[2]) : std::nullopt;
  }
};
ClusterLawFit fit_cluster_law(std::span<const double> r, std::span<const double> nu_bar,
                              std::span<const double> sigma, std::optional<double> nu_inf);

/// A straight line y = c0 + c1 x, weighted when sigma is given.
FitResult fit_affine(std::span<const double> x, std::span<const double> y,
                     std::span<const double> sigma);

/// Eq (5): r_c = [(nu_c/nu_inf - 1)/A]^(1/alpha), with its standard error by linear
/// propagation (delta method) of the covariance of (A, alpha) and of independent errors
/// on nu_c and nu_inf. Empty when r_c is not defined: (nu_c/nu_inf - 1)/A <= 0 or
/// alpha = 0.
struct ClusterSize {
  double r_c = 0.0;
  std::optional<double> se;
};
std::optional<ClusterSize> cluster_size(double nu_c, double nu_inf, double a, double alpha,
                                        const Eigen::Matrix2d* cov_a_alpha = nullptr,
                                        double se_nu_c = 0.0, double se_nu_inf = 0.0);

/// Fig 6: r_c(theta) = C (theta_c - theta)^(-beta), fitted on ln r_c with errors
/// se(r_c)/r_c (unweighted without errors). theta_c is fitted (kept above the largest
/// theta by fitting ln(theta_c - max theta)) unless given. p = (ln C, beta, theta_c).
struct DivergenceFit {
  FitResult fit;  ///< parameters (ln C, beta[, s = ln(theta_c - theta_max)])
  double beta = 0.0, theta_c = 0.0, log_c = 0.0;
  std::optional<double> se_beta, se_theta_c, se_log_c;
  bool theta_c_fitted = false;
};
DivergenceFit fit_divergence(std::span<const double> theta, std::span<const double> r_c,
                             std::span<const double> sigma, std::optional<double> theta_c);

}  // namespace cdpile::analysis
