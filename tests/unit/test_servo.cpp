// Closed-form checks of the servo strategies (control/): the proportional
// law against linear and Hertz-like model "packings" driven with the DEM
// update eps += rate * dt, the cap / saturation, the axis mask, the
// tolerance check and the parameter validation.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "virtual_triaxial/control/proportional_servo.h"
#include "virtual_triaxial/control/servo_strategy.h"

using vt::control::AxisMask;
using vt::control::make_servo;
using vt::control::ServoInput;
using vt::control::ServoOutput;
using vt::control::ServoParameters;
using vt::control::ServoStrategy;
using vt::dem::Vec3;

namespace {

ServoParameters params(double gain, double max_rate) {
  ServoParameters p;
  p.gain = gain;
  p.max_strain_rate = max_rate;
  return p;
}

std::unique_ptr<ServoStrategy> started(const ServoParameters& p, const Vec3& target,
                                       const AxisMask& axes = {}) {
  auto s = make_servo("proportional", p);
  s->init(target, axes);
  s->start(0.0);
  return s;
}

ServoInput input(const Vec3& stress, const Vec3& stiffness, double dt) {
  ServoInput in;
  in.time = 0.0;
  in.dt = dt;
  in.stress = stress;
  in.stiffness = stiffness;
  return in;
}

/// Linear packing sigma_i = sigma0_i + K_i eps_i (eps compression positive).
struct LinearPacking {
  Vec3 sigma0, k, eps;
  Vec3 stress() const {
    return {sigma0.x + k.x * eps.x, sigma0.y + k.y * eps.y, sigma0.z + k.z * eps.z};
  }
  void apply(const ServoOutput& o, double dt) { eps += dt * o.strain_rate; }
};

/// Expects `f` to throw std::invalid_argument whose message contains `word`.
template <class F>
void expect_invalid(F f, const std::string& word) {
  try {
    f();
    ADD_FAILURE() << "no exception; expected one naming '" << word << "'";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
  }
}

}  // namespace

// (1) geometric convergence with factor (1 - g) per step, per-axis K.
TEST(ProportionalServo, LinearPackingConvergesGeometrically) {
  const double g = 0.3, dt = 1e-6;
  const Vec3 target{2e5, 1.5e5, 3e5};
  LinearPacking pk{{1e5, 2e5, 1e5}, {1e8, 3e8, 5e7}, {}};
  auto s = started(params(g, 1e4), target);
  const Vec3 e0 = pk.stress() - target;
  for (int n = 1; n <= 12; ++n) {
    const ServoOutput o = s->update(input(pk.stress(), pk.k, dt));
    for (int i = 0; i < 3; ++i) ASSERT_FALSE(o.saturated[i]) << "cap must be inactive";
    pk.apply(o, dt);
    const Vec3 e = pk.stress() - target;
    for (int i = 0; i < 3; ++i) {
      const double expected = std::pow(1.0 - g, n) * e0[i];
      EXPECT_NEAR(e[i], expected, 1e-12 * std::abs(expected)) << "axis " << i << " step " << n;
    }
  }
}

// Sign convention: above target -> expand (negative rate), below -> compress.
TEST(ProportionalServo, SignAndErrorOutput) {
  auto s = started(params(0.5, 1e3), {1e5, 1e5, 1e5});
  const ServoOutput o = s->update(input({1.2e5, 0.8e5, 1e5}, {1e8, 1e8, 1e8}, 1e-6));
  EXPECT_DOUBLE_EQ(o.error.x, 2e4);
  EXPECT_DOUBLE_EQ(o.error.y, -2e4);
  EXPECT_DOUBLE_EQ(o.error.z, 0.0);
  EXPECT_DOUBLE_EQ(o.strain_rate.x, -0.5 * 2e4 / (1e8 * 1e-6));
  EXPECT_DOUBLE_EQ(o.strain_rate.y, 0.5 * 2e4 / (1e8 * 1e-6));
  EXPECT_EQ(o.strain_rate.z, 0.0);
}

// (2) the cap is respected and reported per axis.
TEST(ProportionalServo, CapRespectedAndSaturationReported) {
  const double cap = 10.0, dt = 1e-6;
  auto s = started(params(0.5, cap), {1e5, 1e5, 1e5});
  // x: uncapped rate 0.5*1e5/(1e8*1e-6) = 500 > cap (below target: compress)
  // y: uncapped rate -0.5*1e5/(1e8*1e-6) = -500 (above target: expand)
  // z: uncapped rate 0.5*1e2/(1e8*1e-6) = 0.5 < cap
  const ServoOutput o = s->update(input({0.0, 2e5, 1e5 - 1e2}, {1e8, 1e8, 1e8}, dt));
  EXPECT_EQ(o.strain_rate.x, cap);
  EXPECT_TRUE(o.saturated[0]);
  EXPECT_EQ(o.strain_rate.y, -cap);
  EXPECT_TRUE(o.saturated[1]);
  EXPECT_NEAR(o.strain_rate.z, 0.5, 1e-12);
  EXPECT_FALSE(o.saturated[2]);
  for (int i = 0; i < 3; ++i) EXPECT_LE(std::abs(o.strain_rate[i]), cap);
}

// (3) no stiffness (loose cloud): max rate in the error-reducing direction.
TEST(ProportionalServo, ZeroStiffnessUsesCapTowardsTarget) {
  const double cap = 2.5;
  auto s = started(params(0.5, cap), {1e5, 1e5, 1e5});
  const ServoOutput o = s->update(input({0.0, 3e5, 1e5}, {0.0, 0.0, 0.0}, 1e-6));
  EXPECT_EQ(o.strain_rate.x, cap);   // below target: compress at max rate
  EXPECT_TRUE(o.saturated[0]);
  EXPECT_EQ(o.strain_rate.y, -cap);  // above target: expand at max rate
  EXPECT_TRUE(o.saturated[1]);
  EXPECT_EQ(o.strain_rate.z, 0.0);   // on target: nothing to do
  EXPECT_FALSE(o.saturated[2]);
  // tiny (denormal) and negative stiffness behave like 0
  const ServoOutput t = s->update(input({0.0, 3e5, 0.0}, {1e-310, -1e6, 1e-300}, 1e-6));
  EXPECT_EQ(t.strain_rate.x, cap);
  EXPECT_EQ(t.strain_rate.y, -cap);
  EXPECT_EQ(t.strain_rate.z, cap);
}

// (4) axes outside the mask get rate 0, error 0, never saturated.
TEST(ProportionalServo, UncontrolledAxesGetZeroRate) {
  AxisMask lateral;
  lateral.z = false;  // triaxial shear: z driven open-loop by the protocol
  auto s = started(params(0.5, 1.0), {1e5, 1e5, 1e5}, lateral);
  const ServoOutput o = s->update(input({0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, 1e-6));
  EXPECT_EQ(o.strain_rate.x, 1.0);
  EXPECT_EQ(o.strain_rate.y, 1.0);
  EXPECT_EQ(o.strain_rate.z, 0.0);
  EXPECT_EQ(o.error.z, 0.0);
  EXPECT_FALSE(o.saturated[2]);
  // a non-finite measurement on an uncontrolled axis is ignored
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NO_THROW(s->update(input({1e5, 1e5, nan}, {1e8, 1e8, nan}, 1e-6)));
  EXPECT_TRUE(lateral[0] && lateral[1] && !lateral[2]);
  EXPECT_THROW(lateral[3], std::out_of_range);
}

// (5) within(): |sigma_i - target_i| <= tol |target_i| on controlled axes only.
TEST(ServoStrategy, WithinToleranceSemantics) {
  AxisMask xy;
  xy.z = false;
  auto s = make_servo("proportional", params(0.5, 1.0));
  EXPECT_THROW(s->within({1e5, 1e5, 1e5}, 0.01), std::logic_error);  // before init
  s->init({1e5, 2e5, 3e5}, xy);
  EXPECT_TRUE(s->within({1e5, 2e5, 0.0}, 0.0));            // z ignored, exact match
  EXPECT_TRUE(s->within({1.01e5, 1.98e5, 9e9}, 0.01));     // boundary |e| = tol |t| inclusive
  EXPECT_FALSE(s->within({1.0101e5, 2e5, 3e5}, 0.01));     // x just outside
  EXPECT_FALSE(s->within({1e5, 2.03e5, 3e5}, 0.01));       // y outside
  EXPECT_FALSE(s->within({std::nan(""), 2e5, 3e5}, 0.5));  // NaN is never within
  EXPECT_THROW(s->within({1e5, 2e5, 3e5}, -0.1), std::invalid_argument);
  s->set_targets({0.0, 2e5, 3e5});                         // zero target: exact only
  EXPECT_TRUE(s->within({0.0, 2e5, 3e5}, 0.1));
  EXPECT_FALSE(s->within({1.0, 2e5, 3e5}, 0.1));
  s->init({1e5, 1e5, 1e5}, AxisMask{false, false, false});  // nothing controlled
  EXPECT_TRUE(s->within({0.0, 0.0, 0.0}, 0.0));
}

// (6) bad parameters throw std::invalid_argument naming the parameter.
TEST(ServoStrategy, BadParametersThrowNamingTheParameter) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  expect_invalid([&] { make_servo("proportional", params(0.0, 1.0)); }, "gain");
  expect_invalid([&] { make_servo("proportional", params(1.5, 1.0)); }, "gain");
  expect_invalid([&] { make_servo("proportional", params(-0.5, 1.0)); }, "gain");
  expect_invalid([&] { make_servo("proportional", params(nan, 1.0)); }, "gain");
  expect_invalid([&] { make_servo("proportional", params(0.5, 0.0)); }, "max_strain_rate");
  expect_invalid([&] { make_servo("proportional", params(0.5, -1.0)); }, "max_strain_rate");
  expect_invalid([&] { make_servo("proportional", params(0.5, nan)); }, "max_strain_rate");
  expect_invalid([&] { make_servo("proportional", params(0.5, inf)); }, "max_strain_rate");
  expect_invalid([&] { make_servo("proportional", ServoParameters{}); }, "max_strain_rate");
  expect_invalid([&] { make_servo("pid_typo", params(0.5, 1.0)); }, "pid_typo");
  expect_invalid([&] { vt::control::ProportionalServo(params(2.0, 1.0)); }, "gain");
  EXPECT_NO_THROW(make_servo("proportional", params(1.0, 1.0)));  // g = 1 allowed

  auto s = make_servo("proportional", params(0.5, 1.0));
  EXPECT_EQ(s->name(), "proportional");
  expect_invalid([&] { s->init({1e5, nan, 1e5}, {}); }, "target_stress.y");
  s->init({1e5, 1e5, 1e5}, {});
  expect_invalid([&] { s->set_targets({1e5, 1e5, inf}); }, "target_stress.z");
  EXPECT_THROW(s->update(input({1e5, 1e5, 1e5}, {}, 1e-6)), std::logic_error);  // not started
  s->start(0.25);
  EXPECT_TRUE(s->running());
  expect_invalid([&] { s->update(input({1e5, 1e5, 1e5}, {}, 0.0)); }, "dt");
  expect_invalid([&] { s->update(input({1e5, 1e5, 1e5}, {}, nan)); }, "dt");
  expect_invalid([&] { s->update(input({nan, 1e5, 1e5}, {}, 1e-6)); }, "stress");
  s->stop();
  EXPECT_FALSE(s->running());
  EXPECT_THROW(s->update(input({1e5, 1e5, 1e5}, {}, 1e-6)), std::logic_error);
  auto fresh = make_servo("proportional", params(0.5, 1.0));
  EXPECT_THROW(fresh->start(0.0), std::logic_error);
  EXPECT_THROW(fresh->set_targets({1e5, 1e5, 1e5}), std::logic_error);
}

// (7) g = 1 with the exact stiffness cancels the error in one step.
TEST(ProportionalServo, UnitGainCancelsErrorInOneStep) {
  const double dt = 2e-7;
  const Vec3 target{5e5, 4e5, 6e5};
  LinearPacking pk{{3e5, 7e5, 6.5e5}, {2e9, 4e8, 1e9}, {}};
  auto s = started(params(1.0, 1e6), target);
  const ServoOutput o = s->update(input(pk.stress(), pk.k, dt));
  for (int i = 0; i < 3; ++i) ASSERT_FALSE(o.saturated[i]);
  pk.apply(o, dt);
  const Vec3 e = pk.stress() - target;
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(e[i], 0.0, 1e-12 * target[i]) << "axis " << i;
}

// (8) stiffening Hertz-like packing sigma = c eps^1.5, K = 1.5 c eps^0.5:
// with g = 0.5 the error decreases monotonically without overshoot
//   - from a contact-free start (K = 0: the cap drives the approach),
//   - from below with the cap inactive: one step maps u = eps/eps* to
//     u + (1 - u^1.5) / (3 u^0.5), which stays below 1 for u > 0.134
//     (2 s^3 - 3 s + 1 = 0, s = sqrt(u)); start at u = 0.3,
//   - from above with the cap inactive (the tangent overestimates the
//     unloading secant, so the steps fall short: never overshoots).
TEST(ProportionalServo, HertzLikePackingConvergesMonotonically) {
  const double target = 1e5, eps_star = 1e-3;  // sigma(eps_star) = target
  const double c = target / std::pow(eps_star, 1.5);
  const double dt = 1e-6;
  auto sigma = [&](double eps) { return eps > 0.0 ? c * std::pow(eps, 1.5) : 0.0; };
  auto tangent = [&](double eps) { return eps > 0.0 ? 1.5 * c * std::sqrt(eps) : 0.0; };
  struct Case { double eps0, cap; bool may_saturate; int max_steps; };
  // cap 10 /s = 1e-5 strain per step: ~100 capped steps from eps = 0
  for (const Case& cs : {Case{0.0, 10.0, true, 150}, Case{0.3 * eps_star, 1e4, false, 20},
                         Case{2.0 * eps_star, 1e4, false, 20}}) {
    SCOPED_TRACE("eps0 = " + std::to_string(cs.eps0));
    auto s = started(params(0.5, cs.cap), {target, target, target});
    double eps = cs.eps0;
    const double e0 = sigma(eps) - target;
    double prev = std::abs(e0);
    int n = 0;
    while (!s->within({sigma(eps), sigma(eps), sigma(eps)}, 0.005) && n < cs.max_steps) {
      const double sg = sigma(eps), k = tangent(eps);
      const ServoOutput o = s->update(input({sg, sg, sg}, {k, k, k}, dt));
      if (!cs.may_saturate) {
        ASSERT_FALSE(o.saturated[0]) << "step " << n;
      }
      eps += o.strain_rate.x * dt;
      ++n;
      const double e = sigma(eps) - target;
      ASSERT_GE(e * e0, 0.0) << "overshoot at step " << n;
      ASSERT_LT(std::abs(e), prev) << "error did not decrease at step " << n;
      prev = std::abs(e);
    }
    EXPECT_LT(n, cs.max_steps);
    EXPECT_LE(std::abs(sigma(eps) - target), 0.005 * target);
  }
}
