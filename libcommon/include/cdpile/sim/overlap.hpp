/// The overlaps a run makes, apart from those of the pile it starts from (docs/method.md,
/// "Warnings"): the overlap warning is about the run's own steps.
#pragma once

#include "cdpile/model.hpp"

#include <cstdint>
#include <utility>
#include <vector>

namespace cdpile::sim {

/// The pile's overlaps at the start of a run, by pair, and how far a later state goes
/// beyond them. A pile deposited with a contact stiffness keeps the overlaps its impacts
/// made (the gap term never pushes an overlap out, docs/method.md "Force selection"); they
/// are the pile's, inherited by every run of it, and say nothing about the run's step.
class OverlapGrowth {
 public:
  /// `start`: the contacts of the run's first frame (the pile's last step, or the frame a
  /// branch starts from); their gaps [m] are the baseline.
  explicit OverlapGrowth(const Contacts& start);
  /// The largest overlap in `now` beyond its pair's overlap at the start [m]: a pair that
  /// had none counts whole; 0 when no contact overlaps more than it did.
  double grown(const Contacts& now) const;

 private:
  std::vector<std::pair<std::uint64_t, double>> start_;  ///< (cd::pair_key, overlap [m]), sorted
};

}  // namespace cdpile::sim
