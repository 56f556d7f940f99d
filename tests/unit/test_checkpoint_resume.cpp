// triax_run checkpoints and --resume (protocol/run_checkpoint.h,
// io/checkpoint_file.h): a run killed with SIGKILL (the test hook
// VT_TEST_KILL_AT_SAMPLE, as kill -9 at a known sample) and resumed from its
// last checkpoint finishes equal to the uninterrupted run, bit for bit: every
// sample of the results series, every summary attribute and the JSON summary
// (except the wall time). Killed in the shear stage (proportional servo
// consolidation before it), in a PID-servo consolidation (the servo's
// integral and previous error, then a stage change after the resume) and in
// a shear under the adaptive rate strategy (its smoothed index and rate). The
// killed run's results file is valid and says `interrupted`; a changed
// protocol or a missing checkpoint is refused naming it.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "support/cli.h"
#include "support/measures_bits.h"
#include "virtual_triaxial/io/results_file.h"

namespace fs = std::filesystem;

namespace {

using vt::test::bits;

fs::path tmpdir() {
  static const fs::path d = vt::test::scratch_dir("resume");
  return d;
}

vt::test::CliRun triax_run(const std::string& args, const std::string& env = "") {
  return vt::test::run_program("triax_run", args, tmpdir(), env);
}

/// drained_mini.yaml (200 spheres) with a checkpoint every 100 control
/// ticks and `edit` applied (from -> to pairs).
fs::path protocol(const std::string& name, const std::vector<std::pair<std::string, std::string>>& edit) {
  std::string y = vt::test::slurp(fs::path(VT_SOURCE_DIR) / "tests/data/protocols/drained_mini.yaml");
  auto replace = [&](const std::string& from, const std::string& to) {
    const std::size_t at = y.find(from);
    if (at == std::string::npos) throw std::runtime_error("protocol: no '" + from + "'");
    y.replace(at, from.size(), to);
  };
  replace("../sample_200_100kPa.h5", std::string(VT_SOURCE_DIR) + "/tests/data/sample_200_100kPa.h5");
  replace("progress_seconds: 5.0", "progress_seconds: 5.0\n  checkpoint_ticks: 100");
  for (const auto& [from, to] : edit) replace(from, to);
  const fs::path p = tmpdir() / (name + ".yaml");
  std::ofstream(p) << y;
  return p;
}

/// The JSON summary line without the wall time and the results path.
std::string summary_line(const std::string& out) {
  std::string line = out.substr(out.rfind('{'));
  line = std::regex_replace(line, std::regex("\"wall_seconds\":[^,]*,"), "");
  return std::regex_replace(line, std::regex("\"results\":\"[^\"]*\""), "");
}

/// Uninterrupted run vs killed at sample `kill_at` + --resume.
void expect_resume_equals_uninterrupted(const fs::path& scene, const std::string& tag, int kill_at,
                                        const std::string& killed_in) {
  const fs::path whole = tmpdir() / (tag + "_whole.h5"), cut = tmpdir() / (tag + "_cut.h5");
  const auto a = triax_run(scene.string() + " --out " + whole.string() + " --threads 1 --quiet");
  ASSERT_EQ(a.code, 0) << a.err;
  EXPECT_FALSE(fs::exists(whole.string() + ".checkpoint.h5")) << "a finished run leaves no checkpoint";

  const auto k = triax_run(scene.string() + " --out " + cut.string() + " --threads 1",
                           "VT_TEST_KILL_AT_SAMPLE=" + std::to_string(kill_at));
  ASSERT_EQ(k.code, -1) << "killed by SIGKILL: " << k.err;
  ASSERT_NE(k.err.find("[checkpoint]"), std::string::npos) << k.err;
  ASSERT_TRUE(fs::exists(cut.string() + ".checkpoint.h5"));
  const std::string last_stage = k.err.substr(k.err.rfind("] start:") - 20);
  EXPECT_NE(last_stage.find("[" + killed_in + "]"), std::string::npos) << "killed in " << killed_in << ": " << k.err;
  // the killed run's results: valid, saying so, with the samples of its last flush
  const auto partial = vt::io::read_results_series(cut.string());
  EXPECT_GT(partial.size(), 0u);
  EXPECT_EQ(vt::io::read_summary_texts(cut.string()).at("verdict"), "interrupted");

  const auto r = triax_run("--resume " + cut.string() + " --threads 1");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("resumed from the checkpoint"), std::string::npos) << r.err;
  EXPECT_EQ(summary_line(r.out), summary_line(a.out));
  EXPECT_FALSE(fs::exists(cut.string() + ".checkpoint.h5"));

  const auto sa = vt::io::read_results_series(whole.string()), sb = vt::io::read_results_series(cut.string());
  ASSERT_EQ(sa.size(), sb.size());
  ASSERT_GT(sa.size(), partial.size()) << "the resume added samples";
  for (std::size_t i = 0; i < sa.size(); ++i) ASSERT_EQ(bits(sa[i]), bits(sb[i])) << "sample " << i;
  auto na = vt::io::read_summary_numbers(whole.string()), nb = vt::io::read_summary_numbers(cut.string());
  na.erase("wall_seconds");
  nb.erase("wall_seconds");
  EXPECT_EQ(na, nb);
  EXPECT_EQ(vt::io::read_summary_texts(whole.string()), vt::io::read_summary_texts(cut.string()));
}

}  // namespace

TEST(CheckpointResume, KilledInTheShearResumesToTheUninterruptedRunBitForBit) {
  // 103 samples, the shear from sample 3 on: killed at sample 80 of the shear.
  expect_resume_equals_uninterrupted(protocol("shear", {}), "shear", 80, "shear");
}

TEST(CheckpointResume, KilledInAPidConsolidationResumesWithTheServosMemory) {
  // consolidation to 130 kPa with a PID servo (700 steps, 8 samples), killed at its 5th sample
  const fs::path p = protocol("pid", {{"strategy: proportional", "strategy: pid\n    ki: 0.1\n    kd: 0.05"},
                                      {"confining_pressure: 100.0e3", "confining_pressure: 130.0e3"},
                                      {"steps: 2000", "steps: 4000"}});
  expect_resume_equals_uninterrupted(p, "pid", 5, "consolidation");
}

TEST(CheckpointResume, KilledUnderTheAdaptiveRateResumesWithTheStrategysMemory) {
  // the shear under the adaptive rate strategy (its smoothed I_mom and rate,
  // the stage's specimen at its start for eq. 84), killed in the shear
  const fs::path p = protocol("adaptive", {{"strain_rate_dimensionless: 1.0e-5",
                                            "rate: {strategy: adaptive, target: 0.7}"},
                                           {"stop: {axial_strain: 0.01, softening: 0.3}", "stop: {axial_strain: 0.00015}"}});
  // 50 000 shear steps, 500 samples (the rate falls to its floor 1e-9 at the start): killed at sample 200
  expect_resume_equals_uninterrupted(p, "adaptive", 200, "shear");
}

TEST(CheckpointResume, AChangedProtocolOrNoCheckpointIsRefused) {
  const fs::path p = protocol("changed", {});
  const fs::path out = tmpdir() / "changed.h5";
  const auto k = triax_run(p.string() + " --out " + out.string() + " --threads 1 --quiet", "VT_TEST_KILL_AT_SAMPLE=60");
  ASSERT_EQ(k.code, -1) << k.err;
  std::ofstream(p, std::ios::app) << "# edited\n";
  const auto r = triax_run("--resume " + out.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("triax_run: error: --resume: " + p.string() + ": changed since the checkpoint"),
            std::string::npos) << r.err;
  const auto n = triax_run("--resume " + (tmpdir() / "never.h5").string());
  EXPECT_EQ(n.code, 2);
  EXPECT_NE(n.err.find("--resume: no checkpoint " + (tmpdir() / "never.h5.checkpoint.h5").string()),
            std::string::npos) << n.err;
}
