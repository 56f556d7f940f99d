// Axial strain-rate strategies of a shearing stage (DESIGN §10): one
// interface, each law a small class behind it (beside the servo laws).
//
//   start(rate0) -> update(in)* -> rate()
//
// A strategy returns the axial log-strain rate [1/s, compression positive]
// for the next control tick from the state at the end of the current one.
// Laws:
//   fixed    (FixedRate)     the stage's rate on every tick (today's behaviour);
//   adaptive (AdaptiveRate, adaptive_rate.h) holds a smoothed moment index
//            at a set fraction of the quasi-static threshold I_QS.
// (The `predicted` strategy of issue 16 is `fixed` at the eq. 85 rate of the
// sample; it needs the quasi-static library and is not here yet.)
// Bad values throw std::invalid_argument naming the field; update() before
// start() throws std::logic_error. ROS-free.
#pragma once

#include <memory>
#include <string>

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
};

/// The stage's own rate, unchanged.
class FixedRate : public RateStrategy {
 public:
  const char* name() const override { return "fixed"; }
  void start(double rate0) override;
  double update(const RateInput&) override;
  double rate() const override { return rate_; }

 private:
  double rate_ = 0;
  bool started_ = false;
};

}  // namespace vt::control
