// The main entry script on a mini protocol, end to end (no master needed: the
// script starts its own on a free loopback port):
//   OUT=<tmp> launch_equiv_scripts/run_triaxial.sh tests/data/protocols/rig_script_mini.yaml
// Asserts what the issue asks of the bag and the output folder:
//   - exit code 0, summary.json with verdict completed, results.h5, the plots
//     of scripts/bag_report.py and its CSV, the specimen snapshots and the
//     specimen section picture;
//   - the bag (rig_*.bag, split files) holds every rig topic; the five state
//     topics have exactly one message per control tick of the test (the
//     summary's `ticks`), consecutive ticks, strictly rising simulation-time
//     stamps; servo_state, protocol_status, cell_command, /clock and the
//     servo's parameter_updates are there too;
//   - no process of the rig is left running (its master port is free);
//   - the same protocol on the rig as three processes (nodelets:=false), with
//     the bag_recorder process, records every tick and takes the same decisions;
//   - the checkpoint saved after the consolidation stage continues bit for
//     bit: triax_run on a protocol holding only the shear stage, started from
//     that checkpoint, prints the same phi_peak, eps_peak and e0 as the rig.
#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include "virtual_triaxial/Fabric.h"
#include "virtual_triaxial/KineticEnergy.h"
#include "virtual_triaxial/MomentIndex.h"
#include "virtual_triaxial/Strain.h"
#include "virtual_triaxial/Stress.h"

namespace fs = std::filesystem;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Series {
  std::vector<std::uint64_t> ticks;
  std::vector<double> stamps;
};

template <class M>
Series read_series(const std::vector<fs::path>& bags, const std::string& topic) {
  Series s;
  for (const fs::path& p : bags) {
    rosbag::Bag bag(p.string(), rosbag::bagmode::Read);
    rosbag::View view(bag, rosbag::TopicQuery(std::vector<std::string>{topic}));
    for (const rosbag::MessageInstance& m : view) {
      auto msg = m.instantiate<M>();
      if (!msg) continue;
      s.ticks.push_back(msg->tick);
      s.stamps.push_back(msg->header.stamp.toSec());
    }
  }
  return s;
}

std::map<std::string, std::size_t> topic_counts(const std::vector<fs::path>& bags) {
  std::map<std::string, std::size_t> n;
  for (const fs::path& p : bags) {
    rosbag::Bag bag(p.string(), rosbag::bagmode::Read);
    rosbag::View view(bag);
    for (const rosbag::MessageInstance& m : view) ++n[m.getTopic()];
  }
  return n;
}

/// The script's log, one per test process (a fixed name was overwritten by
/// another worktree's run of this test on a shared machine).
fs::path log_path() { return fs::temp_directory_path() / ("vt_rig_script_" + std::to_string(::getpid()) + ".log"); }

class RigScript : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    out_ = fs::temp_directory_path() / ("vt_rig_script_" + std::to_string(::getpid()));
    fs::remove_all(out_);
    const std::string cmd = "cd '" VT_SOURCE_DIR "' && OUT='" + out_.string() +
                            "' launch_equiv_scripts/run_triaxial.sh tests/data/protocols/rig_script_mini.yaml > '" +
                            log_path().string() + "' 2>&1";
    const int status = std::system(cmd.c_str());
    code_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    for (const auto& e : fs::directory_iterator(out_))
      if (e.path().extension() == ".bag" && e.path().filename().string().rfind("rig", 0) == 0)
        bags_.push_back(e.path());
    std::sort(bags_.begin(), bags_.end());
    const std::string json = slurp(out_ / "summary.json");
    std::smatch m;
    if (std::regex_search(json, m, std::regex("\"ticks\":([0-9]+)"))) ticks_ = std::stoull(m[1]);
    summary_ = json;
  }
  static fs::path out_;
  static int code_;
  static std::vector<fs::path> bags_;
  static std::uint64_t ticks_;
  static std::string summary_;
};
fs::path RigScript::out_;
int RigScript::code_ = -1;
std::vector<fs::path> RigScript::bags_;
std::uint64_t RigScript::ticks_ = 0;
std::string RigScript::summary_;

TEST_F(RigScript, CompletesAndLeavesOneOutputFolder) {
  ASSERT_EQ(code_, 0) << "see " << log_path();
  EXPECT_NE(summary_.find("\"verdict\":\"completed\""), std::string::npos) << summary_;
  EXPECT_GT(ticks_, 100u);
  for (const char* f : {"results.h5", "summary.json", "plots/rig_series.csv", "plots/q_eps_a.png",
                        "plots/eps_v_eps_a.png", "plots/q_p_stress_path.png", "plots/e_log_p.png",
                        "plots/I_mom_eps_a.png", "plots/kinetic_energy_eps_a.png", "ros_home",
                        "specimen_section.png", "specimen/particles.pvd", "specimen/contacts.pvd"})
    EXPECT_TRUE(fs::exists(out_ / f)) << f;
  EXPECT_TRUE(fs::exists(out_ / "checkpoints/after_0_consolidation.h5"));
  EXPECT_TRUE(fs::exists(out_ / "checkpoints/after_1_shear.h5"));
  ASSERT_FALSE(bags_.empty()) << "no rig_*.bag in " << out_;
}

TEST_F(RigScript, BagHoldsEveryRigTopic) {
  ASSERT_FALSE(bags_.empty());
  const auto n = topic_counts(bags_);
  for (const char* t : {"/stress", "/strain", "/moment_index", "/kinetic_energy", "/fabric", "/servo_state",
                        "/protocol_status", "/cell_command", "/clock", "/diagnostics",
                        "/servo/parameter_updates", "/run_test/feedback", "/run_test/result"})
    EXPECT_GT(n.count(t) ? n.at(t) : 0u, 0u) << t << " missing from the bag";
}

template <class M>
void expect_one_per_tick(const std::vector<fs::path>& bags, const std::string& topic, std::uint64_t ticks) {
  const Series s = read_series<M>(bags, topic);
  ASSERT_EQ(s.ticks.size(), ticks) << topic << ": expected one message per control tick of the test";
  for (std::size_t i = 1; i < s.ticks.size(); ++i) {
    ASSERT_EQ(s.ticks[i], s.ticks[i - 1] + 1) << topic << " at message " << i;
    ASSERT_GT(s.stamps[i], s.stamps[i - 1]) << topic << ": simulation-time stamps must rise strictly";
  }
}

TEST_F(RigScript, StateTopicsHaveOneMessagePerTickWithRisingStamps) {
  ASSERT_FALSE(bags_.empty());
  expect_one_per_tick<virtual_triaxial::Stress>(bags_, "/stress", ticks_);
  expect_one_per_tick<virtual_triaxial::Strain>(bags_, "/strain", ticks_);
  expect_one_per_tick<virtual_triaxial::MomentIndex>(bags_, "/moment_index", ticks_);
  expect_one_per_tick<virtual_triaxial::KineticEnergy>(bags_, "/kinetic_energy", ticks_);
  expect_one_per_tick<virtual_triaxial::Fabric>(bags_, "/fabric", ticks_);
}

TEST_F(RigScript, NoRigProcessIsLeftBehind) {
  const std::string log = slurp(log_path());
  std::smatch m;
  ASSERT_TRUE(std::regex_search(log, m, std::regex("master http://127\\.0\\.0\\.1:([0-9]+)"))) << log;
  const std::string port = m[1];
  // Nothing listens on the master port any more.
  const std::string cmd = "ss -ltn 2>/dev/null | grep -q ':" + port + " '";
  EXPECT_NE(std::system(cmd.c_str()), 0) << "something still listens on port " << port;
  EXPECT_NE(std::system(("pgrep -f '[r]osmaster.*" + port + "' > /dev/null").c_str()), 0);
}

std::string json_field(const std::string& json, const std::string& key) {
  std::smatch m;
  if (!std::regex_search(json, m, std::regex("\"" + key + "\":([^,}]+)"))) return "(missing " + key + ")";
  return m[1];
}

TEST_F(RigScript, TheConsolidationCheckpointContinuesBitForBit) {
  ASSERT_EQ(code_, 0);
  const fs::path ckpt = out_ / "checkpoints/after_0_consolidation.h5";
  ASSERT_TRUE(fs::exists(ckpt));
  // The shear stage of tests/data/protocols/rig_script_mini.yaml alone.
  const fs::path proto = out_ / "shear_from_checkpoint.yaml";
  {
    std::ofstream y(proto);
    y << "particles: {sample_file: " << ckpt.string() << "}\n"
      << "material: {friction: 0.5}\ndamping: {model: OD, ratio: 0.003}\ntime_step_ratio: 0.3\n"
      << "control: {interval: 10, quasi_static_threshold: 1.0e-3,\n"
      << "  servo: {strategy: pid, gain: 1.0, ki: 0.6, max_dimensionless_rate: 1.0e-4}}\n"
      << "stages:\n  - {name: shear, type: drained_shear, confining_pressure: 100.0e3,\n"
      << "     strain_rate_dimensionless: 1.0e-5, axial_axis: z, stop: {axial_strain: 0.01}}\n"
      << "output: {interval: 200, progress_seconds: 5.0}\n";
  }
  const fs::path json = out_ / "shear_from_checkpoint.json";
  const std::string cmd = "OMP_NUM_THREADS=1 '" VT_PROGRAM_DIR "/triax_run' '" +
                          proto.string() + "' --quiet --out '" + (out_ / "shear.h5").string() + "' > '" +
                          json.string() + "' 2>/dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const std::string headless = slurp(json);
  for (const char* key : {"phi_peak_deg", "eps_peak", "e0", "mean_moment_index_to_peak", "q_peak_pa"})
    EXPECT_EQ(json_field(headless, key), json_field(summary_, key)) << key;
}

// The rig as three processes (RIG_ARGS nodelets:=false), recorded by the
// bag_recorder process instead of the nodelet: every state message is in
// the bag, and the test takes the same decisions as the nodelet rig.
TEST_F(RigScript, TheProcessRigWithTheStandaloneRecorderRecordsEveryTickAndAgrees) {
  ASSERT_EQ(code_, 0);
  const fs::path out = out_.string() + "_processes";
  fs::remove_all(out);
  const std::string cmd = "cd '" VT_SOURCE_DIR "' && OUT='" + out.string() +
                          "' RIG_ARGS='nodelets:=false' launch_equiv_scripts/run_triaxial.sh "
                          "tests/data/protocols/rig_script_mini.yaml > '" +
                          (fs::temp_directory_path() / "vt_rig_script_processes.log").string() + "' 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << "see " << (fs::temp_directory_path() / "vt_rig_script_processes.log");
  std::vector<fs::path> bags;
  for (const auto& e : fs::directory_iterator(out))
    if (e.path().extension() == ".bag" && e.path().filename().string().rfind("rig", 0) == 0) bags.push_back(e.path());
  ASSERT_FALSE(bags.empty());
  expect_one_per_tick<virtual_triaxial::Stress>(bags, "/stress", ticks_);
  expect_one_per_tick<virtual_triaxial::Fabric>(bags, "/fabric", ticks_);
  const std::string json = slurp(out / "summary.json");
  for (const char* key : {"phi_peak_deg", "eps_peak", "e0", "mean_moment_index_to_peak", "ticks"})
    EXPECT_EQ(json_field(json, key), json_field(summary_, key)) << key;
}

}  // namespace
