// Small fixed-size vector and matrix types for the DEM core.
//
// Plain aggregates with inline operators: no hidden temporaries on the hot
// path, and every operation is an IEEE multiply/add so that power-of-two
// rescaling of inputs rescales every result exactly (the bit-for-bit
// dimensionless-invariance test of DESIGN §3 relies on this).
#pragma once

#include <cmath>

namespace vt::dem {

struct Vec3 {
  double x = 0.0, y = 0.0, z = 0.0;

  double& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  Vec3& operator+=(const Vec3& o) { x += o.x; y += o.y; z += o.z; return *this; }
  Vec3& operator-=(const Vec3& o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
  Vec3& operator*=(double s) { x *= s; y *= s; z *= s; return *this; }
};

inline Vec3 operator+(const Vec3& a, const Vec3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(const Vec3& a, const Vec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator-(const Vec3& a) { return {-a.x, -a.y, -a.z}; }
inline Vec3 operator*(double s, const Vec3& a) { return {s * a.x, s * a.y, s * a.z}; }
inline Vec3 operator*(const Vec3& a, double s) { return {s * a.x, s * a.y, s * a.z}; }
inline double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double norm2(const Vec3& a) { return dot(a, a); }
/// s a + b, the same bits wherever it is written: with hardware FMA
/// (FP_FAST_FMA, e.g. -march=native on x86-64) one rounding per component
/// (std::fma), whatever the compiler's contraction choices in the
/// surrounding code; without it the compiler cannot contract either, and a
/// library fma would be slow, so the product is rounded, then the sum.
inline Vec3 fused_multiply_add(double s, const Vec3& a, const Vec3& b) {
#ifdef FP_FAST_FMA
  return {std::fma(s, a.x, b.x), std::fma(s, a.y, b.y), std::fma(s, a.z, b.z)};
#else
  return {s * a.x + b.x, s * a.y + b.y, s * a.z + b.z};
#endif
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
/// c ? a : b per component: a select, not a jump (so that a loop over
/// contacts that uses it can run as SIMD; see src/dem/sphere_pairs.cpp).
inline Vec3 select(bool c, const Vec3& a, const Vec3& b) {
  return {c ? a.x : b.x, c ? a.y : b.y, c ? a.z : b.z};
}

/// Row-major 3x3 matrix, m[r][c].
struct Mat3 {
  double m[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};

  static Mat3 identity() {
    Mat3 r;
    r.m[0][0] = r.m[1][1] = r.m[2][2] = 1.0;
    return r;
  }
  static Mat3 diagonal(const Vec3& d) {
    Mat3 r;
    r.m[0][0] = d.x; r.m[1][1] = d.y; r.m[2][2] = d.z;
    return r;
  }
  double operator()(int r, int c) const { return m[r][c]; }
  double& operator()(int r, int c) { return m[r][c]; }
  double trace() const { return m[0][0] + m[1][1] + m[2][2]; }
  Vec3 column(int c) const { return {m[0][c], m[1][c], m[2][c]}; }
};

/// Frobenius norm of m - s I (s = 0: of m itself).
inline double frobenius_distance(const Mat3& m, double s) {
  double sum = 0.0;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      const double d = m.m[a][b] - (a == b ? s : 0.0);
      sum += d * d;
    }
  return std::sqrt(sum);
}

inline Vec3 operator*(const Mat3& a, const Vec3& v) {
  return {a.m[0][0] * v.x + a.m[0][1] * v.y + a.m[0][2] * v.z,
          a.m[1][0] * v.x + a.m[1][1] * v.y + a.m[1][2] * v.z,
          a.m[2][0] * v.x + a.m[2][1] * v.y + a.m[2][2] * v.z};
}
inline Mat3 operator*(const Mat3& a, const Mat3& b) {
  Mat3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      r.m[i][j] = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j];
  return r;
}
inline Mat3 operator+(const Mat3& a, const Mat3& b) {
  Mat3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.m[i][j] = a.m[i][j] + b.m[i][j];
  return r;
}
inline Mat3 operator*(double s, const Mat3& a) {
  Mat3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.m[i][j] = s * a.m[i][j];
  return r;
}
inline double determinant(const Mat3& a) {
  return a.m[0][0] * (a.m[1][1] * a.m[2][2] - a.m[1][2] * a.m[2][1]) -
         a.m[0][1] * (a.m[1][0] * a.m[2][2] - a.m[1][2] * a.m[2][0]) +
         a.m[0][2] * (a.m[1][0] * a.m[2][1] - a.m[1][1] * a.m[2][0]);
}
Mat3 inverse(const Mat3& a);
/// Outer product a b^T.
inline Mat3 outer(const Vec3& a, const Vec3& b) {
  Mat3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.m[i][j] = a[i] * b[j];
  return r;
}
/// Frobenius inner product a : b.
inline double contract(const Mat3& a, const Mat3& b) {
  double s = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) s += a.m[i][j] * b.m[i][j];
  return s;
}

}  // namespace vt::dem
