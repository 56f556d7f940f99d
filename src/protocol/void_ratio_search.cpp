#include "virtual_triaxial/protocol/void_ratio_search.h"

#include <cmath>
#include <cstdio>

namespace vt::protocol {

namespace {

template <class... A>
std::string line(const char* f, A... a) {
  char buf[256];
  std::snprintf(buf, sizeof buf, f, a...);
  return buf;
}

}  // namespace

VoidRatioSearch find_mu1_for_void_ratio(PreparationSettings s, double target, double tol,
                                        const std::function<void(const std::string&)>& progress, double mu1_max,
                                        int max_iterations) {
  VoidRatioSearch out;
  auto prepare = [&](double mu1) {
    s.mu1 = mu1;
    PreparationResult r = prepare_sample(s);
    ++out.preparations;
    if (progress)
      progress(line("[target e] mu1 = %.5f -> e = %.4f (target %.4f)", mu1, r.converged ? r.final.void_ratio : NAN,
                    target));
    return r;
  };
  double lo = 0.0, hi = mu1_max;
  PreparationResult r_lo = prepare(lo);
  if (!r_lo.converged) {
    out.message = "preparation with mu1 = 0 failed: " + r_lo.failure;
    return out;
  }
  if (std::fabs(r_lo.final.void_ratio - target) <= tol) {
    out.reachable = true, out.mu1 = lo, out.result = std::move(r_lo);
    return out;
  }
  PreparationResult r_hi = prepare(hi);
  if (!r_hi.converged) {
    out.message = "preparation with mu1 = " + std::to_string(hi) + " failed: " + r_hi.failure;
    return out;
  }
  const double e_lo = r_lo.final.void_ratio, e_hi = r_hi.final.void_ratio;
  if (std::fabs(e_hi - target) <= tol) {
    out.reachable = true, out.mu1 = hi, out.result = std::move(r_hi);
    return out;
  }
  if (target < e_lo - tol || target > e_hi + tol) {
    out.message = line("target void ratio %.4f is out of reach: this size distribution and pressure give e from "
                       "%.4f (mu1 = 0, densest) to %.4f",
                       target, e_lo, e_hi) +
                  line(" (mu1 = %.2f, loosest)", mu1_max);
    return out;
  }
  for (int it = 0; it < max_iterations; ++it) {
    const double mid = 0.5 * (lo + hi);
    PreparationResult r = prepare(mid);
    if (!r.converged) {
      out.message = "preparation with mu1 = " + std::to_string(mid) + " failed: " + r.failure;
      return out;
    }
    const double e = r.final.void_ratio;
    if (std::fabs(e - target) <= tol) {
      out.reachable = true, out.mu1 = mid, out.result = std::move(r);
      return out;
    }
    (e < target ? lo : hi) = mid;
  }
  out.message = "no mu1 within " + std::to_string(max_iterations) + " bisection steps gave e within " +
                std::to_string(tol) + " of the target (e(mu1) is not monotonic enough for this sample size)";
  return out;
}

}  // namespace vt::protocol
