#include "virtual_triaxial/dem/material_scaling.h"

#include <cmath>
#include <stdexcept>

namespace vt::dem {

void scale_material(SimulationState& s, double density, double young) {
  if (!(std::isfinite(density) && density > 0.0))
    throw std::invalid_argument("material.density: must be finite and > 0");
  if (!(std::isfinite(young) && young > 0.0))
    throw std::invalid_argument("material.young_modulus: must be finite and > 0");
  const double f_rho = density / s.settings.material.density;
  const double f_e = young / s.settings.material.young;
  if (f_rho == 1.0 && f_e == 1.0) return;
  const double f_v = std::sqrt(f_e / f_rho);
  Particles& p = s.particles;
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.mass[i] *= f_rho;
    p.inertia[i] = p.inertia[i] * f_rho;
    p.velocity[i] = p.velocity[i] * f_v;
    p.omega[i] = p.omega[i] * f_v;
  }
  for (ContactHistory& c : s.contacts) c.spring = c.spring * f_e;
  EnergyBudget& e = s.energy;
  for (double* t : {&e.boundary_work, &e.damping, &e.friction, &e.kinetic_translational,
                    &e.kinetic_rotational, &e.elastic, &e.kinetic_reference, &e.elastic_reference})
    *t *= f_e;
  s.time /= f_v;
  s.velocity_gradient = f_v * s.velocity_gradient;
  s.settings.material.density = density;
  s.settings.material.young = young;
}

}  // namespace vt::dem
