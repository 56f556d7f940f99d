#include "virtual_triaxial/control/rate_strategy.h"

#include <cmath>
#include <stdexcept>

#include "virtual_triaxial/control/adaptive_rate.h"

namespace vt::control {

void FixedRate::start(double rate0) {
  if (!(std::isfinite(rate0) && rate0 > 0.0)) throw std::invalid_argument("rate0: must be finite and > 0");
  rate_ = rate0;
  started_ = true;
}

void FixedRate::restore_memory(const std::vector<double>& m) {
  if (m.size() != 1) throw std::invalid_argument("rate memory: '" + std::string(name_) + "' keeps 1 number");
  rate_ = m[0];
}

double FixedRate::update(const RateInput&) {
  if (!started_) throw std::logic_error("FixedRate::update before start");
  return rate_;
}

bool parse_rate_strategy(const std::string& name, RateStrategyKind& out) {
  if (name == "fixed") out = RateStrategyKind::Fixed;
  else if (name == "predicted") out = RateStrategyKind::Predicted;
  else if (name == "adaptive") out = RateStrategyKind::Adaptive;
  else return false;
  return true;
}

const char* to_string(RateStrategyKind kind) {
  switch (kind) {
    case RateStrategyKind::Fixed: return "fixed";
    case RateStrategyKind::Predicted: return "predicted";
    case RateStrategyKind::Adaptive: return "adaptive";
  }
  return "?";
}

std::unique_ptr<RateStrategy> make_rate_strategy(const RateSpec& spec, double t0) {
  switch (spec.strategy) {
    case RateStrategyKind::Fixed: return std::make_unique<FixedRate>("fixed");
    case RateStrategyKind::Predicted: return std::make_unique<FixedRate>("predicted");
    case RateStrategyKind::Adaptive: {
      AdaptiveRateParameters p = spec.adaptive;
      p.t0 = t0;
      return std::make_unique<AdaptiveRate>(p);
    }
  }
  throw std::invalid_argument("strategy: unknown");
}

}  // namespace vt::control
