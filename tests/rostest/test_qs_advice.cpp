// rostest qs_advice.test: test_protocol_node's ~predict_quasi_static service.
//   1. the README's main job (dense_1000, 100 kPa, OD 0.3 %, eps' 1e-5 to
//      10 %): the answer is eq. 84 in closed form on the answered e0,
//      sigma_bar0 and Delta (0.27 e0^-4 sigma_bar0^0.67 Delta^-2.5 I_QS),
//      eq. 85 (eps'_QS / T0), the plan (steps = eps_final / (c_t eps'),
//      wall = steps N cost), the rate warning, and the same numbers as `triax_qs predict`'s
//      code (io::build_qs_advice) on the file; the I_QS is the protocol's;
//   2. the same protocol as inline YAML with I_QS = 0.05 % and ND: the answer
//      states that I_QS, and eq. 84 is linear in it (half the rate at half
//      the threshold, times the ND/OD factor Delta^0.5);
//   3. refusals name the field: no shear stage (stages), two protocols
//      (protocol_file), nothing given before any test (protocol_file);
//      the node keeps serving.
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <ros/ros.h>

#include "virtual_triaxial/PredictQuasiStatic.h"
#include "virtual_triaxial/io/qs_advice.h"
#include "virtual_triaxial/io/scene_builder.h"
#include "virtual_triaxial/io/scene_parser.h"

namespace {

std::string g_protocol;
const char* kService = "/test_protocol_node/predict_quasi_static";

virtual_triaxial::PredictQuasiStatic::Response ask(const std::string& file, const std::string& yaml,
                                                   double cost) {
  virtual_triaxial::PredictQuasiStatic srv;
  srv.request.protocol_file = file;
  srv.request.protocol_yaml = yaml;
  srv.request.cost_per_particle_step = cost;
  EXPECT_TRUE(ros::service::call(kService, srv));
  return srv.response;
}

std::string main_job_yaml(const std::string& extra_control, const std::string& model) {
  // the main job's protocol text with an absolute sample path and changes
  std::ifstream in(g_protocol);
  std::stringstream ss;
  ss << in.rdbuf();
  std::string t = ss.str();
  const std::string dir = g_protocol.substr(0, g_protocol.find_last_of('/'));
  const std::string rel = "../samples/dense_1000.h5";
  t.replace(t.find(rel), rel.size(), dir + "/" + rel);
  const std::string thr = "quasi_static_threshold: 1.0e-3";
  t.replace(t.find(thr), thr.size(), extra_control);
  const std::string od = "model: OD";
  t.replace(t.find(od), od.size(), "model: " + model);
  return t;
}

TEST(QsAdvice, MainJobClosedFormsAndTriaxQsNumbers) {
  ASSERT_TRUE(ros::service::waitForService(kService, ros::Duration(60)));
  const double cost = 2e-6;
  const auto r = ask(g_protocol, "", cost);
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_EQ(r.protocol, g_protocol);
  EXPECT_EQ(r.particles, 1000u);
  EXPECT_EQ(r.shape, "sphere");
  EXPECT_EQ(r.damping_model, "OD");
  EXPECT_DOUBLE_EQ(r.damping_ratio, 0.003);
  EXPECT_DOUBLE_EQ(r.quasi_static_threshold, 1e-3);     // control.quasi_static_threshold
  EXPECT_DOUBLE_EQ(r.confining_pressure, 100e3);
  EXPECT_NEAR(r.void_ratio, 0.609, 0.001);               // the shipped sample (README)
  // eq. 84, OD: 0.27 e0^-4 sigma_bar0^0.67 Delta^-2.5 I_QS
  const double eq84 = 0.27 * std::pow(r.void_ratio, -4) * std::pow(r.sigma_bar0, 0.67) *
                      std::pow(r.dispersity_index, -2.5) * r.quasi_static_threshold;
  EXPECT_NEAR(r.eps_prime_qs / eq84, 1.0, 1e-12);
  EXPECT_NEAR(r.strain_rate_qs * r.t0 / r.eps_prime_qs, 1.0, 1e-12);      // eq. 85
  EXPECT_NEAR(r.eps_prime_qs_other_damping / r.eps_prime_qs, std::sqrt(r.dispersity_index), 1e-9);
  // the plan: steps = ceil(eps_final / (c_t eps')), wall = steps N cost
  EXPECT_EQ(r.shear_stage, "shear");
  EXPECT_DOUBLE_EQ(r.shear_eps_prime, 1e-5);
  EXPECT_DOUBLE_EQ(r.final_axial_strain, 0.10);
  EXPECT_DOUBLE_EQ(r.qs_steps, std::ceil(0.10 / (0.3 * r.eps_prime_qs)));
  EXPECT_DOUBLE_EQ(r.shear_steps, std::ceil(0.10 / (0.3 * 1e-5)));
  EXPECT_NEAR(r.qs_wall_time / (r.qs_steps * 1000 * cost), 1.0, 1e-9);
  EXPECT_FALSE(r.cost_measured);
  // the main job is far too fast: the advice says so
  bool warned = false;
  for (const std::string& w : r.warnings) warned |= w.find("predicted quasi-static rate") != std::string::npos;
  EXPECT_TRUE(warned) << "no rate warning";
  // the same numbers as `triax_qs predict` (io::build_qs_advice on the file)
  const vt::io::SceneConfig scene = vt::io::load_scene(g_protocol);
  const vt::io::QsAdvice a = vt::io::build_qs_advice(scene, vt::io::build_simulation(scene), cost);
  EXPECT_EQ(r.json, vt::io::qs_advice_json(a));
  EXPECT_DOUBLE_EQ(r.eps_prime_qs, a.prediction.eps_prime_qs);
  EXPECT_DOUBLE_EQ(r.eps_prime_eq72, a.eps_prime_eq72);
}

TEST(QsAdvice, InlineYamlStatesItsThresholdAndModel) {
  const auto od = ask(g_protocol, "", 2e-6);
  const auto nd = ask("", main_job_yaml("quasi_static_threshold: 5.0e-4", "ND"), 2e-6);
  ASSERT_TRUE(nd.success) << nd.message;
  EXPECT_DOUBLE_EQ(nd.quasi_static_threshold, 5e-4);
  EXPECT_EQ(nd.damping_model, "ND");
  // eq. 84 is linear in I_QS; ND / OD = Delta^(-2 + 2.5)
  EXPECT_NEAR(nd.eps_prime_qs / od.eps_prime_qs, 0.5 * std::sqrt(od.dispersity_index), 1e-9);
}

TEST(QsAdvice, RefusalsNameTheField) {
  // a protocol without a shear stage
  std::string t = main_job_yaml("quasi_static_threshold: 1.0e-3", "OD");
  t = t.substr(0, t.find("  - name: shear")) + "output:" + t.substr(t.find("\noutput:") + 8);
  auto r = ask("", t, 2e-6);
  EXPECT_FALSE(r.success);
  EXPECT_EQ(r.message.rfind("stages:", 0), 0u) << r.message;
  r = ask(g_protocol, "particles: {}", 2e-6);
  EXPECT_FALSE(r.success);
  EXPECT_EQ(r.message.rfind("protocol_file:", 0), 0u) << r.message;
  r = ask("/nonexistent/protocol.yaml", "", 2e-6);
  EXPECT_FALSE(r.success);
  EXPECT_NE(r.message.find("/nonexistent/protocol.yaml"), std::string::npos) << r.message;
  // no test has run on this node: nothing to default to
  r = ask("", "", 2e-6);
  EXPECT_FALSE(r.success);
  EXPECT_EQ(r.message.rfind("protocol_file:", 0), 0u) << r.message;
  // still serving, and measuring the cost when none is given
  r = ask(g_protocol, "", 0.0);
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_TRUE(r.cost_measured);
  EXPECT_GT(r.cost_per_particle_step, 0.0);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_qs_advice");
  ros::NodeHandle pnh("~");
  pnh.getParam("protocol", g_protocol);
  return RUN_ALL_TESTS();
}
