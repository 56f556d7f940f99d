#include "virtual_triaxial/dem/material.h"

#include <cmath>

namespace vt::dem {

std::string Material::validate() const {
  if (!(std::isfinite(density) && density > 0.0)) return "density: must be a finite number > 0 kg/m^3";
  if (!(std::isfinite(young) && young > 0.0)) return "young_modulus: must be a finite number > 0 Pa";
  if (!(std::isfinite(poisson) && poisson > -1.0 && poisson < 0.5))
    return "poisson_ratio: must lie in (-1, 0.5)";
  if (!(std::isfinite(friction) && friction >= 0.0)) return "friction: must be a finite number >= 0";
  return {};
}

}  // namespace vt::dem
