// Closed-form checks of the PID servo (control/pid_servo.h) on the linear
// plant of one control update with a constant drift d per update:
//
//   sigma_{n+1} = sigma_n + K * rate_n * dt + d          (compression positive)
//
// i.e. the error obeys e_{n+1} = e_n - u_n + d with u_n the stiffness-
// normalised action of the law when the servo is told the exact K. Checked:
// defaults == proportional law bit for bit; convergence without drift over
// the whole allowed gain box; proportional steady error d/g vs. zero steady
// error with an integral term; anti-windup after a long saturation (against
// a windup-prone integrator written here for comparison); the rate limit;
// live parameter changes; parameter validation and the factory.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "virtual_triaxial/control/pid_servo.h"
#include "virtual_triaxial/control/proportional_servo.h"
#include "virtual_triaxial/control/servo_strategy.h"

using vt::control::AxisMask;
using vt::control::make_servo;
using vt::control::PidServo;
using vt::control::ServoInput;
using vt::control::ServoOutput;
using vt::control::ServoParameters;
using vt::dem::Vec3;

namespace {

ServoParameters pid(double g, double ki, double kd, double cap, double max_change = 0.0) {
  ServoParameters p;
  p.gain = g;
  p.ki = ki;
  p.kd = kd;
  p.max_strain_rate = cap;
  p.max_rate_change = max_change;
  return p;
}

ServoInput input(const Vec3& stress, const Vec3& stiffness, double dt) {
  ServoInput in;
  in.dt = dt;
  in.stress = stress;
  in.stiffness = stiffness;
  return in;
}

/// sigma_{n+1} = sigma_n + K_true rate dt + d, per axis.
struct LinearPlant {
  Vec3 sigma, k, drift;
  void apply(const ServoOutput& o, double dt) {
    for (int i = 0; i < 3; ++i) sigma[i] += k[i] * o.strain_rate[i] * dt + drift[i];
  }
};

template <class F>
void expect_invalid(F f, const std::string& word) {
  try {
    f();
    ADD_FAILURE() << "no exception; expected one naming '" << word << "'";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
  }
}

/// Largest overshoot (opposite sign, as a fraction of |e0|) of the free
/// response of the linear PI loop (exact K, no drift, kd = 0) from error e0
/// and an empty integral: S_n = S_{n-1} + ki e_n, e_{n+1} = e_n - g e_n - S_n.
double pi_free_overshoot(double g, double ki) {
  double e = 1.0, s = 0.0, peak = 0.0;
  for (int n = 0; n < 10000; ++n) {
    s += ki * e;
    e -= g * e + s;
    peak = std::max(peak, -e);
  }
  return peak;
}

}  // namespace

// With ki = kd = max_rate_change = 0 the PID law is the proportional law, bit
// for bit, through capped (K = 0, then K small) and linear phases and a ramp.
TEST(PidServo, DefaultsReproduceTheProportionalLawBitForBit) {
  const double dt = 1e-6, target = 1e5, eps_star = 1e-3;
  const double c = target / std::pow(eps_star, 1.5);  // Hertz-like sigma = c eps^1.5
  ServoParameters p;
  p.gain = 0.7;
  p.max_strain_rate = 10.0;
  auto prop = make_servo("proportional", p);
  auto pidl = make_servo("pid", p);
  for (auto* s : {prop.get(), pidl.get()}) {
    s->init({target, 0.8 * target, target}, AxisMask{true, true, false});
    s->start(0.0);
  }
  Vec3 eps;
  for (int n = 0; n < 400; ++n) {
    if (n == 200) {
      prop->set_targets({1.3 * target, target, target});
      pidl->set_targets({1.3 * target, target, target});
    }
    Vec3 sg, k;
    for (int i = 0; i < 3; ++i) {
      sg[i] = eps[i] > 0.0 ? c * std::pow(eps[i], 1.5) : 0.0;
      k[i] = eps[i] > 0.0 ? 1.5 * c * std::sqrt(eps[i]) : 0.0;
    }
    const ServoOutput a = prop->update(input(sg, k, dt));
    const ServoOutput b = pidl->update(input(sg, k, dt));
    for (int i = 0; i < 3; ++i) {
      ASSERT_EQ(a.strain_rate[i], b.strain_rate[i]) << "axis " << i << " update " << n;
      ASSERT_EQ(a.error[i], b.error[i]);
      ASSERT_EQ(a.saturated[i], b.saturated[i]);
    }
    eps += dt * a.strain_rate;
  }
  const Vec3 sg{c * std::pow(eps.x, 1.5), c * std::pow(eps.y, 1.5), 0.0};
  EXPECT_TRUE(pidl->within(sg, 1e-6)) << "the run did not converge: " << sg.x << ", " << sg.y;
}

// The first updates follow the formula of pid_servo.h literally.
TEST(PidServo, FirstUpdatesFollowTheFormula) {
  const double g = 0.4, ki = 0.3, kd = 0.15, dt = 2e-6, k = 5e8;
  PidServo s(pid(g, ki, kd, 1e6));
  s.init({1e5, 1e5, 1e5}, AxisMask{true, false, false});
  s.start(0.0);
  const double e0 = 3e3, e1 = -1e3, e2 = 2e2;
  ServoOutput o = s.update(input({1e5 + e0, 0, 0}, {k, 0, 0}, dt));
  EXPECT_NEAR(o.strain_rate.x, -(g * e0 + ki * e0) / (k * dt), 1e-14);  // no derivative on update 0
  o = s.update(input({1e5 + e1, 0, 0}, {k, 0, 0}, dt));
  EXPECT_NEAR(o.strain_rate.x, -(g * e1 + ki * (e0 + e1) + kd * (e1 - e0)) / (k * dt), 1e-14);
  o = s.update(input({1e5 + e2, 0, 0}, {k, 0, 0}, dt));
  EXPECT_NEAR(o.strain_rate.x, -(g * e2 + ki * (e0 + e1 + e2) + kd * (e2 - e1)) / (k * dt), 1e-14);
  EXPECT_NEAR(s.integral_term().x, ki * (e0 + e1 + e2), 1e-9);
  EXPECT_EQ(o.strain_rate.y, 0.0);
  EXPECT_EQ(s.integral_term().y, 0.0);
  EXPECT_FALSE(o.saturated[0]);
  // sign: above target -> expand (negative rate)
  EXPECT_LT(s.update(input({2e5, 0, 0}, {k, 0, 0}, dt)).strain_rate.x, 0.0);
  // start() clears the state: the integral, and the derivative memory
  s.start(1.0);
  EXPECT_EQ(s.integral_term().x, 0.0);
  o = s.update(input({1e5 + e0, 0, 0}, {k, 0, 0}, dt));
  EXPECT_NEAR(o.strain_rate.x, -(g + ki) * e0 / (k * dt), 1e-14);
}

// (a) no drift: the loop converges to the target for every corner and the
// middle of the allowed box g in (0, 1], ki in [0, 1], kd in [0, 0.2]. The
// slowest of these cases has spectral radius sqrt(1 - g) = 0.894 (g = 0.2,
// ki > 0), so 400 updates shrink the error below 0.894^400 ~ 1e-19 times a
// polynomial transient factor; asserted: |e| <= 1e-9 |e0|.
TEST(PidServo, ConvergesToTheTargetWithoutDrift) {
  const double dt = 1e-6;
  const Vec3 target{2e5, 1.5e5, 3e5};
  for (double g : {0.2, 0.5, 1.0})
    for (double ki : {0.0, 0.5, 1.0})
      for (double kd : {0.0, 0.1, 0.2}) {
        SCOPED_TRACE("g " + std::to_string(g) + " ki " + std::to_string(ki) + " kd " + std::to_string(kd));
        LinearPlant pl{{1e5, 2e5, 1e5}, {1e8, 3e8, 5e7}, {}};
        auto s = make_servo("pid", pid(g, ki, kd, 1e5));
        s->init(target, {});
        s->start(0.0);
        const Vec3 e0 = pl.sigma - target;
        for (int n = 0; n < 400; ++n) {
          const ServoOutput o = s->update(input(pl.sigma, pl.k, dt));
          for (int i = 0; i < 3; ++i) ASSERT_FALSE(o.saturated[i]) << "the cap must stay inactive";
          pl.apply(o, dt);
        }
        for (int i = 0; i < 3; ++i) EXPECT_LE(std::abs(pl.sigma[i] - target[i]), 1e-9 * std::abs(e0[i]));
      }
}

// (b) constant drift d per update (shearing pushes the lateral stress):
//   proportional: e_{n+1} = (1 - g) e_n + d, so e_n = d/g + (1 - g)^n (e_0 - d/g)
//                 -> steady error d/g with the sign of d;
//   PID (ki > 0): the integral term settles at d and the error at 0.
TEST(PidServo, IntegralRemovesTheSteadyErrorOfAConstantDrift) {
  const double dt = 1e-6, g = 0.5, ki = 0.2;
  const Vec3 target{1e5, 1e5, 1e5};
  const Vec3 drift{500.0, -300.0, 0.0};  // [Pa per update]; 0.5 % and 0.3 % of the target
  const Vec3 k{1e8, 2e8, 1e8};
  for (const char* law : {"proportional", "pid"}) {
    SCOPED_TRACE(law);
    const bool is_pid = std::string(law) == "pid";
    auto s = make_servo(law, pid(g, is_pid ? ki : 0.0, 0.0, 1e5));
    s->init(target, {});
    s->start(0.0);
    LinearPlant pl{target, k, drift};  // starts on target
    for (int n = 1; n <= 300; ++n) {
      const ServoOutput o = s->update(input(pl.sigma, pl.k, dt));
      pl.apply(o, dt);
      if (!is_pid) {  // closed form of the proportional loop, e_0 = 0
        for (int i = 0; i < 3; ++i) {
          const double expected = drift[i] / g * (1.0 - std::pow(1.0 - g, n));
          ASSERT_NEAR(pl.sigma[i] - target[i], expected, 1e-9 * target[i]) << "axis " << i << " update " << n;
        }
      }
    }
    for (int i = 0; i < 3; ++i) {
      const double e = pl.sigma[i] - target[i];
      if (is_pid) {
        // below 1e-6 of the proportional steady error (and so of the target)
        EXPECT_LE(std::abs(e), 1e-6 * std::max(std::abs(drift[i] / g), 1.0)) << "axis " << i;
        const PidServo& p = dynamic_cast<const PidServo&>(*s);
        EXPECT_NEAR(p.integral_term()[i], drift[i], 1e-6 * std::max(std::abs(drift[i]), 1.0));
      } else {
        EXPECT_NEAR(e, drift[i] / g, 1e-9 * target[i]) << "axis " << i;  // e_ss = d/g, with sign
      }
    }
  }
}

// (c) anti-windup. Phase A: the plant does not respond (K = 0: no contacts;
// 1000 updates at the cap, target unreachable). Phase B: the plant responds
// with K = 1e8 Pa, but the cap (10 1/s, i.e. at most K dt cap = 1e3 Pa per
// update) keeps the law saturated for ~100 more updates of approach.
// With conditional integration the integral term stays exactly 0 while
// saturated (asserted), so the loop leaves saturation with an empty integral
// and |e| < K dt cap / g = 2000 Pa, after which it is the linear PI loop.
// Its free response from (e, S = 0) overshoots by at most rho |e| with
// rho = pi_free_overshoot(0.5, 0.1) = 0.2114 (from the closed-form
// recurrence), so the overshoot is bounded by rho K dt cap / g = 423 Pa
// (0.42 % of the target) -- asserted; and it settles within 1e-3 of the
// target within 130 updates of phase B (99 capped updates of approach plus
// ~10 for the PI transient, |z| = sqrt(1 - g) = 0.707 per update).
// The same PI law without anti-windup integrates -1e5 Pa for 1000 updates
// (S = -1e7 Pa): after those 130 updates it is still running at the cap,
// 3e4 Pa past the target, and its overshoot exceeds 100 % of the target
// (S must unwind through sum ki e ~ 1e7 Pa of positive error first).
TEST(PidServo, AntiWindupBoundsTheOvershootAfterALongSaturation) {
  const double dt = 1e-6, g = 0.5, ki = 0.1, cap = 10.0, target = 1e5, k = 1e8;
  const int hold = 1000, settle = 130;
  PidServo s(pid(g, ki, 0.0, cap));
  s.init({target, target, target}, AxisMask{true, false, false});
  s.start(0.0);

  // the windup-prone reference: the same law, always integrating
  double naive_s = 0.0;
  auto naive_rate = [&](double sigma, double kk) {
    const double e = sigma - target;
    naive_s += ki * e;
    const double u = g * e + naive_s;
    if (kk > 0.0 && std::abs(u) < kk * dt * cap) return -u / (kk * dt);
    return u > 0.0 ? -cap : cap;
  };

  double sigma = 0.0, naive_sigma = 0.0;
  for (int n = 0; n < hold; ++n) {  // phase A: K = 0, nothing moves
    const ServoOutput o = s.update(input({sigma, 0, 0}, {0.0, 0, 0}, dt));
    ASSERT_EQ(o.strain_rate.x, cap);
    ASSERT_TRUE(o.saturated[0]);
    ASSERT_EQ(s.integral_term().x, 0.0) << "the integral grew while saturated (update " << n << ")";
    naive_rate(naive_sigma, 0.0);
  }
  EXPECT_NEAR(naive_s, hold * ki * (-target), 1e-6 * target);

  const double rho = pi_free_overshoot(g, ki);
  EXPECT_NEAR(rho, 0.21136, 1e-5);
  const double bound = rho * k * dt * cap / g;
  double overshoot = 0.0, naive_overshoot = 0.0;
  int settled_at = -1;
  for (int n = 0; n < settle; ++n) {  // phase B: the plant responds
    const ServoOutput o = s.update(input({sigma, 0, 0}, {k, 0, 0}, dt));
    if (o.saturated[0]) {
      EXPECT_EQ(s.integral_term().x, 0.0) << "update " << n;
    }
    sigma += k * o.strain_rate.x * dt;
    naive_sigma += k * naive_rate(naive_sigma, k) * dt;
    overshoot = std::max(overshoot, sigma - target);
    naive_overshoot = std::max(naive_overshoot, naive_sigma - target);
    if (std::abs(sigma - target) <= 1e-3 * target) {
      if (settled_at < 0) settled_at = n;
    } else {
      settled_at = -1;  // left the band again
    }
  }
  std::printf("[anti-windup] overshoot %.1f Pa (bound %.1f Pa), settled after %d updates; "
              "without anti-windup: overshoot %.3g Pa, error %.3g Pa after %d updates\n",
              overshoot, bound, settled_at, naive_overshoot, naive_sigma - target, settle);
  EXPECT_LE(overshoot, bound);
  EXPECT_GE(settled_at, 0) << "not within 1e-3 of the target after " << settle << " updates";
  EXPECT_LE(std::abs(sigma - target), 1e-3 * target);
  // The reference is still at the cap: 100 updates of 1e3 Pa to the target,
  // then 30 more past it (its integral, -1.05e7 Pa, outweighs g e).
  EXPECT_NEAR(naive_sigma - target, 30 * k * dt * cap, 1e-6 * target) << "the reference integrator recovered";
  for (int n = 0; n < 1000; ++n) {
    naive_sigma += k * naive_rate(naive_sigma, k) * dt;
    naive_overshoot = std::max(naive_overshoot, naive_sigma - target);
  }
  EXPECT_GT(naive_overshoot, 1.0 * target) << "the reference integrator should wind up";
}

// (d) rate limit: |rate_n - rate_{n-1}| <= max_rate_change on every update
// (rate_{-1} = 0), the clip is reported as saturation, the integral does not
// wind up while the limit holds the rate back, and the loop still converges.
TEST(PidServo, RateLimitBoundsTheRateChangeEveryUpdate) {
  const double dt = 1e-6, g = 0.5, ki = 0.1, kd = 0.1, cap = 1e4, m = 50.0;
  const Vec3 target{1e5, 5e4, 2e5};
  LinearPlant pl{{0.0, 1e5, 2e5}, {1e8, 2e8, 1e8}, {}};
  PidServo s(pid(g, ki, kd, cap, m));
  s.init(target, {});
  s.start(0.0);
  Vec3 prev;
  int limited = 0;
  for (int n = 0; n < 3000; ++n) {
    if (n == 1500) s.set_targets({2e5, 1e5, 1e5});  // a second step, from a moving state
    const ServoOutput o = s.update(input(pl.sigma, pl.k, dt));
    for (int i = 0; i < 3; ++i) {
      const double change = std::abs(o.strain_rate[i] - prev[i]);
      ASSERT_LE(change, m * (1.0 + 1e-12)) << "axis " << i << " update " << n;
      ASSERT_LE(std::abs(o.strain_rate[i]), cap);
      if (change >= m * (1.0 - 1e-12)) {
        ++limited;
        EXPECT_TRUE(o.saturated[i]) << "a binding rate limit must be reported";
      }
    }
    prev = o.strain_rate;
    pl.apply(o, dt);
  }
  EXPECT_GT(limited, 10) << "the rate limit never bound: the test does not test it";
  const Vec3 final_target{2e5, 1e5, 1e5};
  for (int i = 0; i < 3; ++i) EXPECT_LE(std::abs(pl.sigma[i] - final_target[i]), 1e-6 * final_target[i]);

  // Held back by the limit while the error keeps its sign: no integration.
  PidServo w(pid(g, ki, 0.0, cap, m));
  w.init({1e5, 1e5, 1e5}, AxisMask{true, false, false});
  w.start(0.0);
  for (int n = 0; n < 5; ++n) {  // the law wants 0.5*1e5/(1e8*1e-6) = 500 1/s; gets 50, 100, ...
    const ServoOutput o = w.update(input({0.0, 0, 0}, {1e8, 0, 0}, dt));
    EXPECT_NEAR(o.strain_rate.x, m * (n + 1), 1e-9);
    EXPECT_TRUE(o.saturated[0]);
    EXPECT_EQ(w.integral_term().x, 0.0);
  }
}

// Live tuning: set_parameters() keeps the state; the integral term is in Pa,
// so changing ki does not make the output jump; ki = 0 clears it.
TEST(PidServo, SetParametersIsBumplessAndKeepsTheState) {
  const double dt = 1e-6, k = 1e8, e = -2e3;
  PidServo s(pid(0.5, 0.2, 0.0, 1e5));
  s.init({1e5, 1e5, 1e5}, AxisMask{true, false, false});
  s.start(0.0);
  for (int n = 0; n < 3; ++n) s.update(input({1e5 + e, 0, 0}, {k, 0, 0}, dt));
  EXPECT_NEAR(s.integral_term().x, 3 * 0.2 * e, 1e-9);
  s.set_parameters(pid(0.8, 0.05, 0.0, 1e5));
  EXPECT_NEAR(s.integral_term().x, 3 * 0.2 * e, 1e-9) << "a gain change reset the integral";
  EXPECT_TRUE(s.running());
  const ServoOutput o = s.update(input({1e5 + e, 0, 0}, {k, 0, 0}, dt));
  EXPECT_NEAR(o.strain_rate.x, -(0.8 * e + 3 * 0.2 * e + 0.05 * e) / (k * dt), 1e-12);
  EXPECT_EQ(s.parameters().gain, 0.8);
  s.set_parameters(pid(0.8, 0.0, 0.0, 1e5));
  EXPECT_EQ(s.integral_term().x, 0.0) << "ki = 0 must clear the integral term";
  // a lowered cap has priority over the rate limit
  s.set_parameters(pid(0.8, 0.0, 0.0, 1e5, 1.0));
  s.update(input({0.0, 0, 0}, {0.0, 0, 0}, dt));  // K = 0: wants +cap, limited to +1
  s.set_parameters(pid(0.8, 0.0, 0.0, 0.5, 1.0));
  EXPECT_EQ(s.update(input({0.0, 0, 0}, {0.0, 0, 0}, dt)).strain_rate.x, 0.5);
  // a refused change keeps the old tuning
  expect_invalid([&] { s.set_parameters(pid(1.5, 0.0, 0.0, 1.0)); }, "gain");
  EXPECT_EQ(s.parameters().gain, 0.8);
  EXPECT_EQ(s.parameters().max_strain_rate, 0.5);
  // the proportional law takes live changes as well
  auto p = make_servo("proportional", pid(0.5, 0.0, 0.0, 1.0));
  p->set_parameters(pid(0.25, 0.0, 0.0, 2.0));
  EXPECT_EQ(p->parameters().gain, 0.25);
  expect_invalid([&] { p->set_parameters(pid(0.5, 0.0, 0.0, -1.0)); }, "max_strain_rate");
  EXPECT_EQ(p->parameters().max_strain_rate, 2.0);
}

// (e) bad parameters and inputs throw std::invalid_argument naming the field.
TEST(PidServo, BadParametersThrowNamingTheField) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (double ki : {-0.1, 1.5, nan, inf})
    expect_invalid([&] { make_servo("pid", pid(0.5, ki, 0.0, 1.0)); }, "ki");
  for (double kd : {-0.1, 0.25, nan})
    expect_invalid([&] { make_servo("pid", pid(0.5, 0.0, kd, 1.0)); }, "kd");
  for (double m : {-1.0, nan, inf})
    expect_invalid([&] { make_servo("pid", pid(0.5, 0.0, 0.0, 1.0, m)); }, "max_rate_change");
  expect_invalid([&] { PidServo(pid(0.0, 0.0, 0.0, 1.0)); }, "gain");
  expect_invalid([&] { PidServo(pid(0.5, 0.0, 0.0, 0.0)); }, "max_strain_rate");
  // the new fields are validated for every strategy
  expect_invalid([&] { make_servo("proportional", pid(0.5, 2.0, 0.0, 1.0)); }, "ki");
  EXPECT_NO_THROW(make_servo("pid", pid(1.0, 1.0, 0.2, 1.0, 0.0)));  // the corners are allowed
  EXPECT_NO_THROW(make_servo("pid", pid(1.0, 0.0, 0.0, 1.0, 1e9)));

  PidServo s(pid(0.5, 0.1, 0.0, 1.0));
  EXPECT_THROW(s.start(0.0), std::logic_error);  // before init
  s.init({1e5, 1e5, 1e5}, {});
  expect_invalid([&] { s.set_targets({nan, 1e5, 1e5}); }, "target_stress.x");
  EXPECT_THROW(s.update(input({1e5, 1e5, 1e5}, {}, 1e-6)), std::logic_error);  // not started
  s.start(0.0);
  expect_invalid([&] { s.update(input({1e5, 1e5, 1e5}, {}, 0.0)); }, "dt");
  expect_invalid([&] { s.update(input({1e5, 1e5, nan}, {}, 1e-6)); }, "stress");
  expect_invalid([&] { s.update(input({1e5, 1e5, 1e5}, {inf, 0, 0}, 1e-6)); }, "stiffness");
  EXPECT_EQ(s.integral_term().z, 0.0) << "a refused update changed the state";
  s.stop();
  EXPECT_THROW(s.update(input({1e5, 1e5, 1e5}, {}, 1e-6)), std::logic_error);
}

// (f) the factory knows "pid"; an unknown name lists both strategies.
TEST(PidServo, FactoryBuildsPidAndListsIt) {
  auto s = make_servo("pid", pid(0.5, 0.1, 0.05, 1.0, 0.5));
  ASSERT_NE(dynamic_cast<PidServo*>(s.get()), nullptr);
  EXPECT_EQ(s->name(), "pid");
  EXPECT_EQ(s->parameters().ki, 0.1);
  EXPECT_EQ(s->parameters().kd, 0.05);
  EXPECT_EQ(s->parameters().max_rate_change, 0.5);
  try {
    make_servo("pid2", pid(0.5, 0.0, 0.0, 1.0));
    ADD_FAILURE() << "unknown strategy accepted";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("'pid2'"), std::string::npos) << m;
    EXPECT_NE(m.find("known: proportional, pid"), std::string::npos) << m;
  }
}
