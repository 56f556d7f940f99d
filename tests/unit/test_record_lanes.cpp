// records_to_lanes / lanes_to_records (lane_transpose.h): eight consecutive
// records of three (Vec3) or four (Quaternion) doubles into lanes field by
// field and back, by vector shuffles. Every lane must hold exactly its
// record's field, every record its lanes' values, and nothing outside the
// 8 N doubles may be written.
#include <gtest/gtest.h>

#include <vector>

#include "virtual_triaxial/dem/lane_transpose.h"

using namespace vt::dem::lanes;

namespace {

/// A distinct value for field f of record k (exact in double).
double named(int k, int f) { return 100.0 * k + f + 0.25; }

template <int N>
void check_records_to_lanes() {
  // records from an offset of one double: the loads need no alignment
  std::vector<double> src(8 * N + 2, -1.0);
  for (int k = 0; k < 8; ++k)
    for (int f = 0; f < N; ++f) src[1 + N * k + f] = named(k, f);
  double lanes[N][8];
  records_to_lanes<N>(src.data() + 1, lanes);
  for (int f = 0; f < N; ++f)
    for (int k = 0; k < 8; ++k) EXPECT_EQ(lanes[f][k], named(k, f)) << "N " << N << " field " << f << " lane " << k;
}

template <int N>
void check_lanes_to_records() {
  double lanes[N][8];
  for (int f = 0; f < N; ++f)
    for (int k = 0; k < 8; ++k) lanes[f][k] = named(k, f);
  std::vector<double> dst(8 * N + 2, -1.0);
  lanes_to_records<N>(lanes, dst.data() + 1);
  EXPECT_EQ(dst.front(), -1.0) << "N " << N << ": written before the records";
  EXPECT_EQ(dst.back(), -1.0) << "N " << N << ": written after the records";
  for (int k = 0; k < 8; ++k)
    for (int f = 0; f < N; ++f)
      EXPECT_EQ(dst[1 + N * k + f], named(k, f)) << "N " << N << " record " << k << " field " << f;
}

}  // namespace

TEST(RecordLanes, Vec3RecordsIntoLanesFieldByField) { check_records_to_lanes<3>(); }
TEST(RecordLanes, QuaternionRecordsIntoLanesFieldByField) { check_records_to_lanes<4>(); }
TEST(RecordLanes, LanesBackIntoVec3RecordsAndNothingElse) { check_lanes_to_records<3>(); }
TEST(RecordLanes, LanesBackIntoQuaternionRecordsAndNothingElse) { check_lanes_to_records<4>(); }
