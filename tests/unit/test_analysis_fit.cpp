// The fits recover known parameters from synthetic data within their stated
// uncertainties, and the uncertainties are honest (coverage close to 68 %).
#include "cdpile/analysis/fit.hpp"
#include "cdpile/error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace cdpile;
using namespace cdpile::analysis;

TEST(Fit, AffineExact) {
  std::vector<double> x = {0, 1, 2, 3}, y = {1, 3, 5, 7};
  FitResult f = fit_affine(x, y, {});
  EXPECT_NEAR(f.p[0], 1.0, 1e-12);
  EXPECT_NEAR(f.p[1], 2.0, 1e-12);
  EXPECT_NEAR(f.chi2, 0.0, 1e-20);
  EXPECT_EQ(f.dof, 2);
  // weighted, with an exact line, the covariance is (J^T W J)^-1 (chi2/dof < 1)
  std::vector<double> s = {0.1, 0.1, 0.1, 0.1};
  FitResult g = fit_affine(x, y, s);
  // var(intercept) = s^2 sum x^2 / (n sum x^2 - (sum x)^2) = 0.01 * 14 / 20
  EXPECT_NEAR(*g.se(0), std::sqrt(0.01 * 14.0 / 20.0), 1e-12);
  EXPECT_NEAR(*g.se(1), std::sqrt(0.01 * 4.0 / 20.0), 1e-12);
}

TEST(Fit, TooFewPointsOrBadDataIsAnError) {
  std::vector<double> x = {1.0}, y = {1.0};
  EXPECT_THROW(fit_affine(x, y, {}), Error);
  std::vector<double> x2 = {1.0, 2.0, 3.0}, y2 = {1.0, NAN, 2.0};
  EXPECT_THROW(fit_affine(x2, y2, {}), Error);
  std::vector<double> y3 = {1.0, 2.0, 3.0}, s3 = {1.0, 0.0, 1.0};
  EXPECT_THROW(fit_affine(x2, y3, s3), Error);
  // two points, two parameters: exact, no uncertainty
  std::vector<double> x4 = {0.0, 1.0}, y4 = {0.0, 1.0};
  FitResult f = fit_affine(x4, y4, {});
  EXPECT_EQ(f.dof, 0);
  EXPECT_FALSE(f.se(0));
}

namespace {
// Synthetic nu_bar following eq (4) with Gaussian noise of known standard error.
struct ClusterData {
  std::vector<double> r, nu, se;
};
ClusterData cluster_data(double nu_inf, double a, double alpha, double noise, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  ClusterData d;
  for (double r = 1.0; r <= 10.0 + 1e-9; r += 0.5) {
    const double s = noise * (1.0 + 1.0 / r);
    d.r.push_back(r);
    d.nu.push_back(nu_inf * (1.0 + a * std::pow(r, alpha)) + s * g(rng));
    d.se.push_back(s);
  }
  return d;
}
}  // namespace

TEST(Fit, ClusterLawRecoversAAndAlpha) {
  const double nu_inf = 0.05, a = 2.0, alpha = -1.5;
  ClusterData d = cluster_data(nu_inf, a, alpha, 0.002, 7);
  ClusterLawFit f = fit_cluster_law(d.r, d.nu, d.se, nu_inf);
  ASSERT_TRUE(f.fit.converged) << f.fit.status;
  ASSERT_TRUE(f.fit.se(0) && f.fit.se(1));
  EXPECT_LT(std::abs(f.a() - a), 3.0 * *f.fit.se(0));
  EXPECT_LT(std::abs(f.alpha() - alpha), 3.0 * *f.fit.se(1));
  EXPECT_LT(*f.fit.se(1), 0.2);  // the data determine alpha well

  ClusterLawFit g = fit_cluster_law(d.r, d.nu, d.se, std::nullopt);
  ASSERT_TRUE(g.fit.converged) << g.fit.status;
  ASSERT_TRUE(g.nu_inf_fitted());
  EXPECT_LT(std::abs(*g.nu_inf_fitted() - nu_inf), 3.0 * *g.fit.se(2));
  EXPECT_LT(std::abs(g.alpha() - alpha), 3.0 * *g.fit.se(1));
}

TEST(Fit, ClusterLawUncertaintyIsHonest) {
  // Over many noise realisations, |alpha_hat - alpha| < se in about 68 % of the fits.
  const double nu_inf = 0.05, a = 2.0, alpha = -1.5;
  int inside_a = 0, inside_alpha = 0, total = 0;
  for (unsigned seed = 1; seed <= 300; ++seed) {
    ClusterData d = cluster_data(nu_inf, a, alpha, 0.002, seed);
    ClusterLawFit f = fit_cluster_law(d.r, d.nu, d.se, nu_inf);
    if (!f.fit.converged || !f.fit.se(1)) continue;
    ++total;
    inside_a += std::abs(f.a() - a) < *f.fit.se(0);
    inside_alpha += std::abs(f.alpha() - alpha) < *f.fit.se(1);
  }
  ASSERT_GE(total, 295);
  EXPECT_NEAR(inside_a / double(total), 0.70, 0.08);
  EXPECT_NEAR(inside_alpha / double(total), 0.70, 0.08);
}

TEST(Fit, EnvelopeExponentialApproach) {
  const double nu_c = 0.08, b = 0.07, tau = 5.0;
  std::mt19937_64 rng(3);
  std::normal_distribution<double> g(0.0, 1.0);
  int inside = 0, total = 0;
  for (int rep = 0; rep < 200; ++rep) {
    std::vector<double> th, env, se;
    for (double t = 0.25; t < 20.0; t += 0.5) {
      th.push_back(t);
      env.push_back(nu_c - b * std::exp(-t / tau) + 0.002 * g(rng));
      se.push_back(0.002);
    }
    EnvelopeFit f = fit_envelope(th, env, se);
    ASSERT_TRUE(f.fit.converged) << f.fit.status;
    ASSERT_TRUE(f.fit.se(0));
    if (rep == 0) {
      EXPECT_LT(std::abs(f.nu_c() - nu_c), 3 * *f.fit.se(0));
      EXPECT_LT(std::abs(f.tau() - tau), 3 * *f.fit.se(2));
    }
    ++total;
    inside += std::abs(f.nu_c() - nu_c) < *f.fit.se(0);
  }
  EXPECT_NEAR(inside / double(total), 0.70, 0.09);
}

TEST(Fit, ClusterSizeEq5AndItsError) {
  // r_c = [(0.08/0.05 - 1)/2]^(1/-1.5) = 0.3^(-2/3)
  auto rc = cluster_size(0.08, 0.05, 2.0, -1.5);
  ASSERT_TRUE(rc);
  EXPECT_NEAR(rc->r_c, std::pow(0.3, -2.0 / 3.0), 1e-12);
  EXPECT_FALSE(rc->se);
  EXPECT_FALSE(cluster_size(0.05, 0.08, 2.0, -1.5));  // nu_inf > nu_c with A > 0: undefined
  EXPECT_FALSE(cluster_size(0.08, 0.05, 2.0, 0.0));
  EXPECT_FALSE(cluster_size(0.08, 0.0, 2.0, -1.5));
  // the delta-method error against finite differences
  Eigen::Matrix2d cov;
  cov << 0.04, 0.001, 0.001, 0.01;
  auto e = cluster_size(0.08, 0.05, 2.0, -1.5, &cov, 0.002, 0.001);
  ASSERT_TRUE(e && e->se);
  auto f = [](double nc, double ni, double a, double al) {
    return std::pow((nc / ni - 1.0) / a, 1.0 / al);
  };
  const double h = 1e-7;
  const double ga = (f(0.08, 0.05, 2 + h, -1.5) - f(0.08, 0.05, 2 - h, -1.5)) / (2 * h);
  const double gl = (f(0.08, 0.05, 2, -1.5 + h) - f(0.08, 0.05, 2, -1.5 - h)) / (2 * h);
  const double gc = (f(0.08 + h, 0.05, 2, -1.5) - f(0.08 - h, 0.05, 2, -1.5)) / (2 * h);
  const double gi = (f(0.08, 0.05 + h, 2, -1.5) - f(0.08, 0.05 - h, 2, -1.5)) / (2 * h);
  const double var = ga * ga * 0.04 + 2 * ga * gl * 0.001 + gl * gl * 0.01 +
                     gc * gc * 0.002 * 0.002 + gi * gi * 0.001 * 0.001;
  EXPECT_NEAR(*e->se, std::sqrt(var), 1e-6 * std::sqrt(var));
}

namespace {
struct RcData {
  std::vector<double> th, rc, se;
};
RcData rc_data(double theta_c, double beta, double c, double rel, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  RcData d;
  for (double t = 15.0; t <= 19.5 + 1e-9; t += 0.25) {
    d.th.push_back(t);
    d.rc.push_back(c * std::pow(theta_c - t, -beta) * std::exp(rel * g(rng)));
    d.se.push_back(rel * d.rc.back());
  }
  return d;
}
}  // namespace

TEST(Fit, DivergenceRecoversBetaAndThetaC) {
  const double theta_c = 19.96, beta = 0.5, c = 6.0;
  RcData d = rc_data(theta_c, beta, c, 0.03, 11);
  DivergenceFit f = fit_divergence(d.th, d.rc, d.se, std::nullopt);
  ASSERT_TRUE(f.fit.converged) << f.fit.status;
  ASSERT_TRUE(f.se_beta && f.se_theta_c);
  EXPECT_TRUE(f.theta_c_fitted);
  EXPECT_LT(std::abs(f.beta - beta), 3 * *f.se_beta);
  EXPECT_LT(std::abs(f.theta_c - theta_c), 3 * *f.se_theta_c);
  EXPECT_GT(f.theta_c, 19.5);

  DivergenceFit g = fit_divergence(d.th, d.rc, d.se, theta_c);
  ASSERT_TRUE(g.se_beta);
  EXPECT_FALSE(g.theta_c_fitted);
  EXPECT_LT(std::abs(g.beta - beta), 3 * *g.se_beta);
  EXPECT_LT(*g.se_beta, *f.se_beta);                            // knowing theta_c pins beta better
  EXPECT_THROW(fit_divergence(d.th, d.rc, d.se, 19.0), Error);  // theta_c inside the data
}

TEST(Fit, DivergenceUncertaintyIsHonest) {
  const double theta_c = 19.96, beta = 0.5, c = 6.0;
  int in_beta = 0, in_tc = 0, total = 0;
  for (unsigned seed = 100; seed < 400; ++seed) {
    RcData d = rc_data(theta_c, beta, c, 0.03, seed);
    DivergenceFit f = fit_divergence(d.th, d.rc, d.se, std::nullopt);
    if (!f.fit.converged || !f.se_beta || !f.se_theta_c) continue;
    ++total;
    in_beta += std::abs(f.beta - beta) < *f.se_beta;
    in_tc += std::abs(f.theta_c - theta_c) < *f.se_theta_c;
  }
  ASSERT_GE(total, 290);
  EXPECT_NEAR(in_beta / double(total), 0.70, 0.1);
  EXPECT_NEAR(in_tc / double(total), 0.70, 0.1);
}
