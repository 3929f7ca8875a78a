/// clusterfit: eq (4) per theta window, affine A(theta) and alpha(theta), r_c (eq 5), and
/// the divergence r_c ~ (theta_c - theta)^-beta (Fig 6), from correlate's product and
/// critical's. Definitions: docs/analysis.md.
#pragma once

#include "cdpile/analysis/run_record.hpp"

#include <limits>
#include <optional>

namespace cdpile::analysis {

enum class NuInfSource {
  automatic,  ///< `ensemble` when a critical product is given, else `pile`
  ensemble,   ///< critical's ensemble mean nu(theta) over the window (the paper's definition)
  pile,       ///< the mean pile nu of the window's frames (from correlate)
  fit,        ///< a free parameter of the fit
};
const char* nu_inf_name(NuInfSource s);

enum class RcFrom { window, affine };

struct ClusterFitOptions {
  double r_min = 1.0;   ///< [D]
  double r_max = 10.0;  ///< L [D]
  NuInfSource nu_inf = NuInfSource::automatic;
  std::optional<double> nu_c;        ///< overrides the critical product's nu_c
  double nu_c_se = 0.0;              ///< its standard error, with nu_c given
  ThetaRange theta;                  ///< windows fitted
  std::optional<ThetaRange> affine;  ///< default: every fitted window
  ThetaRange power{15.0, std::numeric_limits<double>::infinity()};  ///< windows of the power law
  std::optional<double> theta_c;                                    ///< given: not fitted
  RcFrom rc_from = RcFrom::window;
  int min_points = 4;  ///< radii needed to fit a window
};

Product clusterfit(const Product& correlate, const Product* critical, const ClusterFitOptions& opt);

}  // namespace cdpile::analysis
