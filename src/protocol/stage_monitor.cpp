#include "virtual_triaxial/protocol/stage_monitor.h"

#include <cmath>
#include <sstream>

namespace vt::protocol {

bool is_sample_tick(std::int64_t stage_steps, std::int64_t tick_steps, std::int64_t sample_interval) {
  return stage_steps == tick_steps || stage_steps % sample_interval == 0;
}

std::string StageMonitor::check(const TickSample& s) {
  const StopCriteria& c = stage_.stop;
  if (s.q > q_peak_) q_peak_ = s.q;
  std::ostringstream r;
  r.precision(6);
  if (c.steps && s.stage_steps >= *c.steps) {
    r << "steps " << s.stage_steps;
    return r.str();
  }
  if (c.mean_stress && s.p >= *c.mean_stress) {
    r << "mean stress " << s.p << " Pa >= " << *c.mean_stress << " Pa";
    return r.str();
  }
  // Unloading extends the axial axis: its axial_strain criterion is on |eps_a|.
  const double eps = stage_.type == StageType::DrainedUnload ? -s.eps_a : s.eps_a;
  if (c.axial_strain && eps >= *c.axial_strain) {
    r << "axial strain " << s.eps_a << " >= " << *c.axial_strain;
    return r.str();
  }
  if (c.deviator_below && s.q <= *c.deviator_below) {
    r << "deviator q " << s.q << " Pa <= " << *c.deviator_below << " Pa";
    return r.str();
  }
  if (c.softening && q_peak_ > 0.0 && s.q <= (1.0 - *c.softening) * q_peak_) {
    r << "softening: q " << s.q << " Pa <= " << (1.0 - *c.softening) << " x q_peak " << q_peak_ << " Pa";
    return r.str();
  }
  if (!s.ufr || s.contacts <= 0) return {};
  if (c.ufr_below && *s.ufr < *c.ufr_below) {
    r << "UFR " << *s.ufr << " < " << *c.ufr_below;
    return r.str();
  }
  if (c.balanced && *s.ufr < c.balanced->ufr_below) {
    double worst = 0.0;
    for (int i = 0; i < 3; ++i) {
      if (!boundary_.servo[i]) continue;
      const double t = boundary_.target[i];
      const double err = std::abs(s.stress[i] - t) / (t > 0.0 ? t : 1.0);
      if (!(err <= worst)) worst = err;  // NaN propagates as "not balanced"
    }
    if (worst <= c.balanced->stress_tolerance) {
      r << "balanced: stresses within " << worst * 100 << " % of the targets, UFR " << *s.ufr;
      return r.str();
    }
  }
  return {};
}

}  // namespace vt::protocol
