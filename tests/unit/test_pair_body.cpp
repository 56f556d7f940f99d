// The spheroid pair loop's per-particle lines (pair_body.h) and their copy
// into lanes (lane_transpose.h: an 8 x 8 transpose with AVX-512, scalar
// copies otherwise): every lane of every field must hold exactly the field
// of its particle, for repeated and scattered indices alike.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "virtual_triaxial/dem/pair_body.h"

using namespace vt::dem;

namespace {

/// A body whose eight fields are distinct numbers that name particle p and field f.
PairBody numbered(int p) {
  PairBody b;
  const double base = 100.0 * p;
  b.support.b2 = base + 0.5;
  b.support.k = base + 1.25;
  b.support.e = {base + 2.0, base + 3.0, base + 4.0};
  b.support.bound = base + 5.0;
  b.radii = {base + 6.0, base + 7.0};
  return b;
}

/// Field f of b, by name, in PairBody's order.
double field(const PairBody& b, int f) {
  const double fields[PairBody::kFields] = {b.support.b2,  b.support.k,     b.support.e.x, b.support.e.y,
                                            b.support.e.z, b.support.bound, b.radii.hertz, b.radii.minor};
  return fields[f];
}

}  // namespace

TEST(PairBody, EveryLineIsAlignedInAVector) {
  // (its size and field order are static_asserts in pair_body.h)
  for (std::size_t n : {1u, 3u, 1000u}) {
    std::vector<PairBody> bodies(n);
    for (const PairBody& b : bodies) ASSERT_EQ(reinterpret_cast<std::uintptr_t>(&b) % 64, 0u) << n;
  }
}

TEST(PairBody, LanesHoldEachParticlesFieldsExactly) {
  std::vector<PairBody> bodies;
  for (int p = 0; p < 64; ++p) bodies.push_back(numbered(p));
  std::mt19937 rng(7);
  // scattered indices, then runs of one owner (as the pair loop's owners),
  // then every lane on one particle (a group's unused lanes repeat lane 0)
  std::vector<std::vector<std::int32_t>> cases;
  for (int c = 0; c < 50; ++c) {
    std::vector<std::int32_t> idx(8);
    for (auto& i : idx) i = static_cast<std::int32_t>(rng() % bodies.size());
    cases.push_back(idx);
  }
  cases.push_back({3, 3, 3, 4, 4, 9, 9, 9});
  cases.push_back({17, 17, 17, 17, 17, 17, 17, 17});
  cases.push_back({0, 1, 2, 3, 4, 5, 6, 63});
  for (const auto& idx : cases) {
    double lanes[PairBody::kFields][8];
    double* const dst[PairBody::kFields] = {lanes[0], lanes[1], lanes[2], lanes[3],
                                            lanes[4], lanes[5], lanes[6], lanes[7]};
    for (auto& row : lanes)
      for (double& x : row) x = -1.0;
    body_lanes(bodies.data(), idx.data(), dst);
    for (int f = 0; f < PairBody::kFields; ++f)
      for (int k = 0; k < 8; ++k) ASSERT_EQ(lanes[f][k], field(bodies[static_cast<std::size_t>(idx[k])], f))
          << "field " << f << " lane " << k << " particle " << idx[k];
  }
}

TEST(PairBody, FewerFieldsLeaveTheRestUntouched) {
  std::vector<PairBody> bodies;
  for (int p = 0; p < 8; ++p) bodies.push_back(numbered(p));
  const double* rows[8];
  for (int k = 0; k < 8; ++k) rows[k] = reinterpret_cast<const double*>(&bodies[static_cast<std::size_t>(7 - k)]);
  double lanes[8][8];
  for (auto& row : lanes)
    for (double& x : row) x = -2.0;
  double* const dst[3] = {lanes[0], lanes[1], lanes[2]};
  lanes::rows_to_lanes<3>(rows, dst);
  for (int f = 0; f < 3; ++f)
    for (int k = 0; k < 8; ++k) EXPECT_EQ(lanes[f][k], field(bodies[static_cast<std::size_t>(7 - k)], f));
  for (int f = 3; f < 8; ++f)
    for (int k = 0; k < 8; ++k) EXPECT_EQ(lanes[f][k], -2.0) << "field " << f << " written";
}
