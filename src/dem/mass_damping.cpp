#include "virtual_triaxial/dem/mass_damping.h"

#include <cctype>
#include <cmath>

namespace vt::dem {

bool parse_damping_model(const std::string& s, DampingModel& out) {
  std::string u;
  for (char c : s) u.push_back(static_cast<char>(std::toupper(static_cast<unsigned char>(c))));
  if (u == "OD") { out = DampingModel::OD; return true; }
  if (u == "ND") { out = DampingModel::ND; return true; }
  return false;
}

const char* to_string(DampingModel m) { return m == DampingModel::OD ? "OD" : "ND"; }

double MassDamping::alpha(double r, double t0, double e, double rho) const {
  if (model_ == DampingModel::OD) return 4.0 * ratio_ / t0;   // eq. 101
  return 2.0 * ratio_ / r * std::sqrt(e / rho);               // eq. 63
}

}  // namespace vt::dem
