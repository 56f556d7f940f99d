// Quasi-static advisor, closed forms (Yousefi 2017, chapter 6): eq. 84 on the
// leave-out sample, its consistency with eqs. 83 and 85, the ND/OD gain
// sqrt(Delta) of section 6.14, eq. 72 against eq. 70, the run planner and
// the errors that name the argument.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "virtual_triaxial/quasi_static/inertial_number.h"
#include "virtual_triaxial/quasi_static/qs_rate_prediction.h"
#include "virtual_triaxial/quasi_static/qs_warnings.h"
#include "virtual_triaxial/quasi_static/run_plan.h"

namespace qs = vt::quasi_static;

namespace {
// Table 39, leave-out sample TTT.
qs::QsSample ttt() { return {0.312, 1e-5, 6.150}; }

std::string error_of(void (*f)()) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}
}  // namespace

// Section 6.12: "Using Eq. (84), eps'_QS is obtained to be 3.36e-7 and
// 1.36e-7 for the ND and OD models". Printed to 3 digits: 1 % tolerance.
TEST(QsPrediction, Eq84ReproducesTheLeaveOutSampleOfSection612) {
  const auto nd = qs::predict_qs_rate(ttt(), qs::QsDamping::ND);
  const auto od = qs::predict_qs_rate(ttt(), qs::QsDamping::OD);
  EXPECT_NEAR(nd.eps_prime_qs, 3.36e-7, 0.01 * 3.36e-7);
  EXPECT_NEAR(od.eps_prime_qs, 1.36e-7, 0.01 * 1.36e-7);
  EXPECT_TRUE(nd.inside_calibration);
  EXPECT_FALSE(nd.extrapolated_threshold);
  EXPECT_EQ(nd.exponent_delta, -2.0);
  EXPECT_EQ(od.exponent_delta, -2.5);
}

// Eq. 83 is eq. 84 at I_QS = 0.1 % (K = 2.7e-4); eq. 84 is linear in I_QS;
// section 6.14: the ND/OD ratio is sqrt(Delta).
TEST(QsPrediction, Eq83IsEq84AtOneTenthPercentAndNdGainsSqrtDelta) {
  const qs::QsSample s{0.61, 1.4e-6, 1.36};
  const double eq83 = 2.7e-4 * std::pow(0.61, -4.0) * std::pow(1.4e-6, 0.67) * std::pow(1.36, -2.0);
  const auto p = qs::predict_qs_rate(s, qs::QsDamping::ND, 1e-3);
  EXPECT_NEAR(p.eps_prime_qs, eq83, 1e-14 * eq83);
  const auto p5 = qs::predict_qs_rate(s, qs::QsDamping::ND, 5e-3);
  EXPECT_NEAR(p5.eps_prime_qs / p.eps_prime_qs, 5.0, 1e-12);
  EXPECT_TRUE(qs::predict_qs_rate(s, qs::QsDamping::ND, 5e-4).extrapolated_threshold);
  for (double delta : {1.0, 2.837, 6.15}) {
    const qs::QsSample d{0.4, 4e-6, delta};
    const double ratio = qs::predict_qs_rate(d, qs::QsDamping::ND).eps_prime_qs /
                         qs::predict_qs_rate(d, qs::QsDamping::OD).eps_prime_qs;
    EXPECT_NEAR(ratio, std::sqrt(delta), 1e-12 * ratio) << "Delta " << delta;
  }
  // outside table 39's ranges: loose (e0 0.75) and Delta 8 are flagged
  EXPECT_FALSE(qs::predict_qs_rate({0.75, 4e-6, 1.36}, qs::QsDamping::OD).inside_calibration);
  EXPECT_FALSE(qs::predict_qs_rate({0.4, 4e-6, 8.0}, qs::QsDamping::OD).inside_calibration);
}

// Eq. 85 (printed dimensional form) = eq. 84 / T0 with T0 = d_min sqrt(rho/E)
// for spheres, for both models and any I_QS (the 0.17 is 0.67 - 0.5).
TEST(QsPrediction, Eq85EqualsEq84OverT0ForSpheres) {
  const double d_min = 1.6e-3, d_avg = 2.1e-3, rho = 2650.0, e = 70e9, sc = 100e3, e0 = 0.61;
  const double t0 = d_min * std::sqrt(rho / e);
  for (auto m : {qs::QsDamping::OD, qs::QsDamping::ND})
    for (double iqs : {1e-3, 3e-3}) {
      const auto p = qs::predict_qs_rate({e0, sc / e, d_avg / d_min}, m, iqs);
      const double a = qs::dimensional_rate(p.eps_prime_qs, t0);
      const double b = qs::eq85_rate(m, d_min, d_avg, sc, rho, e, e0, iqs);
      EXPECT_NEAR(a, b, 1e-12 * a) << qs::to_string(m) << " I_QS " << iqs;
    }
}

// Eq. 72 is eq. 70 in the dimensionless scheme: the rate it returns, made
// dimensional with T0 = d_min sqrt(rho/E) and sigma_m = sigma_bar0 E, has
// exactly the threshold inertial number.
TEST(QsPrediction, Eq72IsEq70InTheDimensionlessScheme) {
  const double d_min = 2e-3, d_avg = 4.4e-3, rho = 2650.0, e = 72e9, sbar = 4e-6;
  const qs::QsSample s{0.4, sbar, d_avg / d_min};
  for (auto m : {qs::QsDamping::OD, qs::QsDamping::ND}) {
    const double ithr = qs::fitted_inertial_threshold(m);
    const double eps = qs::eq72_rate(s, ithr);
    const double rate = eps / (d_min * std::sqrt(rho / e));
    EXPECT_NEAR(qs::inertial_number(rate, d_avg, rho, sbar * e), ithr, 1e-12 * ithr);
  }
  EXPECT_EQ(qs::fitted_inertial_threshold(qs::QsDamping::ND), 5.8e-4);   // section 6.15
  EXPECT_EQ(qs::fitted_inertial_threshold(qs::QsDamping::OD), 3.7e-4);
}

// steps = eps_final / (c_t eps'); the README's quasi-static protocol: 6 %
// at eps' = 1e-7 and c_t = 0.3 is 2 000 000 shearing steps.
TEST(QsPrediction, RunPlanCountsStepsAndScalesTheMeasuredCost) {
  const auto p = qs::plan_run(0.06, 1e-7, 0.3, 1000, 1.5e-7);
  EXPECT_EQ(p.steps, 2000000.0);
  EXPECT_NEAR(p.wall_seconds, 2e6 * 1000 * 1.5e-7, 1e-9);
  EXPECT_EQ(qs::plan_run(0.1, 1e-5, 0.3, 4000, 1e-7).steps, 33334.0);   // ceil
}

TEST(QsPrediction, BadArgumentsAreNamed) {
  EXPECT_EQ(error_of([] { qs::predict_qs_rate({0.0, 1e-6, 1.0}, qs::QsDamping::ND); }),
            "void_ratio: must be finite and > 0");
  EXPECT_EQ(error_of([] { qs::predict_qs_rate({0.5, -1.0, 1.0}, qs::QsDamping::ND); }),
            "sigma_bar0: must be finite and > 0");
  EXPECT_EQ(error_of([] { qs::predict_qs_rate({0.5, 1e-6, 0.9}, qs::QsDamping::ND); }),
            "dispersity_index: must be finite and >= 1");
  EXPECT_EQ(error_of([] { qs::predict_qs_rate({0.5, 1e-6, 1.0}, qs::QsDamping::ND, NAN); }),
            "threshold: must be finite and > 0");
  EXPECT_EQ(error_of([] { qs::plan_run(0.1, 0.0, 0.3, 10, 1e-7); }),
            "eps_prime: must be finite and > 0");
  qs::QsDamping m;
  EXPECT_TRUE(qs::parse_qs_damping("nd", m));
  EXPECT_EQ(m, qs::QsDamping::ND);
  EXPECT_FALSE(qs::parse_qs_damping("cundall", m));
}

// Item 6 of issue 15: warnings where the dissertation advises against an
// input, each naming the protocol field; none for the chapter-6 settings.
TEST(QsPrediction, WarningsFollowTheDissertationsAdvice) {
  qs::QsInputs in;
  in.model = qs::QsDamping::OD;
  in.damping_ratio = 0.003;
  in.time_step_ratio = 0.3;
  in.shear_eps_prime = 1e-7;
  in.predicted_eps_prime_qs = 1.2e-7;
  EXPECT_TRUE(qs::qs_warnings(in).empty());
  auto starts = [](const std::vector<std::string>& w, const std::string& p) {
    return w.size() == 1 && w[0].rfind(p, 0) == 0;
  };
  auto x = in;
  x.damping_ratio = 0.0;
  EXPECT_TRUE(starts(qs::qs_warnings(x), "damping.ratio: xi = 0"));
  x.damping_ratio = 0.0015;   // half the OD optimum
  EXPECT_TRUE(starts(qs::qs_warnings(x), "damping.ratio: xi = 0.15 % is below the OD optimum"));
  x.model = qs::QsDamping::ND;
  x.damping_ratio = 0.003;    // below 2/3 of ND's 0.5 %
  EXPECT_TRUE(starts(qs::qs_warnings(x), "damping.ratio: xi = 0.3 % is below the ND optimum"));
  x = in;
  x.damping_ratio = 0.02;
  EXPECT_TRUE(starts(qs::qs_warnings(x), "damping.ratio: xi = 2 % is 6.7x the optimum"));
  x = in;
  x.time_step_ratio = 0.1;
  EXPECT_TRUE(starts(qs::qs_warnings(x), "time_step_ratio: c_t = 0.1 is far from 0.3"));
  x = in;
  x.shear_eps_prime = 1e-5;
  EXPECT_TRUE(starts(qs::qs_warnings(x), "stages: the shear rate eps' = 1e-05 is 83.3x"));
  x.quasi_static_wanted = false;
  EXPECT_TRUE(qs::qs_warnings(x).empty());
}
