#include "virtual_triaxial/dem/viscous_contact_damping.h"

#include <stdexcept>

namespace vt::dem {

namespace {
/// x'' of the dimensionless collision (header): -x^1.5 - beta x^(1/4) x'.
double acceleration(double x, double u, double beta) {
  const double xp = x > 0.0 ? x : 0.0;
  const double r = std::sqrt(xp);
  return -xp * r - beta * std::sqrt(r) * u;
}
constexpr double kBetaMax = 2.5;  // e(2.5) < 1e-3: the pair sticks beyond
}  // namespace

double ViscousContactDamping::restitution_of(double beta) {
  const double h = 2.5e-4;  // the undamped collision lasts tau = 3.2
  double x = 0.0, u = 1.0;
  for (int k = 0; k < 400000; ++k) {
    const double a1 = acceleration(x, u, beta);
    const double x2 = x + 0.5 * h * u, u2 = u + 0.5 * h * a1;
    const double a2 = acceleration(x2, u2, beta);
    const double x3 = x + 0.5 * h * u2, u3 = u + 0.5 * h * a2;
    const double a3 = acceleration(x3, u3, beta);
    const double x4 = x + h * u3, u4 = u + h * a3;
    const double a4 = acceleration(x4, u4, beta);
    const double xn = x + h / 6.0 * (u + 2.0 * u2 + 2.0 * u3 + u4);
    const double un = u + h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
    if (xn <= 0.0 && k > 0) return -(u + (x / (x - xn)) * (un - u));  // back at x = 0 (linear in the step)
    if (un >= 0.0 && u < 0.0) return 0.0;                              // stopped before separating: stuck
    x = xn;
    u = un;
  }
  return 0.0;
}

double ViscousContactDamping::coefficient_for(double e) {
  if (!(e > 0.0 && e <= 1.0)) throw std::invalid_argument("restitution: must be in (0, 1]");
  if (e == 1.0) return 0.0;
  if (!(restitution_of(kBetaMax) < e))
    throw std::invalid_argument("restitution: must be >= " + std::to_string(restitution_of(kBetaMax)) +
                                " (a smaller one sticks: the pair does not separate)");
  double lo = 0.0, hi = kBetaMax;  // e(lo) >= e > e(hi); e falls with beta
  for (int k = 0; k < 48; ++k) {
    const double mid = 0.5 * (lo + hi);
    (restitution_of(mid) >= e ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi) / std::sqrt(1.5);
}

ViscousContactDamping::ViscousContactDamping(double restitution)
    : restitution_(restitution), a_(coefficient_for(restitution)) {}

}  // namespace vt::dem
