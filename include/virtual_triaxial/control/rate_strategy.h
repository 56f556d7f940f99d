// Axial strain-rate strategies of a shearing stage (DESIGN §10): one
// interface, each law a small class behind it (beside the servo laws).
//
//   start(rate0) -> update(in)* -> rate()
//
// A strategy returns the axial log-strain rate [1/s, compression positive]
// for the next control tick from the state at the end of the current one.
// Laws:
//   fixed    (FixedRate)     the stage's rate on every tick (today's behaviour);
//   predicted (FixedRate named "predicted") the eq. 85 rate of the sample at
//            the stage start, eps'_QS(target I_QS) / T0 (eq. 84 is linear in
//            I_QS), held; the stage judge (protocol/stage_judge.h) computes
//            that rate, one home for rig and headless;
//   adaptive (AdaptiveRate, adaptive_rate.h) holds a smoothed moment index
//            at a set fraction of the quasi-static threshold I_QS, starting
//            from the same prediction.
// Bad values throw std::invalid_argument naming the field; update() before
// start() throws std::logic_error. ROS-free.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "virtual_triaxial/control/adaptive_rate_parameters.h"

namespace vt::control {

/// The state at the end of a control tick that a rate strategy may use.
struct RateInput {
  double moment_index = 0;  ///< I_mom (eqs. 67-68) at the tick's end [1]
  double quasi_static_threshold = 1e-3;  ///< I_QS [1]
};

class RateStrategy {
 public:
  virtual ~RateStrategy() = default;
  virtual const char* name() const = 0;
  /// rate0: the first tick's rate [1/s], finite and > 0.
  virtual void start(double rate0) = 0;
  /// The rate of the next tick [1/s].
  virtual double update(const RateInput& in) = 0;
  /// The rate last returned (rate0 before any update) [1/s].
  virtual double rate() const = 0;
  /// Its memory between ticks as numbers, restored bit for bit after
  /// start() by restore_memory() (a checkpointed run, protocol/run_checkpoint.h);
  /// restore_memory() throws std::invalid_argument on a wrong length.
  virtual std::vector<double> memory() const = 0;
  virtual void restore_memory(const std::vector<double>& m) = 0;
};

/// The stage's own rate, unchanged (also `predicted`: the eq. 85 rate, held).
class FixedRate : public RateStrategy {
 public:
  /// `name`: "fixed" or "predicted" (a string literal).
  explicit FixedRate(const char* name = "fixed") : name_(name) {}
  const char* name() const override { return name_; }
  void start(double rate0) override;
  double update(const RateInput&) override;
  double rate() const override { return rate_; }
  /// The rate (1 number).
  std::vector<double> memory() const override { return {rate_}; }
  void restore_memory(const std::vector<double>& m) override;

 private:
  const char* name_;
  double rate_ = 0;
  bool started_ = false;
};

enum class RateStrategyKind { Fixed, Predicted, Adaptive };

/// Parses "fixed", "predicted", "adaptive" (exact, lower case); false if unknown.
bool parse_rate_strategy(const std::string& name, RateStrategyKind& out);
const char* to_string(RateStrategyKind kind);

/// A shearing stage's `rate:` block (config/scenes/README.md). `adaptive.t0`
/// is filled in by make_rate_strategy. For `predicted`, `adaptive.target` is
/// the fraction of I_QS the eq. 84 rate is computed for (default 1: eq. 85).
struct RateSpec {
  RateStrategyKind strategy = RateStrategyKind::Fixed;
  AdaptiveRateParameters adaptive;
};

/// The strategy of `spec` for a sample with characteristic time t0 [s].
/// Throws std::invalid_argument naming the field when `spec` is bad.
std::unique_ptr<RateStrategy> make_rate_strategy(const RateSpec& spec, double t0);

}  // namespace vt::control
