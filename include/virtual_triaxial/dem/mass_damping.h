// Mass-proportional damping (chapter 3.2.2, chapter 5.2, appendix 2).
//
// Damping force F_d = alpha m v and moment M_d = alpha I omega (eq. 23-29),
// applied to the fluctuating (non-affine) velocity only. Two models:
//   OD, conventional/global:  alpha_0 = 4 xi / T0 for every particle (eq. 101),
//       equivalently 2 xi / R_min sqrt(E/rho) (eq. 60/100);
//   ND, size-dependent:       alpha_i = 2 xi / R_i sqrt(E/rho) (eq. 63),
//       R_i the nominal (equal-volume) radius of particle i.
// xi is the damping ratio [-]; alpha is in [1/s]. For the smallest particle
// both models give the same alpha.
#pragma once

#include <string>

namespace vt::dem {

enum class DampingModel { OD, ND };

/// Parse "OD"/"ND" (case-insensitive). Returns false on anything else.
bool parse_damping_model(const std::string& s, DampingModel& out);
const char* to_string(DampingModel m);

class MassDamping {
 public:
  MassDamping() = default;
  MassDamping(DampingModel model, double ratio) : model_(model), ratio_(ratio) {}

  DampingModel model() const { return model_; }
  double ratio() const { return ratio_; }

  /// alpha [1/s] for a particle of nominal radius r; t0 [s], e [Pa], rho [kg/m^3].
  double alpha(double r, double t0, double e, double rho) const;

 private:
  DampingModel model_ = DampingModel::OD;
  double ratio_ = 0.0;
};

}  // namespace vt::dem
