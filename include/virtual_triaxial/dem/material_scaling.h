// Density and stiffness scaling of a saved state (chapter 3.3-3.4; the
// dimensionless scheme of chapter 3.2, appendices 1-2).
//
// `scale_material` gives a state the density rho' = f_rho rho and Young's
// modulus E' = f_E E while keeping every DIMENSIONLESS quantity of it:
//   geometry (positions, sizes, overlaps) unchanged        [m]
//   mass, inertia            x f_rho                       [kg], [kg m^2]
//   velocity, omega          x sqrt(f_E / f_rho)           (v T0/L0, omega T0 kept;
//                                                           T0 = L0 sqrt(rho/E))
//   tangential springs       x f_E                         [N] (F / (E L0^2) kept)
//   energy budget terms      x f_E                         [J] (W / (E L0^3) kept)
//   time                     x sqrt(f_rho / f_E)           [s] (t / T0 kept)
// so that sigma_bar = sigma/E, eps' = epsdot T0, xi and c_t mean the same
// thing before and after. Consequences (the dissertation's equivalences):
//   * a test given in eps' runs the same dimensionless history (section
//     3.3.2; bit for bit when f_rho and f_E are powers of two);
//   * density scaling at a fixed epsdot [1/s] = a higher eps' by
//     sqrt(f_rho) (mass scaling, table 7 D-1/D-1e);
//   * stiffness scaling 1/f at a fixed epsdot and a fixed confining pressure
//     [Pa] = eps' higher by sqrt(f) and sigma_bar higher by f (table 7
//     D-2/D-2e).
// Geometry is unchanged, so the Poisson ratio and the sizes are not scaled
// here (a different nu changes the contact law itself).
#pragma once

#include "virtual_triaxial/dem/simulation.h"

namespace vt::dem {

/// Scales `state` to density `density` [kg/m^3] and modulus `young` [Pa]
/// as above. Throws std::invalid_argument ("material.density: ...",
/// "material.young_modulus: ...") for a non-positive or non-finite value.
void scale_material(SimulationState& state, double density, double young);

}  // namespace vt::dem
