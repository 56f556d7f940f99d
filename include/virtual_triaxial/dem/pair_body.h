// A particle's data for the spheroid pair loop in one cache line, and the
// copy of eight particles' lines into the loop's lanes.
//
// PairBody (64 bytes, one line): the support data of the particle this
// evaluation (SpheroidSupport, spheroid_contact.h: b^2, a^2 - b^2 [m^2], the
// symmetry axis e, the bounding radius [m]) and its contact radii
// (ContactRadii: R_i of eq. 104 and b [m]), eight doubles in that order.
//
// body_lanes(body, idx, dst) sets dst[f][k] = field f of particle idx[k]
// for the eight fields f and eight lanes k: the pair loop's lanes of the
// owners (or the partners) of a group of eight pairs, by the 8 x 8
// transpose of lane_transpose.h (with AVX-512: one load per particle and
// one store per field instead of eight scalar loads and stores per lane).
#pragma once

#include <cstddef>
#include <cstdint>

#include "virtual_triaxial/dem/lane_transpose.h"
#include "virtual_triaxial/dem/spheroid_contact.h"

namespace vt::dem {

/// Per-particle radii the spheroid contact law reads for a partner: R_i of
/// eq. 104, the average radius (a + 2b)/3 (R for a sphere), and the minor
/// semi-axis b (R for a sphere) [m].
struct ContactRadii {
  double hertz = 0.0;
  double minor = 0.0;
};

struct alignas(64) PairBody {
  SpheroidSupport support;
  ContactRadii radii;
  static constexpr int kFields = 8;
};
static_assert(sizeof(SpheroidSupport) == 6 * sizeof(double), "SpheroidSupport: b2, k, e, bound");
static_assert(sizeof(ContactRadii) == 2 * sizeof(double), "ContactRadii: hertz, minor");
static_assert(sizeof(PairBody) == 64, "one cache line");
static_assert(offsetof(PairBody, support) == 0 && offsetof(SpheroidSupport, b2) == 0 &&
                  offsetof(SpheroidSupport, k) == 8 && offsetof(SpheroidSupport, e) == 16 &&
                  offsetof(SpheroidSupport, bound) == 40 && offsetof(PairBody, radii) == 48 &&
                  offsetof(ContactRadii, hertz) == 0 && offsetof(ContactRadii, minor) == 8,
              "the fields in body_lanes' order");

/// The lanes body_lanes fills at a time.
constexpr int kBodyLanes = 8;

/// dst[f][k] = field f (in PairBody's order: b2, k, e.x, e.y, e.z, bound,
/// hertz, minor) of body[idx[k]], for f and k in 0..7. Each dst[f] points
/// to eight doubles.
__attribute__((always_inline)) inline void body_lanes(const PairBody* body, const std::int32_t* idx,
                                                      double* const* dst) {
  const double* rows[kBodyLanes];
  for (int k = 0; k < kBodyLanes; ++k) rows[k] = reinterpret_cast<const double*>(body + idx[k]);
  lanes::rows_to_lanes<PairBody::kFields>(rows, dst);
}

}  // namespace vt::dem
