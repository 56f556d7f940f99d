// Quasi-static advisor against the dissertation's own data (Yousefi 2017,
// chapters 5 and 6). The input tables are transcribed in
// tests/data/quasi_static/ (table numbers in each file); every test below
// refits the published values from the published inputs with the library's
// estimators and states its tolerance. Printed values carry 2-3 significant
// digits, so most tolerances are the printed rounding.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "support/csv_table.h"
#include "virtual_triaxial/quasi_static/cowper_symonds_fit.h"
#include "virtual_triaxial/quasi_static/friction_line_fit.h"
#include "virtual_triaxial/quasi_static/optimum_damping.h"
#include "virtual_triaxial/quasi_static/rate_sweep_fit.h"

namespace qs = vt::quasi_static;
using vt::test::number;
using vt::test::read_csv_table;

namespace {

const std::string kDir = std::string(VT_SOURCE_DIR) + "/tests/data/quasi_static/";
constexpr double kPi = 3.14159265358979323846;

struct Run {
  double eps_prime, phi_deg, i_mom;
};

// Table 51 rows of one sample and damping model, fastest rate first.
std::vector<Run> table51(const std::string& sample, const std::string& damping) {
  static const auto t = read_csv_table(kDir + "table51_chapter6_models.csv");
  std::vector<Run> out;
  for (const auto& r : t.select({{"sample", sample}, {"damping", damping}}))
    out.push_back({number(r, "eps_prime"), number(r, "phi_max_deg"), number(r, "i_mom")});
  std::sort(out.begin(), out.end(), [](const Run& a, const Run& b) { return a.eps_prime > b.eps_prime; });
  return out;
}

// Half a unit of the last of `digits` significant digits of a printed
// value, plus 1 % for the rounding of the inputs it was computed from.
double printed_tolerance(const std::string& printed, int digits) {
  const double v = std::stod(printed);
  return 0.5 * std::pow(10.0, std::floor(std::log10(v)) - (digits - 1)) + 0.01 * v;
}

std::vector<qs::RatePoint> rate_points(const std::vector<Run>& runs, std::size_t n) {
  std::vector<qs::RatePoint> p;
  for (std::size_t i = 0; i < n; ++i) p.push_back({runs[i].eps_prime, runs[i].i_mom});
  return p;
}

std::vector<qs::FrictionPoint> friction_points(const std::vector<Run>& runs, std::size_t n) {
  std::vector<qs::FrictionPoint> p;
  for (std::size_t i = 0; i < n; ++i) p.push_back({runs[i].i_mom, runs[i].phi_deg, 0.0});
  return p;
}

// Table 50 (chapter 5, samples A and B): one damping sweep at one rate.
struct SweepRun {
  double xi, phi_deg, i_mom;
};
std::vector<SweepRun> table50(const std::string& sample, const std::string& rate,
                              const std::string& damping) {
  static const auto t = read_csv_table(kDir + "table50_chapter5_models.csv");
  std::vector<SweepRun> out;
  for (const auto& r : t.select({{"sample", sample}, {"eps_prime", rate}, {"damping", damping}}))
    out.push_back({number(r, "xi"), number(r, "phi_max_deg"), number(r, "i_mom")});
  return out;
}

std::vector<qs::DampingPoint> damping_points(const std::vector<SweepRun>& s) {
  std::vector<qs::DampingPoint> p;
  for (const auto& r : s) p.push_back({r.xi, r.i_mom});
  return p;
}

}  // namespace

TEST(QsTables, TranscribedTablesAreComplete) {
  EXPECT_EQ(read_csv_table(kDir + "table51_chapter6_models.csv").rows.size(), 342u);  // 19 x 2 x 9
  EXPECT_EQ(read_csv_table(kDir + "table50_chapter5_models.csv").rows.size(), 216u);  // 2 x 4 x 27
  for (const char* s : {"121", "220", "TTT"})
    for (const char* d : {"ND", "OD"}) EXPECT_EQ(table51(s, d).size(), 9u) << s << d;
}

// Table 42: eq. 73 through the two (1e-5, 5e-6) and three (+ 2e-6) fastest
// rates of table 51 (ND), solved at I_QS = 0.1 %. Tolerance: half a unit
// of the last printed digit (2 digits for 2 points, 3 for 3 points) plus 1 %
// for the rounding of table 51's I_mom (0.001 %). Exception: sample 121, 3 points,
// printed 1.05e-8 where table 51's rows give 1.47e-8 (the 2-point value and
// every other sample agree; 121's peaks at 1e-5 and 5e-6 sit at 0.2 % strain,
// so the author may have used other rows for it): checked only to be within
// the table's own 3-point error band (x/÷ 1.5).
TEST(QsTables, Eq73TwoAndThreePointFitsReproduceTable42) {
  const auto t = read_csv_table(kDir + "table42_rate_sweep_approximations.csv");
  ASSERT_EQ(t.rows.size(), 19u);
  for (const auto& r : t.rows) {
    const std::string s = r.at("sample");
    const auto runs = table51(s, "ND");
    const auto two = qs::fit_rate_sweep(rate_points(runs, 2));
    const auto three = qs::fit_rate_sweep(rate_points(runs, 3));
    EXPECT_NEAR(two.eps_prime_qs, number(r, "eps_qs_2pt"), printed_tolerance(r.at("eps_qs_2pt"), 2))
        << s;
    EXPECT_TRUE(std::isnan(two.se_ln_eps_prime_qs)) << "2 points: exact line, no uncertainty";
    const double ratio3 = three.eps_prime_qs / number(r, "eps_qs_3pt");
    if (s == "121")
      EXPECT_TRUE(ratio3 > 1.0 / 1.5 && ratio3 < 1.5) << ratio3;
    else
      EXPECT_NEAR(three.eps_prime_qs, number(r, "eps_qs_3pt"), printed_tolerance(r.at("eps_qs_3pt"), 3))
          << s;
    EXPECT_GT(three.se_ln_eps_prime_qs, 0.0) << s;
    EXPECT_NEAR(three.extrapolation_decades, std::log10(2e-6 / three.eps_prime_qs), 1e-12) << s;
  }
}

// Table 43: eq. 74 through all nine rates of each sample (ND and OD).
// Tolerance: tan phi0 within 0.006 (printed to 0.01), k within 0.06
// (printed to 0.01, inputs rounded to 0.01 deg and 0.001 %).
// Exception: 422OD, whose printed k is 1.43 with R^2 0.899 while the rows of
// table 51 give k = 1.52: checked to 0.1.
TEST(QsTables, Eq74LinesReproduceTable43) {
  const auto t = read_csv_table(kDir + "table43_friction_lines.csv");
  ASSERT_EQ(t.rows.size(), 38u);
  for (const auto& r : t.rows) {
    const std::string s = r.at("sample"), d = r.at("damping");
    const auto f = qs::fit_friction_line(friction_points(table51(s, d), 9));
    EXPECT_NEAR(f.tan_phi_qs, number(r, "tan_phi0"), 0.006) << s << d;
    EXPECT_NEAR(f.slope, number(r, "k"), s + d == "422OD" ? 0.1 : 0.06) << s << d;
    EXPECT_TRUE(f.slope_positive);
    EXPECT_GT(f.se_phi_qs_deg, 0.0);
  }
}

// Table 47: tan phi_QS from the three rates 1e-5, 5e-6, 2e-6 (ND), by
// (b) eq. 74 and (a) eq. 75. The reference is tan_phi_qs (1 + error/100).
// Tolerance (b): 0.009 in tan phi (the printed tan phi_QS is rounded to
// 0.005, the error to 0.05 %, and table 51's rounding of phi (0.01 deg) and
// I_mom (0.001 %) moves a three-point intercept by up to about 0.003).
// Exceptions (b): 121, +4.1 % where the table prints -0.5 % (as for table
// 42, the only other misfit, the author's 121 rows seem to differ from table
// 51's), and 241, +4.7 % against +1.3 % printed; both checked to be within
// the table's own largest (b) error, 5.2 %.
// Tolerance (a): 0.02 in tan phi: eq. 75 through three points is a 3x3
// nonlinear solve whose b_phi is ill-determined (0.14 for 422), so small
// input rounding moves the intercept; exceptions 121 and 422 (eq. 75 is
// the method the dissertation itself calls less precise) are checked to the
// table's largest (a) error, 15 %, and 121 (17.8 % where 12.6 % is printed;
// the same 121 rows as above) to 20 %.
TEST(QsTables, PhiQsFromThreeFastRatesReproducesTable47) {
  const auto t = read_csv_table(kDir + "table47_phi_qs_approximations.csv");
  ASSERT_EQ(t.rows.size(), 19u);
  double sum_b = 0.0, sum_a = 0.0;
  for (const auto& r : t.rows) {
    const std::string s = r.at("sample");
    const auto runs = table51(s, "ND");
    const double tq = number(r, "tan_phi_qs");
    const auto line = qs::fit_friction_line(friction_points(runs, 3));
    std::vector<qs::RateFrictionPoint> rp;
    for (std::size_t i = 0; i < 3; ++i) rp.push_back({runs[i].eps_prime, runs[i].phi_deg});
    const auto cs = qs::fit_cowper_symonds(rp);
    const double ref_b = tq * (1.0 + number(r, "error_b_percent") / 100.0);
    const double ref_a = tq * (1.0 + number(r, "error_a_percent") / 100.0);
    if (s == "121" || s == "241")
      EXPECT_LT(std::fabs(line.tan_phi_qs / tq - 1.0), 0.052) << s;
    else
      EXPECT_NEAR(line.tan_phi_qs, ref_b, 0.009) << s;
    if (s == "121" || s == "422")
      EXPECT_LT(std::fabs(cs.tan_phi_qs / tq - 1.0), s == "121" ? 0.20 : 0.15) << s;
    else
      EXPECT_NEAR(cs.tan_phi_qs, ref_a, 0.02) << s;
    sum_b += std::fabs(line.tan_phi_qs / tq - 1.0);
    sum_a += std::fabs(cs.tan_phi_qs / tq - 1.0);
  }
  // Table 47's conclusion: (b) is the better method (average 1.8 % vs 5.1 %).
  EXPECT_LT(sum_b / 19, 0.03);
  EXPECT_LT(sum_b, sum_a);
}

// Table 26: optimum xi of samples C and D from tables 24/25 (eps' = 1e-6):
// 0.441 % and 0.509 %, within 0.05 percentage points.
TEST(QsTables, OptimumDampingReproducesTable26) {
  const auto t = read_csv_table(kDir + "tables24_30_samples_c_d.csv");
  const auto pub = read_csv_table(kDir + "tables13_15_26_29_30_published.csv");
  for (const char* s : {"C", "D"}) {
    std::vector<qs::DampingPoint> p;
    for (const auto& r : t.select({{"sample", s}, {"kind", "damping"}}))
      p.push_back({number(r, "xi"), number(r, "i_mom")});
    const auto o = qs::find_optimum_damping(p);
    const double ref = number(pub.select({{"table", "26"}, {"sample", s}}).at(0), "xi_opt");
    EXPECT_NEAR(o.ratio, ref, 0.0005) << s;
    EXPECT_GT(o.min_i_mom, 0.0);
  }
}

// Table 13: the optimum xi of samples A and B with OD and ND from table
// 50's damping sweeps at eps' = 1e-7 (the rate nearest their eps'_QS),
// within 0.05 percentage points; eps'_QS from eq. 73 through the I_mom at
// the optimum at the four rates 1e-5..1e-8 (fig. 35), within 2 % (the
// vertex values are read off our curve, not the author's).
TEST(QsTables, OptimumAndQuasiStaticRateReproduceTable13) {
  const auto pub = read_csv_table(kDir + "tables13_15_26_29_30_published.csv");
  for (const char* s : {"A", "B"})
    for (const char* d : {"OD", "ND"}) {
      const auto row = pub.select({{"table", "13"}, {"sample", s}, {"damping", d}}).at(0);
      const auto o7 = qs::find_optimum_damping(damping_points(table50(s, "1e-7", d)));
      EXPECT_NEAR(o7.ratio, number(row, "xi_opt"), 0.0005) << s << d;
      std::vector<qs::RatePoint> at_opt;
      for (const char* rate : {"1e-5", "1e-6", "1e-7", "1e-8"})
        at_opt.push_back({std::stod(rate),
                          qs::find_optimum_damping(damping_points(table50(s, rate, d))).min_i_mom});
      const auto fit = qs::fit_rate_sweep(at_opt);
      EXPECT_NEAR(fit.eps_prime_qs / number(row, "eps_qs"), 1.0, 0.02) << s << d;
      EXPECT_GT(fit.law.r_squared, 0.99) << s << d;
    }
}

// Table 15: chapter 5's damping-based phi_QS: eq. 74 through the runs with
// xi >= xi_opt at one fast rate (A: 1e-6, B: 1e-5), xi_opt from the same
// sweep; within 0.1 deg of the printed (one-decimal) value.
TEST(QsTables, DampingBasedPhiQsReproducesTable15) {
  const auto pub = read_csv_table(kDir + "tables13_15_26_29_30_published.csv");
  for (const auto& row : pub.select({{"table", "15"}})) {
    const auto runs = table50(row.at("sample"), row.at("eps_prime"), row.at("damping"));
    const auto o = qs::find_optimum_damping(damping_points(runs));
    std::vector<qs::FrictionPoint> p;
    for (const auto& r : runs) p.push_back({r.i_mom, r.phi_deg, r.xi});
    const auto f = qs::fit_friction_line_above_optimum(p, o.ratio);
    EXPECT_NEAR(f.phi_qs_deg, number(row, "phi_qs_deg"), 0.1) << row.at("sample") << row.at("damping");
  }
}

// Tables 29 and 30 (samples C and D): eq. 73 through table 27/28's four
// rates gives eps'_QS (printed 5e-8 and 1.3e-7: 1 and 2 digits, so 10 % and
// 4 %); the damping-based phi_QS from tables 24/25 with the optimum of
// table 26's method is within 0.1 deg of 19.47 and 19.70 deg.
TEST(QsTables, SamplesCAndDReproduceTables29And30) {
  const auto t = read_csv_table(kDir + "tables24_30_samples_c_d.csv");
  const auto pub = read_csv_table(kDir + "tables13_15_26_29_30_published.csv");
  for (const char* s : {"C", "D"}) {
    std::vector<qs::RatePoint> rp;
    for (const auto& r : t.select({{"sample", s}, {"kind", "rate"}}))
      rp.push_back({number(r, "eps_prime"), number(r, "i_mom")});
    const auto fit = qs::fit_rate_sweep(rp);
    const double ref29 = number(pub.select({{"table", "29"}, {"sample", s}}).at(0), "eps_qs");
    EXPECT_NEAR(fit.eps_prime_qs / ref29, 1.0, std::string(s) == "C" ? 0.10 : 0.04) << s;

    std::vector<qs::FrictionPoint> fp;
    std::vector<qs::DampingPoint> dp;
    for (const auto& r : t.select({{"sample", s}, {"kind", "damping"}})) {
      fp.push_back({number(r, "i_mom"), number(r, "phi_peak_deg"), number(r, "xi")});
      dp.push_back({number(r, "xi"), number(r, "i_mom")});
    }
    const auto line = qs::fit_friction_line_above_optimum(fp, qs::find_optimum_damping(dp).ratio);
    const double ref30 = number(pub.select({{"table", "30"}, {"sample", s}}).at(0), "phi_qs_deg");
    EXPECT_NEAR(line.phi_qs_deg, ref30, 0.1) << s;
  }
}

// Eq. 86 collapses a damping x rate grid onto one power law in xi eps' for
// xi >= xi_opt (chapter 5, figs. 47-50): on table 50's sample B, ND, the
// rates 1e-5..1e-7 with xi >= 0.5 % fit with R^2 > 0.98 and an exponent
// inside chapter 6's range of b_I (0.47-1.14).
TEST(QsTables, Eq86CollapsesDampingAndRateOntoOneLaw) {
  std::vector<qs::DampingRatePoint> p;
  for (const char* rate : {"1e-5", "1e-6", "1e-7"})
    for (const auto& r : table50("B", rate, "ND")) p.push_back({r.xi, std::stod(rate), r.i_mom});
  const auto fit = qs::fit_damping_rate_product(p, 0.005);
  EXPECT_GT(fit.law.r_squared, 0.98);
  EXPECT_GT(fit.law.b, 0.47);
  EXPECT_LT(fit.law.b, 1.14);
  EXPECT_EQ(fit.law.points, 18);   // 6 ratios >= 0.5 % x 3 rates
}

TEST(QsTables, EstimatorsRefuseDataTheyCannotUse) {
  EXPECT_THROW(qs::fit_rate_sweep({{1e-5, 0.01}}), std::invalid_argument);
  EXPECT_THROW(qs::fit_rate_sweep({{1e-5, 0.01}, {1e-6, 0.02}}), std::invalid_argument);  // b < 0
  EXPECT_THROW(qs::find_optimum_damping({{0.001, 0.01}, {0.002, 0.02}, {0.003, 0.03}}),
               std::invalid_argument);   // minimum at the end: not bracketed
  EXPECT_THROW(qs::fit_cowper_symonds({{1e-5, 30.0}, {1e-5, 31.0}, {1e-6, 25.0}}),
               std::invalid_argument);   // repeated rate
  EXPECT_THROW(qs::fit_friction_line({{0.01, 30.0, 0.0}}), std::invalid_argument);
}
