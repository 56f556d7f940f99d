// Particle material (SI): density rho [kg/m^3], Young's modulus E [Pa],
// Poisson's ratio nu [-], inter-particle friction coefficient mu [-].
#pragma once

#include <string>

namespace vt::dem {

struct Material {
  double density = 2650.0;
  double young = 70e9;
  double poisson = 0.3;
  double friction = 0.5;

  /// Empty string when valid, otherwise "field: reason".
  std::string validate() const;
};

}  // namespace vt::dem
