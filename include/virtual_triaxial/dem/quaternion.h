// Unit quaternion for particle orientation (body -> world rotation).
#pragma once

#include "virtual_triaxial/dem/vec3.h"

namespace vt::dem {

struct Quaternion {
  double w = 1.0, x = 0.0, y = 0.0, z = 0.0;

  /// Rotate a body-frame vector into the world frame.
  Vec3 rotate(const Vec3& v) const {
    const Vec3 u{x, y, z};
    const Vec3 t = 2.0 * cross(u, v);
    return v + w * t + cross(u, t);
  }
  /// Rotate a world-frame vector into the body frame.
  Vec3 rotate_inverse(const Vec3& v) const { return Quaternion{w, -x, -y, -z}.rotate(v); }
};

inline Quaternion operator*(const Quaternion& a, const Quaternion& b) {
  return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,
          a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
          a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
          a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

}  // namespace vt::dem
