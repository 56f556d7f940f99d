#include "virtual_triaxial/dem/local_damping.h"

#include <stdexcept>

namespace vt::dem {

LocalDamping::LocalDamping(double coefficient) : a_(coefficient) {
  if (!(coefficient >= 0.0 && coefficient < 1.0)) throw std::invalid_argument("coefficient: must be in [0, 1)");
}

}  // namespace vt::dem
