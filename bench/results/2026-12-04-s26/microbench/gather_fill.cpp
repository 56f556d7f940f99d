#include <immintrin.h>
#include <chrono>
#include <cstdio>
#include <vector>
#include <random>
#include <cstdint>
// fill 24 fields of 8 lanes from AoS particle data (stride 8 doubles) by index
struct Lanes { alignas(64) double f[24][8]; };
int main() {
  const int N = 12000, NP = 40000, R = 200;
  std::vector<double> P(N * 24);
  for (int i = 0; i < N * 24; ++i) P[i] = i * 0.5;
  std::vector<int32_t> idx(NP * 8);
  std::mt19937 rng(1);
  for (auto& x : idx) x = (int)(rng() % 600) + 0;  // local partners (in cache)
  for (int p = 0; p < NP; ++p) for (int k = 0; k < 8; ++k) idx[p * 8 + k] += (p * 8 / 30) % (N - 600);
  Lanes L; double sink = 0;
  for (int mode = 0; mode < 2; ++mode) {
    auto t0 = std::chrono::steady_clock::now();
    for (int r = 0; r < R; ++r)
      for (int p = 0; p < NP; p += 1) {
        const int32_t* ix = &idx[p * 8];
        if (mode == 0) {
          for (int k = 0; k < 8; ++k) {
            const double* s = &P[ix[k] * 24];
            for (int f = 0; f < 24; ++f) L.f[f][k] = s[f];
          }
        } else {
          __m256i vi = _mm256_loadu_si256((const __m256i*)ix);
          vi = _mm256_mullo_epi32(vi, _mm256_set1_epi32(24));
          for (int f = 0; f < 24; ++f) _mm512_store_pd(L.f[f], _mm512_i32gather_pd(vi, &P[f], 8));
        }
        asm volatile("" ::"r"(&L) : "memory");
        sink += L.f[3][2];
      }
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    printf("mode %d: %.2f ns per 8-lane group (24 fields) = %.2f ns per element\n", mode, s * 1e9 / (R * (double)NP), s * 1e9 / (R * (double)NP * 192));
  }
  printf("%g\n", sink);
}
