/// The fields of one frame that a view shows over the grains and the force network
/// (to-xdmf; docs/analysis.md, "Seeing the grains"): per grain the local state nu at its
/// centre, per contact row the critical flag, the mobilisation and f_n / <f_n>.
#pragma once

#include "cdpile/analysis/critical.hpp"
#include "cdpile/model.hpp"

#include <cstdint>
#include <vector>

namespace cdpile::analysis {

struct FrameFields {
  /// per grain: critical / contacts (the contacts select_contacts counts by `rule`) whose
  /// contact point is within the radius of the grain's centre; NaN where none is
  std::vector<double> nu;
  /// per contact row: 1 if is_critical with mu_wall against a wall (j < 0), else mu_grain
  std::vector<std::uint8_t> critical;
  /// per contact row: |f_t| / (mu f_n), mu as for `critical`; NaN where f_n <= 0
  std::vector<double> mobilisation;
  /// per contact row: f_n / <f_n>, the mean over the rows with f_n > 0; 0 when none has
  std::vector<double> fn_rel;
};

/// The fields of the frame of grains `g` and contact rows `c`, nu within `nu_radius` [m].
/// Throws cdpile::Error as select_contacts (a force not finite, mu or eps invalid).
FrameFields frame_fields(const Contacts& c, const Grains& g, const Friction& mu,
                         const CriticalRule& rule, double nu_radius);

/// The colour ranges of a view of frames' fields (to-xdmf's ParaView state), over all the
/// frames added: nu from 0 to its largest value, and f_n / <f_n> up to its 99th
/// percentile, so that a few strong contacts do not leave the rest of the network pale.
class ColourRanges {
 public:
  /// Takes one frame's fields into the ranges.
  void add(const FrameFields& f);
  /// The largest nu of a grain over the frames; 0 if none.
  double nu_max() const { return nu_max_; }
  /// The 99th percentile of f_n / <f_n> over the frames' contact rows; 0 if none.
  double fn_rel_high() const;

 private:
  double nu_max_ = 0;
  std::vector<double> fn_rel_;
};

}  // namespace cdpile::analysis
