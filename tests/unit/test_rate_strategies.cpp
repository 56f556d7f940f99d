// Rate strategies (control/rate_strategy.h, adaptive_rate.h) on a model of
// the specimen's moment index (no DEM): I = C(t) (eps')^k, with C rising
// 3-fold over the run (the index grows towards the peak), a sensitivity
// k = 0.8 that differs from the law's assumed 0.85, a first-order lag of 10
// ticks between the rate and the index, and +-15 % tick-to-tick noise.
//   - fixed: the rate never changes;
//   - adaptive: after 300 settling ticks the smoothed index stays within
//     +-10 % of target x I_QS to the end, the rate within [eps'_min,
//     eps'_max], no change per tick beyond max_change; it speeds a run up
//     from a slow start and slows it when the index rises; bounds hold when
//     the target is out of reach;
//   - bad parameters name the field.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "virtual_triaxial/control/adaptive_rate.h"

using namespace vt::control;

namespace {

constexpr double kT0 = 3e-7;    // [s]
constexpr double kIqs = 1e-3;   // I_QS

struct Plant {  // I_mom of a specimen sheared at eps' (see above)
  double index = 0;
  std::uint64_t seed = 12345;
  double noise() {
    seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(seed >> 11) / 9007199254740992.0 * 2.0 - 1.0;  // [-1, 1)
  }
  double tick(double eps_rate, double c) {
    const double steady = c * std::pow(eps_rate, 0.8);
    index += (steady - index) / 10.0;
    return index * (1.0 + 0.15 * noise());
  }
};

AdaptiveRateParameters params() {
  AdaptiveRateParameters p;
  p.target = 0.7;
  p.min_dimensionless = 1e-9;
  p.max_dimensionless = 1e-5;
  p.max_change = 0.02;
  p.smoothing_ticks = 20;
  p.t0 = kT0;
  return p;
}

}  // namespace

TEST(FixedRate, NeverChanges) {
  FixedRate f;
  EXPECT_THROW(f.update({}), std::logic_error);
  f.start(2.5);
  for (double i : {0.0, 1e-4, 1.0}) EXPECT_EQ(f.update({i, kIqs}), 2.5);
  EXPECT_STREQ(f.name(), "fixed");
}

TEST(AdaptiveRate, HoldsTheIndexInItsBandThroughARisingIndex) {
  // C such that eps' = 1e-7 gives I = I_QS at the start; 3x by the end
  const double c0 = kIqs / std::pow(1e-7, 0.8);
  AdaptiveRate a(params());
  a.start(1e-8 / kT0);  // a slow start (10x below)
  Plant plant;
  const int n = 3000;
  double prev = a.rate(), worst = 0;
  for (int k = 0; k < n; ++k) {
    const double c = c0 * (1.0 + 2.0 * k / n);
    const double r = a.update({plant.tick(a.rate() * kT0, c), kIqs});
    ASSERT_GE(r * kT0, 1e-9 * (1 - 1e-12));
    ASSERT_LE(r * kT0, 1e-5 * (1 + 1e-12));
    ASSERT_LE(std::max(r / prev, prev / r), 1.02 * (1 + 1e-12)) << k;
    prev = r;
    if (k >= 300) worst = std::max(worst, std::fabs(a.smoothed_index() / (0.7 * kIqs) - 1.0));
  }
  EXPECT_LT(worst, 0.1) << "the smoothed index left its band";
  // the index tripled: the rate fell by about 3^(1/0.8) = 3.95 from its level at the start of the rise
  const double expected_end = 1e-7 * std::pow(0.7 / 3.0, 1 / 0.8);
  EXPECT_NEAR(a.rate() * kT0 / expected_end, 1.0, 0.2);
}

TEST(AdaptiveRate, StaysWithinItsBoundsWhenTheTargetIsOutOfReach) {
  AdaptiveRateParameters p = params();
  AdaptiveRate a(p);
  a.start(1e-7 / kT0);
  for (int k = 0; k < 2000; ++k) a.update({0.0, kIqs});  // no index at all: rises to eps'_max
  EXPECT_DOUBLE_EQ(a.rate() * kT0, 1e-5);
  for (int k = 0; k < 2000; ++k) a.update({1.0, kIqs});  // far above: falls to eps'_min
  EXPECT_DOUBLE_EQ(a.rate() * kT0, 1e-9);
}

TEST(AdaptiveRate, BadParametersNameTheField) {
  auto field = [](AdaptiveRateParameters p) {
    try {
      AdaptiveRate a(p);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  AdaptiveRateParameters p = params();
  p.target = 1.5;
  EXPECT_EQ(field(p).rfind("target:", 0), 0u) << field(p);
  p = params();
  p.max_dimensionless = 1e-10;
  EXPECT_EQ(field(p).rfind("max:", 0), 0u) << field(p);
  p = params();
  p.max_change = 0;
  EXPECT_EQ(field(p).rfind("max_change:", 0), 0u) << field(p);
  p = params();
  p.t0 = 0;
  EXPECT_EQ(field(p).rfind("t0:", 0), 0u) << field(p);
  AdaptiveRate a(params());
  EXPECT_THROW(a.update({1e-4, kIqs}), std::logic_error);
}
