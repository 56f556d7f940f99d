// Resume of a killed rig test (launch_equiv_scripts/run_triaxial.sh --resume,
// protocol_session_checkpoint.cpp) on tests/data/protocols/rig_resume.yaml
// (200 spheres, PID servo, the adaptive rate of the rate controller node, a
// checkpoint every 200 control ticks):
// with the C++ controllers (nodelets; the Python ones resume the same way:
// checked by hand, not here, to keep the suite short):
//   1. the test run uninterrupted (then `--resume` of its folder is refused:
//      no checkpoint, exit 2);
//   2. the same test, kill -9 of the rig process (the nodelet manager) in the
//      shear once a checkpoint of the shear is on disk (and the rig has gone
//      on past it): the script exits 3, the checkpoint stays;
//   3. run_triaxial.sh --resume on the killed run's folder: exit 0, and
//      - summary.json equals the uninterrupted run's but for the wall time,
//      - every sample of results.h5 and every summary attribute (but the
//        wall time) equal the uninterrupted run's bit for bit,
//      - the killed run's bags are kept (closed at every checkpoint, the last
//        one reindexed: no .active left) and hold every tick up to the
//        checkpoint; the resumed run's bags (rig_r1_*.bag) start at the
//        checkpoint's tick + 1, and together they hold every tick of the uninterrupted
//        run with the same stress message (bits of p, q, time, stress), and
//        bag_report.py's table of every rig topic by tick is the same,
//      - the finished test leaves no checkpoint.
#include <cstdlib>
#include <cstring>
#include <map>
#include <regex>

#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include "../unit/support/measures_bits.h"
#include "support/script_run.h"
#include "virtual_triaxial/Stress.h"
#include "virtual_triaxial/io/checkpoint_file.h"
#include "virtual_triaxial/io/results_file.h"

namespace {
using namespace vt::test;

constexpr double kRunBound = 240.0;  // start, consolidation, shear, stop; busy machine
const char* kProtocol = "tests/data/protocols/rig_resume.yaml";
const char* kEnv = "PLOTS=0 SNAPSHOTS=0";

/// summary.json without the wall time and the results file's path (the test's folder).
std::string summary_without_wall(const fs::path& p) {
  std::string s = slurp(p);
  s = std::regex_replace(s, std::regex("\"wall_seconds\":[^,}]*,?"), "");
  return std::regex_replace(s, std::regex("\"results\":\"[^\"]*\""), "");
}

/// tick -> the bits of its /stress message (time, p, q, the tensor), from bags in order (later ones win).
std::map<std::uint64_t, std::vector<std::uint64_t>> stress_by_tick(const std::vector<fs::path>& bags) {
  std::map<std::uint64_t, std::vector<std::uint64_t>> out;
  for (const fs::path& p : bags) {
    rosbag::Bag bag(p.string(), rosbag::bagmode::Read);
    rosbag::View view(bag, rosbag::TopicQuery(std::vector<std::string>{"/stress"}));
    for (const rosbag::MessageInstance& mi : view) {
      const auto s = mi.instantiate<virtual_triaxial::Stress>();
      if (!s) continue;
      std::vector<double> v = {s->time, s->p, s->q};
      v.insert(v.end(), s->stress.begin(), s->stress.end());
      out[s->tick] = bits(v);
    }
  }
  return out;
}

/// <dir>/<prefix>_<k>.bag for k = 0, 1, ... (the split files of one recording, in order).
std::vector<fs::path> bag_files(const fs::path& dir, const std::string& prefix) {
  std::vector<fs::path> out;
  for (int k = 0; fs::exists(dir / (prefix + "_" + std::to_string(k) + ".bag")); ++k)
    out.push_back(dir / (prefix + "_" + std::to_string(k) + ".bag"));
  return out;
}

std::string joined(const std::vector<fs::path>& files) {
  std::string s;
  for (const fs::path& f : files) s += " '" + f.string() + "'";
  return s;
}

/// Uninterrupted vs killed + resumed, on `protocol` with the script's extra
/// `env`; the checkpoint holds `servo_numbers` of servo memory.
void expect_resume_equals_uninterrupted(const std::string& tag, const std::string& env, const std::string& protocol,
                                        std::size_t servo_numbers) {
  ScriptRun whole(tag + "_whole", env, protocol);
  ASSERT_GE(whole.wait_exit(kRunBound), 0) << whole.log();
  ASSERT_EQ(whole.code(), 0) << whole.log();
  EXPECT_FALSE(fs::exists(whole.out() / "results.h5.checkpoint.h5")) << "a finished test leaves no checkpoint";
  {  // so there is nothing to resume: refused at once, naming the file
    ScriptRun nothing(tag + "_nothing", env, "--resume " + whole.out().string());
    ASSERT_GE(nothing.wait_exit(30.0), 0) << nothing.log();
    EXPECT_EQ(nothing.code(), 2) << nothing.log();
    EXPECT_NE(nothing.log().find("--resume: no checkpoint " + (whole.out() / "results.h5.checkpoint.h5").string()),
              std::string::npos)
        << nothing.log();
    nothing.remove_outputs();
  }

  ScriptRun cut(tag + "_cut", env, protocol);
  const fs::path checkpoint = cut.out() / "results.h5.checkpoint.h5";
  ASSERT_TRUE(cut.wait_for_log("[rig] running", kRunBound)) << cut.log();
  // Wait for a checkpoint inside the shear, then for the rig to go on past it.
  vt::io::CheckpointFile c;
  const auto t0 = Clock::now();
  while (true) {
    ASSERT_LT(seconds_since(t0), kRunBound) << "no checkpoint in the shear\n" << cut.log();
    ASSERT_FALSE(cut.exited()) << "the test ended before a checkpoint in the shear\n" << cut.log();
    if (fs::exists(checkpoint)) {
      c = vt::io::read_checkpoint(checkpoint.string());
      if (c.run.stage_index == 1) break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  const int rig = cut.find("__name:=rig_manager");
  ASSERT_GT(rig, 0) << cut.log();
  ASSERT_EQ(::kill(rig, SIGKILL), 0);
  ASSERT_GE(cut.wait_exit(kRunBound), 0) << cut.log();
  EXPECT_EQ(cut.code(), 3) << cut.log();
  ASSERT_TRUE(fs::exists(checkpoint)) << "the killed test keeps its checkpoint";
  c = vt::io::read_checkpoint(checkpoint.string());  // the last one (maybe later than the one seen)
  ASSERT_EQ(c.run.stage_index, 1u);
  ASSERT_GT(c.run.rig_tick, 0u);
  EXPECT_EQ(c.run.servo_memory.size(), servo_numbers) << "the servo's memory";
  EXPECT_EQ(c.run.rate_controller_memory.size(), 3u) << "the adaptive rate controller's memory";
  EXPECT_FALSE(bag_files(cut.out(), "rig").empty()) << "the bags closed at the checkpoints";
  const std::size_t killed_rows = vt::io::read_results_series((cut.out() / "results.h5").string()).size();

  ScriptRun resumed(tag + "_again", env, "--resume " + cut.out().string());
  ASSERT_GE(resumed.wait_exit(kRunBound), 0) << resumed.log();
  ASSERT_EQ(resumed.code(), 0) << resumed.log();
  EXPECT_FALSE(fs::exists(checkpoint)) << "the finished test leaves no checkpoint";

  EXPECT_EQ(summary_without_wall(cut.out() / "summary.json"), summary_without_wall(whole.out() / "summary.json"));
  const std::string a = (whole.out() / "results.h5").string(), b = (cut.out() / "results.h5").string();
  const auto sa = vt::io::read_results_series(a), sb = vt::io::read_results_series(b);
  ASSERT_EQ(sa.size(), sb.size());
  ASSERT_GT(sb.size(), killed_rows) << "the resume added samples";
  for (std::size_t i = 0; i < sa.size(); ++i) ASSERT_EQ(bits(sa[i]), bits(sb[i])) << "sample " << i;
  auto na = vt::io::read_summary_numbers(a), nb = vt::io::read_summary_numbers(b);
  na.erase("wall_seconds");
  nb.erase("wall_seconds");
  EXPECT_EQ(na, nb);
  EXPECT_EQ(vt::io::read_summary_texts(a), vt::io::read_summary_texts(b));

  // The bags: the killed run's kept (closed at every checkpoint, the open
  // one reindexed), the resumed one continuing its ticks.
  EXPECT_FALSE(fs::exists(cut.out() / "rig_0.bag.active"));
  const std::vector<fs::path> old_bags = bag_files(cut.out(), "rig"), new_bags = bag_files(cut.out(), "rig_r1");
  ASSERT_GE(old_bags.size(), 2u) << "a closed bag per checkpoint, and the reindexed last one\n" << resumed.log();
  ASSERT_FALSE(new_bags.empty()) << resumed.log();
  for (const auto& f : fs::directory_iterator(cut.out()))
    EXPECT_EQ(f.path().string().find(".active"), std::string::npos) << f.path() << " left open";
  const auto ta = stress_by_tick(bag_files(whole.out(), "rig"));
  const auto old_ticks = stress_by_tick(old_bags), new_ticks = stress_by_tick(new_bags);
  ASSERT_FALSE(old_ticks.empty());
  ASSERT_FALSE(new_ticks.empty());
  EXPECT_EQ(new_ticks.begin()->first, c.run.rig_tick + 1) << "the resumed bag continues the tick numbering";
  // Every tick up to the checkpoint is in the killed run's bags.
  for (std::uint64_t t = 1; t <= c.run.rig_tick; ++t) ASSERT_TRUE(old_ticks.count(t)) << "tick " << t << " lost";
  std::vector<fs::path> all = old_bags;
  all.insert(all.end(), new_bags.begin(), new_bags.end());
  const auto tb = stress_by_tick(all);
  ASSERT_EQ(ta.size(), tb.size());
  for (const auto& [tick, v] : ta) {
    const auto it = tb.find(tick);
    ASSERT_NE(it, tb.end()) << "tick " << tick << " is in no bag of the resumed test";
    ASSERT_EQ(it->second, v) << "tick " << tick;
  }
  // Every rig topic, joined by tick (bag_report.py, the tool run_triaxial.sh
  // runs on rig*.bag): the resumed test's two bags give the uninterrupted
  // run's table byte for byte (numbers printed to round-trip precision).
  const std::string report = "cd '" VT_SOURCE_DIR "' && /usr/bin/python3 scripts/bag_report.py --csv-only ";
  ASSERT_EQ(std::system((report + joined(bag_files(whole.out(), "rig")) + " --out '" + (whole.out() / "csv").string() +
                         "' > /dev/null 2>&1").c_str()), 0);
  ASSERT_EQ(std::system((report + joined(all) + " --out '" + (cut.out() / "csv").string() + "' > /dev/null 2>&1").c_str()),
            0);
  const std::string csv_a = slurp(whole.out() / "csv/rig_series.csv"), csv_b = slurp(cut.out() / "csv/rig_series.csv");
  EXPECT_GT(csv_a.size(), 1000u);
  EXPECT_TRUE(csv_a == csv_b) << "rig_series.csv of the resumed test differs from the uninterrupted one's";
  std::printf("[ measured ] killed at tick >= %llu (checkpoint), %zu of %zu samples kept; whole run %zu ticks\n",
              static_cast<unsigned long long>(c.run.rig_tick), static_cast<std::size_t>(c.results_rows), sa.size(),
              ta.size());
  EXPECT_TRUE(cut.left_behind().empty());
  if (!::testing::Test::HasFailure())
    for (const ScriptRun* r : {&whole, &cut, &resumed}) r->remove_outputs();
}

TEST(RigResume, KilledMidShearAndResumedEqualsTheUninterruptedTest) {
  // The C++ controllers, nodelets in the rig's process: the PID servo keeps 10 numbers.
  expect_resume_equals_uninterrupted("resume", kEnv, kProtocol, 10);
}

}  // namespace
