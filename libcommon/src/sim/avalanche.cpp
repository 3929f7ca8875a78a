// The avalanche rule (avalanche.hpp; docs/method.md, "Avalanche").
#include "cdpile/sim/avalanche.hpp"

namespace cdpile::sim {

void AvalancheDetector::update(std::int64_t step, double angle, double a) {
  if (detected) return;
  if (!analysis::avalanche_agitated(a, threshold)) {  // a NaN agitation breaks the run too
    since = -1;
    return;
  }
  if (since < 0) {
    since = step;
    since_deg = angle;
  }
  if (step - since + 1 >= hold) {
    detected = true;
    angle_deg = since_deg;
    start_step = since;
    confirmed_step = step;
  }
}

}  // namespace cdpile::sim
