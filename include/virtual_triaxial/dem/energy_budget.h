// Energy budget of the specimen (DESIGN §5), all in J.
//
// Accumulated over steps since the reference step:
//   boundary_work      W  = sum_steps -sum_c F_on_j . (L d_c) dt, the work of
//                          the contact forces on the affine (cell) motion;
//                          positive when the cell compresses a loaded packing;
//   damping            D  = sum a m |v_mid|^2 dt + a I |w_mid|^2 dt (eq. 2);
//   friction           Fr = Coulomb sliding dissipation (HertzMindlin).
// State terms at the latest measured step: kinetic (fluctuating motion,
// translational + rotational) and elastic (normal + tangential springs).
// Balance: W = (KE - KE_ref) + (U - U_ref) + D + Fr; the relative error is a
// stability signal.
#pragma once

namespace vt::dem {

struct EnergyBudget {
  double boundary_work = 0;
  double damping = 0;
  double friction = 0;
  double kinetic_translational = 0;
  double kinetic_rotational = 0;
  double elastic = 0;
  double kinetic_reference = 0;  ///< KE at the reference step
  double elastic_reference = 0;  ///< U at the reference step
  bool has_reference = false;

  double kinetic() const { return kinetic_translational + kinetic_rotational; }
  /// W - (dKE + dU + D + Fr) [J].
  double balance_error() const {
    return boundary_work - (kinetic() - kinetic_reference + elastic - elastic_reference + damping + friction);
  }
  /// Scale used to make the balance error relative: everything that flowed.
  double scale() const;
  double relative_balance_error() const;
};

}  // namespace vt::dem
