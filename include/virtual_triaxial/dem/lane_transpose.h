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

}  // namespace vt::dem::lanes
