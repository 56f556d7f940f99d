// Rigid-body rotation (rigid_rotation.h): torque-free spheroid (conservation
// of L and energy, precession rate), asymmetric body, damping (eq. 2), constant
// torque closed form, second-order convergence against RK4, exact scaling.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include "virtual_triaxial/dem/rigid_rotation.h"
#include "virtual_triaxial/dem/spheroid.h"

using namespace vt::dem;

namespace {

double rel(const Vec3& a, const Vec3& b) { return norm(a - b) / norm(b); }

/// Rotation angle between two orientations [rad].
double angle_between(const Quaternion& a, const Quaternion& b) {
  const Quaternion r = Quaternion{a.w, -a.x, -a.y, -a.z} * b;
  const double v = std::sqrt(r.x * r.x + r.y * r.y + r.z * r.z);
  return 2.0 * std::atan2(v, std::fabs(r.w));
}

const Quaternion kQ0 = normalized(Quaternion{0.9, 0.2, -0.3, 0.25});

/// A spheroid of aspect 1.2 (b = 1 mm, quartz density).
Vec3 spheroid_inertia() { return Spheroid(1.2e-3, 1e-3).principal_inertia(2650.0); }

/// Body angular velocity tilted by `tilt` from the symmetry axis (body x).
Vec3 tilted_omega(double mag, double tilt) { return {mag * std::cos(tilt), mag * std::sin(tilt), 0.0}; }

struct FreeRun {
  double max_dl = 0, max_de = 0, precession = 0, max_dcos = 0;
};

/// Integrate a torque-free body for n steps with the omega-state API and
/// measure L (world), energy, the precession rate of the body x axis about L.
FreeRun run_free(const Vec3& inertia, const Vec3& w_body, double dt, int n) {
  Quaternion q = kQ0;
  Vec3 w = q.rotate(w_body);
  const Vec3 l0 = angular_momentum_world(q, w, inertia);
  const double e0 = rotational_energy(q, l0, inertia);
  const Vec3 lhat = (1.0 / norm(l0)) * l0;
  const Vec3 ref = std::fabs(lhat.x) < 0.6 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 v1 = (1.0 / norm(cross(lhat, ref))) * cross(lhat, ref), v2 = cross(lhat, v1);
  auto phase = [&](const Quaternion& qq) {
    const Vec3 e = qq.rotate({1, 0, 0});
    return std::atan2(dot(e, v2), dot(e, v1));
  };
  const double cos0 = dot(q.rotate({1, 0, 0}), lhat);
  FreeRun r;
  double phi = phase(q), total = 0;
  for (int s = 0; s < n; ++s) {
    advance_rotation_omega(q, w, Vec3{}, inertia, 0.0, dt);
    const Vec3 l = angular_momentum_world(q, w, inertia);
    r.max_dl = std::max(r.max_dl, rel(l, l0));
    r.max_de = std::max(r.max_de, std::fabs(rotational_energy(q, l, inertia) / e0 - 1));
    r.max_dcos = std::max(r.max_dcos, std::fabs(dot(q.rotate({1, 0, 0}), lhat) - cos0));
    const double p = phase(q);
    double dp = p - phi;
    if (dp > M_PI) dp -= 2 * M_PI;
    if (dp < -M_PI) dp += 2 * M_PI;
    total += dp;
    phi = p;
  }
  r.precession = total / (n * dt);
  return r;
}

}  // namespace

TEST(RigidRotation, FreeSpheroidConservesMomentumEnergyAndPrecessesAtLOverIperp) {
  const Vec3 inertia = spheroid_inertia();
  const Vec3 w_body = tilted_omega(1e3, 0.5);  // 1000 rad/s, 29 deg from the axis
  const Vec3 l_body{inertia.x * w_body.x, inertia.y * w_body.y, inertia.z * w_body.z};
  const double omega_p = norm(l_body) / inertia.y;  // analytic precession rate
  const double spin = l_body.x * (1 / inertia.x - 1 / inertia.y);
  const double fastest = std::max({norm(w_body), omega_p, std::fabs(spin)});
  const double dt = 0.1 / fastest;  // 0.1 of the shortest characteristic time
  const int n = 100000;
  const FreeRun r = run_free(inertia, w_body, dt, n);
  std::printf("[ free spheroid ] %d steps, dt*rate = 0.1: |dL|/L %.1e, |dE|/E %.1e, "
              "precession rel err %.1e, nutation drift %.1e\n",
              n, r.max_dl, r.max_de, std::fabs(r.precession / omega_p - 1), r.max_dcos);
  EXPECT_LT(r.max_dl, 1e-9);
  EXPECT_LT(r.max_de, 1e-9);
  EXPECT_LT(std::fabs(r.precession / omega_p - 1), 1e-4);
  EXPECT_LT(r.max_dcos, 1e-9);  // the symmetry axis keeps its angle to L
}

TEST(RigidRotation, MomentumAndOmegaStatesGiveTheSameTrajectory) {
  const Vec3 inertia = spheroid_inertia();
  const Vec3 torque{1e-9, -2e-9, 5e-10};
  const double dt = 1e-5, alpha = 50.0;
  Quaternion qa = kQ0, qb = kQ0;
  Vec3 w = qa.rotate(tilted_omega(300, 0.7));
  Vec3 l = angular_momentum_world(qa, w, inertia);
  for (int s = 0; s < 2000; ++s) {
    advance_rotation(qa, l, torque, inertia, alpha, dt);
    advance_rotation_omega(qb, w, torque, inertia, alpha, dt);
  }
  EXPECT_LT(angle_between(qa, qb), 1e-11);  // rounding of the conversions only
  EXPECT_LT(rel(angular_momentum_world(qb, w, inertia), l), 1e-12);
}

TEST(RigidRotation, AsymmetricFreeBodyConservesMomentumEnergyBounded) {
  const Vec3 inertia{1.0, 1.6, 2.3};
  const Vec3 w_body{0.3, 1.0, 0.2};  // near the unstable middle axis: tumbling
  const double dt = 0.1 / norm(w_body);
  const int n = 100000;
  const FreeRun r = run_free(inertia, w_body, dt, n);
  std::printf("[ asymmetric ] %d steps: |dL|/L %.1e, max |dE|/E %.1e\n", n, r.max_dl, r.max_de);
  EXPECT_LT(r.max_dl, 1e-9);
  EXPECT_LT(r.max_de, 1e-3);  // O(dt^2), bounded (symplectic), not conserved
}

TEST(RigidRotation, DampedSphereDecaysByTheLeapfrogFactor) {
  const double i = 0.4 * 2650 * 4.0 / 3.0 * M_PI * 1e-15;  // 1 mm sphere
  const Vec3 inertia{i, i, i};
  const double alpha = 200.0, dt = 1e-5;  // alpha dt = 0.002, alpha t = 4 at the end
  const double c = (1 - 0.5 * alpha * dt) / (1 + 0.5 * alpha * dt);
  Quaternion q = kQ0;
  const Vec3 w0{100, -50, 20};
  Vec3 w = w0;
  double factor = 1.0;
  const int n = 2000;
  for (int s = 1; s <= n; ++s) {
    advance_rotation_omega(q, w, Vec3{}, inertia, alpha, dt);
    factor *= c;
    ASSERT_LT(rel(w, factor * w0), 1e-12) << "step " << s;
  }
  const double t = n * dt;
  // (1 - x/2)/(1 + x/2) = exp(-x - x^3/12 - ...): relative error n x^3 / 12 = 1.3e-6
  const double x = alpha * dt;
  EXPECT_NEAR(norm(w) / norm(w0), std::exp(-alpha * t), 1.5 * n * x * x * x / 12 * std::exp(-alpha * t));
  // spheroid: the world angular momentum decays by the same factor, direction kept
  const Vec3 si = spheroid_inertia();
  Quaternion qs = kQ0;
  const Vec3 l0 = angular_momentum_world(qs, qs.rotate(tilted_omega(1e3, 0.4)), si);
  Vec3 l = l0;
  for (int s = 0; s < n; ++s) advance_rotation(qs, l, Vec3{}, si, alpha, dt);
  EXPECT_LT(rel(l, factor * l0), 1e-12);
}

TEST(RigidRotation, ConstantTorqueOnSphereMatchesClosedForm) {
  // theta(t) = w0 t + tau t^2 / (2 I) about a fixed axis; the leapfrog with
  // w(-dt/2) = w0 - tau dt/(2I) reproduces it exactly at t = n dt.
  const double i = 2.0, tau = 3.0, w0 = 0.5, dt = 1e-3;
  const Vec3 u = (1.0 / std::sqrt(3.0)) * Vec3{1, 1, -1};
  Quaternion q;
  Vec3 l = (i * (w0 - tau * dt / (2 * i))) * u;
  const int n = 5000;
  for (int s = 0; s < n; ++s) advance_rotation(q, l, tau * u, {i, i, i}, 0.0, dt);
  const double t = n * dt;
  const double theta = w0 * t + tau * t * t / (2 * i);
  const Quaternion expected = axis_angle(u, theta);
  EXPECT_LT(angle_between(q, expected), 1e-10);
  EXPECT_LT(rel(l, (i * w0 + tau * (t - 0.5 * dt)) * u), 1e-12);  // L at t - dt/2
}

namespace {
// Heavy symmetric top: torque k e x z (potential U = -k e.z), e = body x axis.
struct Top {
  Vec3 inertia{0.4 * 1.0, 0.2 * (1.44 + 1.0), 0.2 * (1.44 + 1.0)};  // a = 1.2, b = 1, m = 1
  double k = 0.3;
  Vec3 torque(const Quaternion& q) const { return k * cross(q.rotate({1, 0, 0}), {0, 0, 1}); }
  double energy(const Quaternion& q, const Vec3& l) const {
    return rotational_energy(q, l, inertia) - k * q.rotate({1, 0, 0}).z;
  }
};

/// Reference: classical RK4 on (q, L), omega = R I^-1 R^T L, dq/dt = 1/2 (0,w) q.
void rk4(const Top& top, Quaternion& q, Vec3& l, double h, int n) {
  struct D {
    Quaternion dq;
    Vec3 dl;
  };
  auto f = [&](const Quaternion& qq, const Vec3& ll) {
    const Quaternion qn = normalized(qq);
    const Vec3 lb = qn.rotate_inverse(ll);
    const Vec3 w = qn.rotate({lb.x / top.inertia.x, lb.y / top.inertia.y, lb.z / top.inertia.z});
    const Quaternion wq = Quaternion{0.0, w.x, w.y, w.z} * qq;
    return D{{0.5 * wq.w, 0.5 * wq.x, 0.5 * wq.y, 0.5 * wq.z}, top.torque(qn)};
  };
  auto add = [](const Quaternion& a, const Quaternion& b, double s) {
    return Quaternion{a.w + s * b.w, a.x + s * b.x, a.y + s * b.y, a.z + s * b.z};
  };
  for (int s = 0; s < n; ++s) {
    const D k1 = f(q, l);
    const D k2 = f(add(q, k1.dq, h / 2), l + (h / 2) * k1.dl);
    const D k3 = f(add(q, k2.dq, h / 2), l + (h / 2) * k2.dl);
    const D k4 = f(add(q, k3.dq, h), l + h * k3.dl);
    Quaternion sum = add(add(add(k1.dq, k2.dq, 2.0), k3.dq, 2.0), k4.dq, 1.0);
    q = normalized(add(q, sum, h / 6));
    l = l + (h / 6) * (k1.dl + 2.0 * k2.dl + 2.0 * k3.dl + k4.dl);
  }
}

double leapfrog_error(const Top& top, const Quaternion& q0, const Vec3& l0, double dt, double t,
                      const Quaternion& q_ref) {
  Quaternion q = q0;
  Vec3 l = l0 - (0.5 * dt) * top.torque(q0);  // L(-dt/2), second-order start
  const int n = static_cast<int>(std::lround(t / dt));
  for (int s = 0; s < n; ++s) advance_rotation(q, l, top.torque(q), top.inertia, 0.0, dt);
  return angle_between(q, q_ref);
}
}  // namespace

TEST(RigidRotation, HeavyTopConvergesAtSecondOrderAndKeepsEnergyBounded) {
  const Top top;
  const Quaternion q0 = kQ0;
  const Vec3 l0 = angular_momentum_world(q0, q0.rotate(tilted_omega(2.0, 0.6)), top.inertia);
  const double t = 10.0;
  Quaternion q_ref = q0;
  Vec3 l_ref = l0;
  rk4(top, q_ref, l_ref, 1e-4, 100000);
  double prev = 0;
  for (const double dt : {0.02, 0.01, 0.005}) {
    const double err = leapfrog_error(top, q0, l0, dt, t, q_ref);
    std::printf("[ heavy top ] dt %.3f: orientation error %.3e rad%s", dt, err,
                prev > 0 ? "" : "\n");
    if (prev > 0) {
      std::printf(", ratio %.2f\n", prev / err);
      EXPECT_GT(prev / err, 3.5);
      EXPECT_LT(prev / err, 4.5);
    }
    prev = err;
  }
  // energy: bounded, O(dt^2), no drift over 1e5 steps
  const double dt = 0.02;
  Quaternion q = q0;
  Vec3 l = l0 - (0.5 * dt) * top.torque(q0);
  const double e0 = top.energy(q0, l0);
  double max_first = 0, max_last = 0;
  const int n = 100000;
  for (int s = 0; s < n; ++s) {
    const Vec3 tau = top.torque(q);
    // integer-time L(t) = (L(t-dt/2) + L(t+dt/2))/2 = L(t-dt/2) + dt/2 tau, with q(t)
    const double de = std::fabs(top.energy(q, l + (0.5 * dt) * tau) - e0);
    advance_rotation(q, l, tau, top.inertia, 0.0, dt);
    if (s < n / 10) max_first = std::max(max_first, de);
    if (s >= n - n / 10) max_last = std::max(max_last, de);
  }
  std::printf("[ heavy top ] energy error, first/last 10%% of 1e5 steps: %.2e / %.2e (E = %.3f)\n",
              max_first, max_last, e0);
  EXPECT_LT(max_last, 2.0 * max_first + 1e-12);  // no secular drift
  EXPECT_LT(max_last / std::fabs(e0), 2e-2);
}

TEST(RigidRotation, PowerOfTwoScalingIsExact) {
  // Length x 2^k (I x 2^5k, L and torque x 2^5k at fixed omega) and time x 2^m
  // (omega, L x 2^-m, torque x 2^-2m) leave the orientation bit for bit.
  const Vec3 inertia = spheroid_inertia();
  const Vec3 torque{1e-9, -2e-9, 5e-10};
  const double dt = 1e-5, alpha = 30.0;
  Quaternion q = kQ0;
  Vec3 w = q.rotate(tilted_omega(300, 0.7));
  for (int s = 0; s < 200; ++s) advance_rotation_omega(q, w, torque, inertia, alpha, dt);
  for (const int k : {-3, 2}) {
    for (const int m : {-5, 4}) {
      const double fl = std::ldexp(1.0, 5 * k), ft = std::ldexp(1.0, m);
      Quaternion qs = kQ0;
      Vec3 ws = (1 / ft) * qs.rotate(tilted_omega(300, 0.7));
      for (int s = 0; s < 200; ++s)
        advance_rotation_omega(qs, ws, (fl / (ft * ft)) * torque, fl * inertia, alpha / ft, dt * ft);
      EXPECT_EQ(qs.w, q.w);
      EXPECT_EQ(qs.x, q.x);
      EXPECT_EQ(qs.y, q.y);
      EXPECT_EQ(qs.z, q.z);
      EXPECT_EQ(ws.x * ft, w.x);
      EXPECT_EQ(ws.y * ft, w.y);
      EXPECT_EQ(ws.z * ft, w.z);
    }
  }
}

TEST(RigidRotation, SmallAngleCosSinMatchesTheLibraryToRounding) {
  // cos_sin uses Taylor polynomials for |x| <= 1/16 (truncation < 1e-19):
  // it must agree with std::cos / std::sin to a few units in the last place,
  // on both sides of the switch and for the tiny angles of a DEM step.
  double worst = 0.0;
  for (int k = -2000; k <= 2000; ++k) {
    for (const double scale : {1.0 / 16, 1e-3, 1e-7}) {
      const double x = scale * k / 2000.0;
      double c, s;
      cos_sin(x, c, s);
      worst = std::max(worst, std::fabs(c - std::cos(x)) / std::numeric_limits<double>::epsilon());
      if (x != 0.0)
        worst = std::max(worst, std::fabs(s - std::sin(x)) / (std::fabs(std::sin(x)) *
                                                                std::numeric_limits<double>::epsilon()));
      else
        EXPECT_EQ(s, 0.0);
    }
  }
  EXPECT_LT(worst, 2.0);  // in units of epsilon (relative for sin)
  double c, s;
  cos_sin(0.7, c, s);  // beyond the switch: the library values
  EXPECT_EQ(c, std::cos(0.7));
  EXPECT_EQ(s, std::sin(0.7));
}

TEST(RigidRotation, SmallAnglePolynomialsHaveTheTaylorTruncationError) {
  // cos_series and sinc_series_minus_1 are the Taylor polynomials of cos x
  // (to x^10) and sin(x)/x (to x^8). Beyond the switch (|x| up to 1) their
  // error is the first omitted term, x^12/12! and x^10/11!, plus rounding:
  // a single wrong coefficient (even the last one, off by 1 %) fails this.
  const double eps = std::numeric_limits<double>::epsilon();
  for (int k = 1; k <= 1000; ++k) {
    const double x = k / 1000.0;
    const double x2 = x * x;
    const double x10 = x2 * x2 * x2 * x2 * x2;
    EXPECT_LE(std::fabs(cos_series(x2) - std::cos(x)), x10 * x2 / 479001600.0 + 4 * eps) << x;
    EXPECT_LE(std::fabs(1.0 + sinc_series_minus_1(x2) - std::sin(x) / x), x10 / 39916800.0 + 4 * eps) << x;
  }
}

TEST(RigidRotation, SincOfSquareMatchesTheLibraryToRounding) {
  // cos_sinc_of_square(x^2) gives cos x and sin(x)/x without a square root
  // for |x| <= 1/16: it must agree with std::cos and std::sin(x)/x (itself
  // rounded twice) to rounding (measured 0.5 eps), up to the switch and for
  // the tiny angles of a DEM step, and be exactly 1, 1 at x = 0.
  double worst = 0.0;
  for (int k = 1; k <= 4000; ++k) {
    for (const double scale : {1.0 / 16, 1e-3, 1e-7}) {
      const double x = scale * k / 4000.0;
      double c, sc;
      cos_sinc_of_square(x * x, c, sc);
      const double eps = std::numeric_limits<double>::epsilon();
      worst = std::max(worst, std::fabs(c - std::cos(x)) / eps);
      worst = std::max(worst, std::fabs(sc - std::sin(x) / x) / eps);  // sinc is ~1
    }
  }
  EXPECT_LE(worst, 1.0);  // in units of epsilon
  double c, sc;
  cos_sinc_of_square(0.0, c, sc);
  EXPECT_EQ(c, 1.0);
  EXPECT_EQ(sc, 1.0);
  cos_sinc_of_square(0.49, c, sc);  // beyond the switch: the library values of x = 0.7
  EXPECT_EQ(c, std::cos(0.7));
  EXPECT_EQ(sc, std::sin(0.7) / 0.7);
  const double above = std::nextafter(1.0 / 256, 1.0);  // just above the switch
  cos_sinc_of_square(above, c, sc);
  EXPECT_EQ(c, std::cos(std::sqrt(above)));
}
