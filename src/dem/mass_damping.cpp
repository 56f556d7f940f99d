#include "virtual_triaxial/dem/mass_damping.h"

#include <cctype>
#include <cmath>
#include <stdexcept>

#include "virtual_triaxial/dem/viscous_contact_damping.h"

namespace vt::dem {

bool parse_damping_model(const std::string& s, DampingModel& out) {
  std::string u;
  for (char c : s) u.push_back(static_cast<char>(std::toupper(static_cast<unsigned char>(c))));
  if (u == "OD") { out = DampingModel::OD; return true; }
  if (u == "ND") { out = DampingModel::ND; return true; }
  if (u == "VISCOUS") { out = DampingModel::Viscous; return true; }
  if (u == "LOCAL") { out = DampingModel::Local; return true; }
  return false;
}

const char* to_string(DampingModel m) {
  switch (m) {
    case DampingModel::OD: return "OD";
    case DampingModel::ND: return "ND";
    case DampingModel::Viscous: return "viscous";
    case DampingModel::Local: return "local";
  }
  return "?";
}

const char* damping_model_names() { return "OD, ND, viscous or local"; }

const char* damping_parameter_name(DampingModel m) {
  switch (m) {
    case DampingModel::Viscous: return "restitution";
    case DampingModel::Local: return "coefficient";
    default: return "ratio";
  }
}

std::string damping_parameter_error(DampingModel m, double x) {
  switch (m) {
    case DampingModel::OD:
    case DampingModel::ND:
      return std::isfinite(x) && x >= 0.0 ? "" : "must be a finite damping ratio >= 0";
    case DampingModel::Viscous:
      try {
        ViscousContactDamping::coefficient_for(x);
        return "";
      } catch (const std::invalid_argument& e) {
        const std::string w = e.what();
        return w.substr(w.find(':') + 2) + " (a coefficient of restitution)";
      }
    case DampingModel::Local:
      return x >= 0.0 && x < 1.0 ? "" : "must be in [0, 1) (Cundall's local damping coefficient)";
  }
  return "unknown damping model";
}

double MassDamping::alpha(double r, double t0, double e, double rho) const {
  switch (model_) {
    case DampingModel::OD: return 4.0 * ratio_ / t0;                // eq. 101
    case DampingModel::ND: return 2.0 * ratio_ / r * std::sqrt(e / rho);  // eq. 63
    default: return 0.0;
  }
}

}  // namespace vt::dem
