#include "virtual_triaxial/quasi_static/qs_rate_prediction.h"
#include "virtual_triaxial/quasi_static/input_checks.h"

#include <cctype>
#include <cmath>
#include <stdexcept>

namespace vt::quasi_static {
namespace {

constexpr double kCoefficient = 0.27;   // eq. 84 (2.7e-4 / 1e-3 of eq. 83)
constexpr double kExpVoid = -4.0;       // eq. 78
constexpr double kExpStress = 0.67;     // eq. 79

double delta_exponent(QsDamping m) { return m == QsDamping::ND ? -2.0 : -2.5; }  // eq. 81

}  // namespace

bool parse_qs_damping(const std::string& text, QsDamping& out) {
  std::string u;
  for (char c : text) u += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  if (u == "OD") { out = QsDamping::OD; return true; }
  if (u == "ND") { out = QsDamping::ND; return true; }
  return false;
}

const char* to_string(QsDamping model) { return model == QsDamping::ND ? "ND" : "OD"; }

QsRatePrediction predict_qs_rate(const QsSample& s, QsDamping model, double threshold) {
  require_positive(s.void_ratio, "void_ratio");
  require_positive(s.sigma_bar0, "sigma_bar0");
  require_positive(threshold, "threshold");
  require_dispersity_index(s.dispersity_index);
  QsRatePrediction p;
  p.exponent_delta = delta_exponent(model);
  p.threshold = threshold;
  p.eps_prime_qs = kCoefficient * std::pow(s.void_ratio, kExpVoid) *
                   std::pow(s.sigma_bar0, kExpStress) *
                   std::pow(s.dispersity_index, p.exponent_delta) * threshold;
  // Table 39's ranges, widened by the printed rounding.
  p.inside_calibration = s.void_ratio >= 0.31 && s.void_ratio <= 0.61 &&
                         s.sigma_bar0 >= 1e-6 && s.sigma_bar0 <= 8e-5 &&
                         s.dispersity_index <= 6.15;
  p.extrapolated_threshold = threshold < 1e-3;
  return p;
}

double dimensional_rate(double eps_prime, double t0) {
  require_positive(t0, "t0");
  return eps_prime / t0;
}

double eq85_rate(QsDamping model, double d_min, double d_avg, double sigma_c,
                 double density, double young_modulus, double void_ratio, double threshold) {
  require_positive(d_min, "d_min");
  require_positive(d_avg, "d_avg");
  require_positive(sigma_c, "sigma_c");
  require_positive(density, "density");
  require_positive(young_modulus, "young_modulus");
  require_positive(void_ratio, "void_ratio");
  require_positive(threshold, "threshold");
  const double pd = model == QsDamping::ND ? 1.0 : 1.5;   // d_min^pd / d_avg^(pd+1)
  return kCoefficient * std::pow(d_min, pd) * std::pow(sigma_c, kExpStress) * threshold /
         (std::pow(d_avg, pd + 1.0) * std::sqrt(density) *
          std::pow(young_modulus, kExpStress - 0.5) * std::pow(void_ratio, -kExpVoid));
}

}  // namespace vt::quasi_static
