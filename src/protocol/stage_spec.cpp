#include "virtual_triaxial/protocol/stage_spec.h"

namespace vt::protocol {

namespace {
const StageType kAll[] = {StageType::IsotropicCompression, StageType::IsotropicConsolidation,
                          StageType::DrainedShear, StageType::UndrainedShear, StageType::DrainedUnload,
                          StageType::Relax};
}  // namespace

const char* to_string(StageType t) {
  switch (t) {
    case StageType::IsotropicCompression: return "isotropic_compression";
    case StageType::IsotropicConsolidation: return "isotropic_consolidation";
    case StageType::DrainedShear: return "drained_shear";
    case StageType::UndrainedShear: return "undrained_shear";
    case StageType::DrainedUnload: return "drained_unload";
    case StageType::Relax: return "relax";
  }
  return "?";
}

bool parse_stage_type(const std::string& name, StageType& out) {
  for (StageType t : kAll)
    if (name == to_string(t)) {
      out = t;
      return true;
    }
  return false;
}

std::string stage_type_names() {
  std::string s;
  for (StageType t : kAll) s += (s.empty() ? "" : ", ") + std::string(to_string(t));
  return s;
}

bool uses_servo(StageType t) {
  return t == StageType::IsotropicConsolidation || t == StageType::DrainedShear || t == StageType::DrainedUnload;
}
bool is_shear(StageType t) { return t == StageType::DrainedShear || t == StageType::UndrainedShear; }

double StageSpec::rate(double t0) const {
  if (strain_rate) return *strain_rate;
  if (strain_rate_dimensionless) return *strain_rate_dimensionless / t0;
  return 0.0;
}

std::vector<int> StageBoundary::servo_axes() const {
  std::vector<int> a;
  for (int i = 0; i < 3; ++i)
    if (servo[i]) a.push_back(i);
  return a;
}

StageBoundary stage_boundary(const StageSpec& st, double t0) {
  StageBoundary b;
  const double r = st.rate(t0);
  const double target = st.confining_pressure.value_or(0.0);
  const int ax = st.axial_axis;
  switch (st.type) {
    case StageType::IsotropicCompression:
      for (double& v : b.open_rate) v = r;
      break;
    case StageType::IsotropicConsolidation:
      for (int i = 0; i < 3; ++i) b.servo[i] = true, b.target[i] = target;
      break;
    case StageType::DrainedShear:
    case StageType::DrainedUnload:
      for (int i = 0; i < 3; ++i)
        if (i != ax) b.servo[i] = true, b.target[i] = target;
      b.open_rate[ax] = st.type == StageType::DrainedShear ? r : -r;
      break;
    case StageType::UndrainedShear:
      for (int i = 0; i < 3; ++i) b.open_rate[i] = i == ax ? r : -0.5 * r;
      break;
    case StageType::Relax:
      break;
  }
  return b;
}

}  // namespace vt::protocol
