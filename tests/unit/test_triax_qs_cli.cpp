// triax_qs: predict on the shipped main-job protocol (eq. 84 from the
// sample's own e0 and Delta, the plan's closed forms, the JSON last line,
// the rate warning), fits from triax_run-style summaries against exact
// synthetic laws, and bad input named with exit code 2.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "support/cli.h"

namespace {

const std::filesystem::path& tmpdir() {
  static const auto d = vt::test::scratch_dir("triax_qs_cli");
  return d;
}
vt::test::CliRun triax_qs(const std::string& args) { return vt::test::run_program("triax_qs", args, tmpdir()); }

std::string last_line(const std::string& s) {
  const auto end = s.find_last_not_of('\n');
  const auto start = s.rfind('\n', end);
  return s.substr(start == std::string::npos ? 0 : start + 1, end - (start == std::string::npos ? 0 : start + 1) + 1);
}

double json_number(const std::string& json, const std::string& key) {
  const std::string k = "\"" + key + "\":";
  const auto p = json.find(k);
  EXPECT_NE(p, std::string::npos) << key << " missing in " << json;
  if (p == std::string::npos) return NAN;
  return std::stod(json.substr(p + k.size()));
}

std::string write_summary(const std::string& name, double i_mom, double phi_deg) {
  const auto path = tmpdir() / name;
  std::ofstream(path) << "{\"verdict\":\"completed\",\"phi_peak_deg\":" << phi_deg
                      << ",\"mean_moment_index_to_peak\":" << i_mom << ",\"quasi_static\":false}\n";
  return path.string();
}

const std::string kSource = VT_SOURCE_DIR;

}  // namespace

// dense_1000 (README: e0 0.609, sigma_bar0 1.43e-6): eq. 84 with OD gives
// 1.17e-7 (the README's "about 1.2e-7"); the plan's steps are
// ceil(0.1 / (0.3 x 1e-5)) and its wall time steps x N x the given cost.
TEST(TriaxQsCli, PredictOnTheMainJobProtocol) {
  const auto r = triax_qs("predict " + kSource + "/config/protocols/drained_100kPa.yaml --cost 1.3e-7");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string j = last_line(r.out);
  ASSERT_EQ(j.front(), '{') << j;
  const double e0 = json_number(j, "void_ratio"), delta = json_number(j, "dispersity_index");
  const double sbar = json_number(j, "sigma_bar0");
  EXPECT_NEAR(e0, 0.609, 0.001);
  EXPECT_NEAR(sbar, 100e3 / 70e9, 1e-9 * sbar);
  EXPECT_GT(delta, 1.2);   // radius 0.8-1.2 mm: Delta = d_avg(mass)/d_min, well above 1
  EXPECT_LT(delta, 1.5);
  const double expect = 0.27 * std::pow(e0, -4) * std::pow(sbar, 0.67) * std::pow(delta, -2.5) * 1e-3;
  EXPECT_NEAR(json_number(j, "eps_prime_qs_eq84"), expect, 1e-5 * expect);
  EXPECT_NEAR(json_number(j, "eps_prime_qs_eq84"), 1.17e-7, 0.02e-7);
  EXPECT_NEAR(json_number(j, "strain_rate_qs_eq85_per_s") * json_number(j, "t0_s"), expect, 1e-5 * expect);
  EXPECT_EQ(json_number(j, "shear_steps"), 33334.0);
  const double qs_steps = json_number(j, "qs_steps");
  EXPECT_NEAR(qs_steps, std::ceil(0.1 / (0.3 * json_number(j, "eps_prime_qs_eq84"))), 1.0);
  EXPECT_NEAR(json_number(j, "qs_wall_s"), qs_steps * 1000 * 1.3e-7, 1e-3 * qs_steps * 1.3e-4);
  EXPECT_NE(j.find("\"cost_measured\":false"), std::string::npos);
  EXPECT_NE(r.err.find("warning: stages: the shear rate eps' = 1e-05 is"), std::string::npos) << r.err;
}

TEST(TriaxQsCli, FitRatesRecoversAnExactPowerLawAndLine) {
  // I_mom = 800 eps'^0.9, tan phi = 0.45 + 5 I_mom
  std::string args = "fit-rates";
  int i = 0;
  for (double e : {1e-5, 5e-6, 2e-6}) {
    const double im = 800 * std::pow(e, 0.9);
    const double phi = std::atan(0.45 + 5 * im) * 180 / M_PI;
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", e);
    args += std::string(" --run ") + buf + "," + write_summary("s" + std::to_string(i++) + ".json", im, phi);
  }
  const auto r = triax_qs(args);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string j = last_line(r.out);
  const double expect = std::pow(1e-3 / 800, 1 / 0.9);
  EXPECT_NEAR(json_number(j, "eps_prime_qs_eq73") / expect, 1.0, 1e-4);   // summaries carry 6 digits
  EXPECT_NEAR(json_number(j, "b_i_eq73"), 0.9, 1e-4);
  EXPECT_NEAR(json_number(j, "phi_qs_eq74_deg"), std::atan(0.45) * 180 / M_PI, 1e-3);
}

TEST(TriaxQsCli, FitDampingFindsTheVertexOfAnExactLogParabola) {
  // ln I = ln 0.01 + 0.8 (ln xi - ln 0.004)^2: optimum 0.4 %
  std::string args = "fit-damping";
  int i = 0;
  for (double xi : {0.001, 0.002, 0.003, 0.005, 0.01, 0.02}) {
    const double l = std::log(xi / 0.004);
    const double im = 0.01 * std::exp(0.8 * l * l);
    args += " --run " + std::to_string(xi) + ",1e-6," + write_summary("d" + std::to_string(i++) + ".json", im, 25.0 + 100 * im);
  }
  const auto r = triax_qs(args);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NEAR(json_number(last_line(r.out), "optimum_damping_ratio"), 0.004, 1e-8);
}

TEST(TriaxQsCli, BadInputExitsWithCode2AndNamesTheField) {
  auto r = triax_qs("predict " + kSource + "/no/such.yaml");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("error: scene: cannot open"), std::string::npos) << r.err;
  r = triax_qs("frobnicate");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("error: command: unknown 'frobnicate'"), std::string::npos) << r.err;
  r = triax_qs("predict " + kSource + "/config/protocols/drained_100kPa.yaml --cost -1");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("error: --cost: must be > 0"), std::string::npos) << r.err;
  // a shear stage without a final strain cannot be planned
  const auto p = tmpdir() / "no_final_strain.yaml";
  std::ofstream(p) << "particles: {sample_file: " << kSource << "/tests/data/sample_200_100kPa.h5}\n"
                   << "stages:\n  - {name: s, type: drained_shear, confining_pressure: 1.0e5,"
                   << " strain_rate_dimensionless: 1.0e-5, stop: {softening: 0.3}}\n";
  r = triax_qs("predict " + p.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("error: stages[0].stop.axial_strain: needed to plan the run"), std::string::npos) << r.err;
  r = triax_qs("fit-rates --run 1e-5 --run 2e-6,x.json");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("error: --run[0]: expected EPS',SUMMARY"), std::string::npos) << r.err;
}
