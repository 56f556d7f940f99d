// Copies of eight particles' records (a 64-byte line of eight doubles each)
// into SIMD lanes (one array of eight doubles per field):
//   rows_to_lanes<F>(rows, dst)   dst[f][k] = rows[k][f], f < F <= 8, k < 8,
//                                 rows[k] 64-byte aligned, 8 readable doubles.
// Plain copies, so both forms give the same bits. Per lane that is F scalar
// loads and F scalar stores; with AVX-512 one 64-byte load per row, an
// 8 x 8 transpose (24 shuffles) and one store per field. On the project's
// AMD EPYC host a block took 4.6 ns against 19 ns by scalars in a
// micro-benchmark (in the spheroid pair loop the whole change saved 0.9 %
// on one thread and 2.6 % on two: the stores were not what limited it).
// tests/unit/test_pair_body.cpp checks the form compiled against the fields
// copied one by one.
//
// records_to_lanes<N> / lanes_to_records<N> do the same for eight
// consecutive records of N = 3 or 4 doubles (a Vec3 array as x, y, z, ...;
// a Quaternion array as w, x, y, z, ...) and back. With AVX-512: N vector
// loads, shuffles (records_to_lanes two per field for N = 3, three for
// N = 4; lanes_to_records two per field), N vector stores, written with
// GCC's vector extensions; without AVX-512, scalar copies. Plain copies:
// both forms give the same bits (tests/unit/test_record_lanes.cpp).
#pragma once

#include <cstdint>

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

namespace vt::dem::lanes {

#if defined(__AVX512F__)
// GCC 12's avx512fintrin.h starts unpack and shuffle results from
// _mm512_undefined_pd() and warns that it is uninitialised (a false alarm).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

/// An index vector for _mm512_permutex2var_pd (0-7: first source, 8-15: second).
inline __m512i pick(long long a, long long b, long long c, long long d, long long e, long long f, long long g,
                    long long h) {
  return _mm512_set_epi64(h, g, f, e, d, c, b, a);
}

/// The 8 x 8 transpose: r[k] holds fields 0..7 of lane k; out[f] lanes 0..7 of field f.
__attribute__((always_inline)) inline void transpose8(const __m512d* r, __m512d* out) {
  __m512d t[8];
  for (int k = 0; k < 4; ++k) {
    t[2 * k] = _mm512_unpacklo_pd(r[2 * k], r[2 * k + 1]);      // f0 of k, k+1; f2 ...; f4 ...; f6 ...
    t[2 * k + 1] = _mm512_unpackhi_pd(r[2 * k], r[2 * k + 1]);  // f1, f3, f5, f7
  }
  const __m512i lo = pick(0, 1, 8, 9, 4, 5, 12, 13);
  const __m512i hi = pick(2, 3, 10, 11, 6, 7, 14, 15);
  __m512d u[8];
  u[0] = _mm512_permutex2var_pd(t[0], lo, t[2]);  // f0 of lanes 0-3, f4 of lanes 0-3
  u[1] = _mm512_permutex2var_pd(t[1], lo, t[3]);  // f1, f5
  u[2] = _mm512_permutex2var_pd(t[0], hi, t[2]);  // f2, f6
  u[3] = _mm512_permutex2var_pd(t[1], hi, t[3]);  // f3, f7
  u[4] = _mm512_permutex2var_pd(t[4], lo, t[6]);  // the same of lanes 4-7
  u[5] = _mm512_permutex2var_pd(t[5], lo, t[7]);
  u[6] = _mm512_permutex2var_pd(t[4], hi, t[6]);
  u[7] = _mm512_permutex2var_pd(t[5], hi, t[7]);
  for (int f = 0; f < 4; ++f) {
    out[f] = _mm512_shuffle_f64x2(u[f], u[f + 4], 0x44);
    out[f + 4] = _mm512_shuffle_f64x2(u[f], u[f + 4], 0xEE);
  }
}
#endif

/// dst[f][k] = rows[k][f] for f < F, k < 8 (each row 64-byte aligned with
/// eight readable doubles).
template <int F>
__attribute__((always_inline)) inline void rows_to_lanes(const double* const* rows, double* const* dst) {
  static_assert(F >= 1 && F <= 8, "at most eight fields");
#if defined(__AVX512F__)
  __m512d r[8], out[8];
  for (int k = 0; k < 8; ++k) r[k] = _mm512_load_pd(rows[k]);
  transpose8(r, out);
  for (int f = 0; f < F; ++f) _mm512_storeu_pd(dst[f], out[f]);
#else
  for (int k = 0; k < 8; ++k)
    for (int f = 0; f < F; ++f) dst[f][k] = rows[k][f];
#endif
}

#if defined(__AVX512F__)
#pragma GCC diagnostic pop
#endif

/// dst[f][k] = src[N k + f] for f < N, k < 8 (N = 3: Vec3 records, N = 4:
/// Quaternion records; 8 N doubles from src).
template <int N>
__attribute__((always_inline)) inline void records_to_lanes(const double* src, double (*dst)[8]);
/// The inverse: dst[N k + f] = src[f][k] for f < N, k < 8.
template <int N>
__attribute__((always_inline)) inline void lanes_to_records(const double (*src)[8], double* dst);

#if defined(__AVX512F__)
namespace detail {
/// Eight doubles, and eight indices for __builtin_shuffle (0-7: the first
/// source, 8-15: the second).
typedef double Doubles8 __attribute__((vector_size(64)));
typedef long long Picks8 __attribute__((vector_size(64)));
__attribute__((always_inline)) inline Doubles8 load8(const double* a) {
  Doubles8 v;
  __builtin_memcpy(&v, a, sizeof v);
  return v;
}
__attribute__((always_inline)) inline void store8(double* a, const Doubles8& v) { __builtin_memcpy(a, &v, sizeof v); }
}  // namespace detail

template <int N>
inline void records_to_lanes(const double* src, double (*dst)[8]) {
  static_assert(N == 3 || N == 4, "records of three or four doubles");
  using namespace detail;
  if constexpr (N == 3) {
    // field f of record k is element 3k + f of a|b|c (24 doubles)
    const Doubles8 a = load8(src), b = load8(src + 8), c = load8(src + 16);
    store8(dst[0], __builtin_shuffle(__builtin_shuffle(a, b, Picks8{0, 3, 6, 9, 12, 15, 0, 0}), c,
                                     Picks8{0, 1, 2, 3, 4, 5, 10, 13}));
    store8(dst[1], __builtin_shuffle(__builtin_shuffle(a, b, Picks8{1, 4, 7, 10, 13, 0, 0, 0}), c,
                                     Picks8{0, 1, 2, 3, 4, 8, 11, 14}));
    store8(dst[2], __builtin_shuffle(__builtin_shuffle(a, b, Picks8{2, 5, 8, 11, 14, 0, 0, 0}), c,
                                     Picks8{0, 1, 2, 3, 4, 9, 12, 15}));
  } else {
    // field f of records 0-3 from a|b, of records 4-7 from c|d
    const Doubles8 a = load8(src), b = load8(src + 8), c = load8(src + 16), d = load8(src + 24);
    for (long long f = 0; f < 4; ++f) {
      const Picks8 pick{f, f + 4, f + 8, f + 12, 0, 0, 0, 0};
      store8(dst[f], __builtin_shuffle(__builtin_shuffle(a, b, pick), __builtin_shuffle(c, d, pick),
                                       Picks8{0, 1, 2, 3, 8, 9, 10, 11}));
    }
  }
}

template <int N>
inline void lanes_to_records(const double (*src)[8], double* dst) {
  static_assert(N == 3 || N == 4, "records of three or four doubles");
  using namespace detail;
  if constexpr (N == 3) {
    const Doubles8 x = load8(src[0]), y = load8(src[1]), z = load8(src[2]);
    // x0 y0 z0 x1 y1 z1 x2 y2 | z2 x3 y3 z3 x4 y4 z4 x5 | y5 z5 x6 y6 z6 x7 y7 z7
    store8(dst, __builtin_shuffle(__builtin_shuffle(x, y, Picks8{0, 8, 0, 1, 9, 0, 2, 10}), z,
                                  Picks8{0, 1, 8, 3, 4, 9, 6, 7}));
    store8(dst + 8, __builtin_shuffle(__builtin_shuffle(x, y, Picks8{0, 3, 11, 0, 4, 12, 0, 5}), z,
                                      Picks8{10, 1, 2, 11, 4, 5, 12, 7}));
    store8(dst + 16, __builtin_shuffle(__builtin_shuffle(x, y, Picks8{13, 0, 6, 14, 0, 7, 15, 0}), z,
                                       Picks8{0, 13, 2, 3, 14, 5, 6, 15}));
  } else {
    const Doubles8 w = load8(src[0]), x = load8(src[1]), y = load8(src[2]), z = load8(src[3]);
    // (w, x) and (y, z) interleaved for records 0-3 and 4-7, then two records per store
    const Picks8 lo{0, 8, 1, 9, 2, 10, 3, 11}, hi{4, 12, 5, 13, 6, 14, 7, 15};
    const Doubles8 wx0 = __builtin_shuffle(w, x, lo), yz0 = __builtin_shuffle(y, z, lo);
    const Doubles8 wx1 = __builtin_shuffle(w, x, hi), yz1 = __builtin_shuffle(y, z, hi);
    const Picks8 first{0, 1, 8, 9, 2, 3, 10, 11}, second{4, 5, 12, 13, 6, 7, 14, 15};
    store8(dst, __builtin_shuffle(wx0, yz0, first));
    store8(dst + 8, __builtin_shuffle(wx0, yz0, second));
    store8(dst + 16, __builtin_shuffle(wx1, yz1, first));
    store8(dst + 24, __builtin_shuffle(wx1, yz1, second));
  }
}
#else
template <int N>
inline void records_to_lanes(const double* src, double (*dst)[8]) {
  static_assert(N == 3 || N == 4, "records of three or four doubles");
  for (int k = 0; k < 8; ++k)
    for (int f = 0; f < N; ++f) dst[f][k] = src[N * k + f];
}

template <int N>
inline void lanes_to_records(const double (*src)[8], double* dst) {
  static_assert(N == 3 || N == 4, "records of three or four doubles");
  for (int k = 0; k < 8; ++k)
    for (int f = 0; f < N; ++f) dst[N * k + f] = src[f][k];
}
#endif

}  // namespace vt::dem::lanes
