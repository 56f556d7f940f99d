#include "virtual_triaxial/quasi_static/qs_warnings.h"

#include <cstdio>

namespace vt::quasi_static {
namespace {
std::string fmt(const char* f, double a, double b = 0.0, double c = 0.0) {
  char buf[400];
  std::snprintf(buf, sizeof buf, f, a, b, c);
  return buf;
}
}  // namespace

double nominal_optimum_ratio(QsDamping model) { return model == QsDamping::ND ? 0.005 : 0.003; }

std::vector<std::string> qs_warnings(const QsInputs& in) {
  std::vector<std::string> w;
  const double opt = nominal_optimum_ratio(in.model);
  const std::string m = to_string(in.model);
  if (in.damping_ratio == 0.0)
    w.push_back("damping.ratio: xi = 0; the dissertation finds undamped shearing softer, more "
                "contractive and further from equilibrium (chapter 5.5); use the optimum, about " +
                fmt("%.2g %%", 100 * opt) + " for " + m);
  else if (in.damping_ratio < opt * 2.0 / 3.0)
    w.push_back("damping.ratio: " + fmt("xi = %.3g %% is below the ", 100 * in.damping_ratio) + m +
                fmt(" optimum (about %.2g %%): the peak friction comes out too low and I_mom too high "
                    "(chapter 5.5)", 100 * opt));
  else if (in.damping_ratio > 3.0 * opt)
    w.push_back("damping.ratio: " + fmt("xi = %.3g %% is %.1fx the optimum", 100 * in.damping_ratio,
                                        in.damping_ratio / opt) +
                "; above the optimum only xi eps' matters (eq. 86): this acts like a faster test");
  if (in.time_step_ratio < 0.15 || in.time_step_ratio > 0.45)
    w.push_back(fmt("time_step_ratio: c_t = %.3g is far from 0.3, the value chapters 3-6 shear with "
                    "(0.32); smaller wastes steps, larger risks instability",
                    in.time_step_ratio));
  if (in.quasi_static_wanted && in.shear_eps_prime > 0.0 && in.predicted_eps_prime_qs > 0.0 &&
      in.shear_eps_prime > in.predicted_eps_prime_qs)
    w.push_back(fmt("stages: the shear rate eps' = %.3g is %.1fx the predicted quasi-static rate "
                    "%.3g (eq. 84); the peak friction will be too high (fig. 83)",
                    in.shear_eps_prime, in.shear_eps_prime / in.predicted_eps_prime_qs,
                    in.predicted_eps_prime_qs));
  return w;
}

}  // namespace vt::quasi_static
