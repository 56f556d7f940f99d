#include "virtual_triaxial/control/rate_strategy.h"

#include <cmath>
#include <stdexcept>

namespace vt::control {

void FixedRate::start(double rate0) {
  if (!(std::isfinite(rate0) && rate0 > 0.0)) throw std::invalid_argument("rate0: must be finite and > 0");
  rate_ = rate0;
  started_ = true;
}

double FixedRate::update(const RateInput&) {
  if (!started_) throw std::logic_error("FixedRate::update before start");
  return rate_;
}

}  // namespace vt::control
