#include <immintrin.h>
#include <chrono>
#include <cstdio>
#include <vector>
#include <random>
#include <cstdint>
struct alignas(64) Body { double v[8]; };
struct Lanes { alignas(64) double f[16][8]; };
static inline void transpose8(const __m512d r[8], double (*out)[8]) {
  __m512d t[8], u[8];
  for (int k = 0; k < 4; ++k) { t[2*k] = _mm512_unpacklo_pd(r[2*k], r[2*k+1]); t[2*k+1] = _mm512_unpackhi_pd(r[2*k], r[2*k+1]); }
  // t0 = a0 b0 a2 b2 a4 b4 a6 b6 ; t1 = a1 b1 a3 b3 ... ; t2 = c0 d0 c2 d2 ...; t3 = c1 d1 ...
  const __m512i lo = _mm512_set_epi64(13,12,5,4,9,8,1,0), hi = _mm512_set_epi64(15,14,7,6,11,10,3,2);
  u[0] = _mm512_permutex2var_pd(t[0], lo, t[2]); // a0 b0 c0 d0 a4 b4 c4 d4
  u[1] = _mm512_permutex2var_pd(t[1], lo, t[3]); // a1 b1 c1 d1 a5 ...
  u[2] = _mm512_permutex2var_pd(t[0], hi, t[2]); // a2 b2 c2 d2 a6 ...
  u[3] = _mm512_permutex2var_pd(t[1], hi, t[3]);
  u[4] = _mm512_permutex2var_pd(t[4], lo, t[6]); // e0 f0 g0 h0 e4 ...
  u[5] = _mm512_permutex2var_pd(t[5], lo, t[7]);
  u[6] = _mm512_permutex2var_pd(t[4], hi, t[6]);
  u[7] = _mm512_permutex2var_pd(t[5], hi, t[7]);
  _mm512_store_pd(out[0], _mm512_shuffle_f64x2(u[0], u[4], 0x44));
  _mm512_store_pd(out[1], _mm512_shuffle_f64x2(u[1], u[5], 0x44));
  _mm512_store_pd(out[2], _mm512_shuffle_f64x2(u[2], u[6], 0x44));
  _mm512_store_pd(out[3], _mm512_shuffle_f64x2(u[3], u[7], 0x44));
  _mm512_store_pd(out[4], _mm512_shuffle_f64x2(u[0], u[4], 0xEE));
  _mm512_store_pd(out[5], _mm512_shuffle_f64x2(u[1], u[5], 0xEE));
  _mm512_store_pd(out[6], _mm512_shuffle_f64x2(u[2], u[6], 0xEE));
  _mm512_store_pd(out[7], _mm512_shuffle_f64x2(u[3], u[7], 0xEE));
}
int main() {
  const int N = 12000, NP = 40000, R = 300;
  std::vector<Body> B(N);
  for (int i = 0; i < N; ++i) for (int f = 0; f < 8; ++f) B[i].v[f] = i * 8 + f;
  std::vector<int32_t> ii(NP * 8), jj(NP * 8);
  std::mt19937 rng(1);
  for (int p = 0; p < NP; ++p) for (int k = 0; k < 8; ++k) { int base = (p * 8 / 30) % (N - 600); ii[p*8+k] = base + (p*8+k)/3 % 3; jj[p*8+k] = base + rng() % 600; }
  Lanes L; double sink = 0;
  for (int rep = 0; rep < 2; ++rep)
  for (int mode = 0; mode < 2; ++mode) {
    auto t0 = std::chrono::steady_clock::now();
    for (int r = 0; r < R; ++r)
      for (int p = 0; p < NP; ++p) {
        const int32_t* xi = &ii[p * 8]; const int32_t* xj = &jj[p * 8];
        if (mode == 0) {
          for (int k = 0; k < 8; ++k) {
            const double* s = B[xi[k]].v; const double* t = B[xj[k]].v;
            for (int f = 0; f < 8; ++f) { L.f[f][k] = s[f]; L.f[8+f][k] = t[f]; }
          }
        } else {
          __m512d r[8];
          for (int k = 0; k < 8; ++k) r[k] = _mm512_load_pd(B[xi[k]].v);
          transpose8(r, L.f);
          for (int k = 0; k < 8; ++k) r[k] = _mm512_load_pd(B[xj[k]].v);
          transpose8(r, L.f + 8);
        }
        asm volatile("" ::"r"(&L) : "memory");
        sink += L.f[3][2] + L.f[12][5];
      }
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    printf("mode %d: %.2f ns per 8-lane group (16 fields)\n", mode, s * 1e9 / (R * (double)NP));
  }
  // check
  { const int32_t* xi = &ii[0]; const int32_t* xj = &jj[0]; __m512d r[8];
    for (int k = 0; k < 8; ++k) r[k] = _mm512_load_pd(B[xi[k]].v); transpose8(r, L.f);
    for (int k = 0; k < 8; ++k) r[k] = _mm512_load_pd(B[xj[k]].v); transpose8(r, L.f + 8);
    int bad = 0; for (int k = 0; k < 8; ++k) for (int f = 0; f < 8; ++f) { bad += L.f[f][k] != B[xi[k]].v[f]; bad += L.f[8+f][k] != B[xj[k]].v[f]; }
    printf("bad %d\n", bad); }
  printf("%g\n", sink);
}
