/// correlate: nu_bar(theta, r) per frame and pooled in theta windows (eq 3, Fig 4), from
/// localnu's product. Definitions: docs/analysis.md.
#pragma once

#include "cdpile/analysis/run_record.hpp"

namespace cdpile::analysis {

struct CorrelateOptions {
  double window = 1.0;        ///< [deg]
  double window_start = 0.0;  ///< [deg] windows are [start + k w, start + (k+1) w)
  ThetaRange theta;           ///< frames used
  bool frame_table = true;
};

Product correlate(const Product& localnu, const CorrelateOptions& opt);

}  // namespace cdpile::analysis
