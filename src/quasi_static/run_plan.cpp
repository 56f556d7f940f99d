#include "virtual_triaxial/quasi_static/run_plan.h"
#include "virtual_triaxial/quasi_static/input_checks.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace vt::quasi_static {
RunPlan plan_run(double final_strain, double eps_prime, double time_step_ratio,
                 std::int64_t particles, double seconds_per_particle_step) {
  require_positive(final_strain, "final_strain");
  require_positive(eps_prime, "eps_prime");
  require_positive(time_step_ratio, "time_step_ratio");
  require_positive(static_cast<double>(particles), "particles");
  require_positive(seconds_per_particle_step, "seconds_per_particle_step");
  RunPlan p;
  p.steps = std::ceil(final_strain / (time_step_ratio * eps_prime));
  p.wall_seconds = p.steps * static_cast<double>(particles) * seconds_per_particle_step;
  return p;
}

}  // namespace vt::quasi_static
