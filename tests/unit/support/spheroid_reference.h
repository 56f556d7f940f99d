// Shared by the spheroid contact tests (test_spheroid_contact.cpp,
// test_spheroid_contact_solver.cpp): deterministic random numbers and
// orientations, and an independent long-double reference of the spheroid
// contact (written without spheroid.h: full rotation matrix and inverse
// shape matrix, support function, brute-force minimum of the gap; and the
// exact inverse construction of a pair with a given normal and overlap).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>

#include "virtual_triaxial/dem/spheroid.h"
#include "virtual_triaxial/dem/spheroid_contact.h"

namespace vt::test {

using dem::Quaternion;
using dem::Spheroid;
using dem::Vec3;

// ---- deterministic random numbers ----------------------------------------
struct Rng {
  std::mt19937_64 g;
  explicit Rng(std::uint64_t seed) : g(seed) {}
  double uniform() { return static_cast<double>(g() >> 11) * 0x1.0p-53; }  // [0,1)
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  Vec3 direction() {  // uniform on the unit sphere
    const double z = uniform(-1.0, 1.0), phi = uniform(0.0, 2.0 * M_PI);
    const double r = std::sqrt(1.0 - z * z);
    return {r * std::cos(phi), r * std::sin(phi), z};
  }
  Quaternion rotation() {  // uniform random rotation (Shoemake)
    const double u1 = uniform(), u2 = uniform(0.0, 2.0 * M_PI), u3 = uniform(0.0, 2.0 * M_PI);
    const double s1 = std::sqrt(1.0 - u1), s2 = std::sqrt(u1);
    return {s1 * std::sin(u2), s1 * std::cos(u2), s2 * std::sin(u3), s2 * std::cos(u3)};
  }
};

inline Quaternion axis_rotation(const Vec3& u, double phi) {
  const double s = std::sin(0.5 * phi);
  return {std::cos(0.5 * phi), s * u.x, s * u.y, s * u.z};
}

/// Orientation whose body x axis is the unit vector u.
inline Quaternion x_axis_to(const Vec3& u) {
  const Vec3 x{1, 0, 0};
  const double c = dot(x, u);
  const Vec3 ax = cross(x, u);
  const double s = norm(ax);
  if (s < 1e-300) return c > 0 ? Quaternion{} : Quaternion{0, 0, 0, 1};
  return axis_rotation((1.0 / s) * ax, std::atan2(s, c));
}

/// A unit vector perpendicular to unit n.
inline Vec3 normalized_perp(const Vec3& n) {
  const Vec3 r = std::fabs(n.x) < 0.6 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 t = r - dot(r, n) * n;
  return (1.0 / norm(t)) * t;
}

inline double max_abs(const Vec3& v) { return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}); }

// ---- independent long-double reference ---------------------------------------
// Written without spheroid.h: full rotation matrix from the quaternion, full
// inverse shape matrix R diag(a^2, b^2, b^2) R^T, support function
// sqrt(n^T A^-1 n); delta = min over the unit sphere of h_i + h_j - n.d by
// dense sampling and a shrinking pattern search.
using LD = long double;
struct V3 {
  LD x, y, z;
};
inline V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline V3 operator*(LD s, V3 a) { return {s * a.x, s * a.y, s * a.z}; }
inline LD dotl(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline V3 unit(V3 a) { return (1.0L / std::sqrt(dotl(a, a))) * a; }
inline V3 to_l(const Vec3& v) { return {v.x, v.y, v.z}; }

struct RefBody {
  LD m[3][3];  // A^-1
  V3 support_point(V3 n) const {
    V3 an{m[0][0] * n.x + m[0][1] * n.y + m[0][2] * n.z, m[1][0] * n.x + m[1][1] * n.y + m[1][2] * n.z,
          m[2][0] * n.x + m[2][1] * n.y + m[2][2] * n.z};
    return (1.0L / std::sqrt(dotl(n, an))) * an;
  }
  LD support(V3 n) const { return dotl(n, support_point(n)); }
};

inline RefBody ref_body(const Spheroid& s) {
  const LD w = s.q.w, x = s.q.x, y = s.q.y, z = s.q.z;
  const LD nq = std::sqrt(w * w + x * x + y * y + z * z);
  const LD qw = w / nq, qx = x / nq, qy = y / nq, qz = z / nq;
  const LD r[3][3] = {{1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qw * qz), 2 * (qx * qz + qw * qy)},
                      {2 * (qx * qy + qw * qz), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qw * qx)},
                      {2 * (qx * qz - qw * qy), 2 * (qy * qz + qw * qx), 1 - 2 * (qx * qx + qy * qy)}};
  const LD dg[3] = {LD(s.a) * s.a, LD(s.b) * s.b, LD(s.b) * s.b};
  RefBody b;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      b.m[i][j] = 0;
      for (int k = 0; k < 3; ++k) b.m[i][j] += r[i][k] * dg[k] * r[j][k];
    }
  return b;
}

struct RefResult {
  LD overlap;
  V3 normal;
};

inline RefResult brute_force(const Spheroid& si, const Spheroid& sj, const Vec3& dd) {
  const RefBody bi = ref_body(si), bj = ref_body(sj);
  const V3 d = to_l(dd);
  auto g = [&](V3 n) { return bi.support(n) + bj.support(n) - dotl(n, d); };
  // Fibonacci sphere, 20000 points.
  const int N = 20000;
  const LD golden = M_PI * (3.0L - std::sqrt(5.0L));
  V3 best{0, 0, 1};
  LD gbest = g(best);
  for (int k = 0; k < N; ++k) {
    const LD z = 1.0L - (2.0L * k + 1.0L) / N;
    const LD r = std::sqrt(1.0L - z * z);
    const V3 n{r * std::cos(golden * k), r * std::sin(golden * k), z};
    const LD gv = g(n);
    if (gv < gbest) {
      gbest = gv;
      best = n;
    }
  }
  // Pattern search on the tangent plane, 8 directions, shrinking step.
  for (LD step = 0.05L; step > 1e-14L;) {
    const V3 ref = std::fabs(best.x) < 0.6L ? V3{1, 0, 0} : V3{0, 1, 0};
    const V3 t1 = unit(ref - dotl(ref, best) * best);
    const V3 t2{best.y * t1.z - best.z * t1.y, best.z * t1.x - best.x * t1.z, best.x * t1.y - best.y * t1.x};
    bool improved = false;
    for (int k = 0; k < 8; ++k) {
      const LD ang = k * M_PI / 4;
      const V3 n = unit(best + (step * std::cos(ang)) * t1 + (step * std::sin(ang)) * t2);
      const LD gv = g(n);
      if (gv < gbest) {
        gbest = gv;
        best = n;
        improved = true;
      }
    }
    if (!improved) step *= 0.5L;
  }
  return {gbest, best};
}

/// Exact inverse construction: for a unit normal n, y = p_i(n) + p_j(n) is the
/// point of the Minkowski sum's boundary with outward normal n; the branch
/// vector d = y - delta n then has overlap delta and normal n (delta below the
/// smallest radius of curvature of the boundary).
struct Constructed {
  Vec3 d;
  V3 normal, contact;
  LD overlap;
};
inline Constructed construct(const Spheroid& si, const Spheroid& sj, const Vec3& n, double delta) {
  const RefBody bi = ref_body(si), bj = ref_body(sj);
  const V3 nl = unit(to_l(n));
  const V3 pi = bi.support_point(nl), pj = bj.support_point(nl);
  const V3 d = pi + pj - LD(delta) * nl;
  Constructed c;
  c.d = {double(d.x), double(d.y), double(d.z)};
  c.normal = nl;
  c.overlap = delta;
  c.contact = pi - (LD(delta) / 2) * nl;
  return c;
}

inline LD dist(V3 a, const Vec3& b) { return std::sqrt(dotl(a - to_l(b), a - to_l(b))); }

struct RandomPair {
  Spheroid si, sj;
  Vec3 n;
  double delta, bmin;
};
inline RandomPair random_pair(Rng& rng, double b0) {
  RandomPair p;
  const double bi = b0 * rng.uniform(0.6, 1.4), bj = b0 * rng.uniform(0.6, 1.4);
  p.si = Spheroid(bi * rng.uniform(1.0, 2.0), bi, rng.rotation());
  p.sj = Spheroid(bj * rng.uniform(1.0, 2.0), bj, rng.rotation());
  p.bmin = std::min(bi, bj);
  p.delta = p.bmin * std::pow(10.0, rng.uniform(-4.0, -2.0));
  p.n = rng.direction();
  return p;
}

}  // namespace vt::test
