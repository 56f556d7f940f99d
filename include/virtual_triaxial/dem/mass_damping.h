// The damping of a scene: which model and its one parameter. Mass-
// proportional damping (chapter 3.2.2, chapter 5.2, appendix 2) lives here;
// the two other models have their own small classes.
//
// Mass-proportional: damping force F_d = alpha m v and moment M_d = alpha I
// omega (eq. 23-29), applied to the fluctuating (non-affine) velocity only:
//   OD, conventional/global:  alpha_0 = 4 xi / T0 for every particle (eq. 101),
//       equivalently 2 xi / R_min sqrt(E/rho) (eq. 60/100);
//   ND, size-dependent:       alpha_i = 2 xi / R_i sqrt(E/rho) (eq. 63),
//       R_i the nominal (equal-volume) radius of particle i.
// xi is the damping ratio [-]; alpha is in [1/s]. For the smallest particle
// both models give the same alpha.
// The other models (alpha = 0 for them):
//   viscous: contact dashpots from a coefficient of restitution e in (0, 1]
//       (Tsuji form, viscous_contact_damping.h); parameter e;
//   local:   Cundall's local non-viscous damping (local_damping.h);
//       parameter a in [0, 1).
#pragma once

#include <string>

namespace vt::dem {

enum class DampingModel { OD, ND, Viscous, Local };

/// Parse "OD"/"ND"/"viscous"/"local" (case-insensitive). Returns false on anything else.
bool parse_damping_model(const std::string& s, DampingModel& out);
const char* to_string(DampingModel m);
/// "OD, ND, viscous or local" (for error messages).
const char* damping_model_names();
/// "" when `parameter` is valid for `model`, else the reason (e.g.
/// "must be in (0, 1] (a coefficient of restitution)").
std::string damping_parameter_error(DampingModel model, double parameter);
/// The name of the model's parameter in scene files: ratio, restitution or coefficient.
const char* damping_parameter_name(DampingModel model);

class MassDamping {
 public:
  MassDamping() = default;
  MassDamping(DampingModel model, double ratio) : model_(model), ratio_(ratio) {}

  DampingModel model() const { return model_; }
  /// The model's parameter: xi (OD, ND), e (viscous) or a (local) [1].
  double ratio() const { return ratio_; }
  bool is_mass_proportional() const { return model_ == DampingModel::OD || model_ == DampingModel::ND; }

  /// alpha [1/s] for a particle of nominal radius r; t0 [s], e [Pa], rho [kg/m^3].
  /// 0 for the viscous and local models.
  double alpha(double r, double t0, double e, double rho) const;

 private:
  DampingModel model_ = DampingModel::OD;
  double ratio_ = 0.0;
};

}  // namespace vt::dem
