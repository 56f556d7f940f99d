// triax_run end to end: bad input gives exit code 2 and a one-line error that
// names the field; c_t >= 1 runs with a warning; a blow-up (c_t far above the
// critical estimate) stops with verdict
// `unstable`, exit code 3, within a few hundred steps, and the results file
// keeps the history up to the last good output; the run limits
// (io/run_limits.h: rate, c_t, particle count) refuse before the run starts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>
#include <string>

#include "virtual_triaxial/io/results_file.h"
#include "virtual_triaxial/io/sample_file.h"
#include "support/cli.h"
#include "support/run_limits_cases.h"
#include "virtual_triaxial/dem/random_stream.h"

namespace fs = std::filesystem;
using namespace vt::dem;

namespace {

using vt::test::CliRun;
using vt::test::slurp;

fs::path tmpdir() {
  static const fs::path d = vt::test::scratch_dir("cli");
  return d;
}

CliRun triax_run(const std::string& args) { return vt::test::run_program("triax_run", args, tmpdir()); }

fs::path write_scene(const std::string& name, const std::string& yaml) {
  const fs::path p = tmpdir() / name;
  std::ofstream(p) << yaml;
  return p;
}

const char* kStages = R"(stages:
  - {name: shear, type: undrained_shear, strain_rate_dimensionless: 1.0e-5, stop: {axial_strain: 0.01}}
output: {interval: 20, progress_seconds: 100}
)";

std::string list_scene(const std::string& material, double ct) {
  return "material: {" + material + "}\n"
         "particles:\n  list:\n"
         "    - {id: 0, radius: 1.0e-3, position: [0.002, 0.005, 0.005]}\n"
         "    - {id: 1, radius: 1.0e-3, position: [0.008, 0.005, 0.005]}\n"
         "cell: {lengths: [0.012, 0.012, 0.012]}\n"
         "time_step_ratio: " + std::to_string(ct) + "\n" + kStages;
}

/// A dense scene: 6 x 6 x 6 simple cubic lattice of 1 mm spheres with 1 %
/// overlap and a small random velocity, as an explicit particle list.
std::string dense_lattice_particles() {
  const int n = 6;
  const double r = 1e-3, a = 2 * r * (1 - 0.01);
  std::string y = "particles:\n  list:\n";
  vt::dem::RandomStream rng(5);
  int id = 0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i, ++id) {
        char line[256];
        std::snprintf(line, sizeof line,
                      "    - {id: %d, radius: 1.0e-3, position: [%.9e, %.9e, %.9e], velocity: [%.6e, %.6e, %.6e]}\n", id,
                      (i + 0.5) * a, (j + 0.5) * a, (k + 0.5) * a, 1e-3 * rng.uniform(-1, 1), 1e-3 * rng.uniform(-1, 1),
                      1e-3 * rng.uniform(-1, 1));
        y += line;
      }
  char cell[128];
  std::snprintf(cell, sizeof cell, "cell: {lengths: [%.9e, %.9e, %.9e]}\n", n * a, n * a, n * a);
  return y + cell;
}

}  // namespace

// The limits of io/run_limits.h refuse before the run starts, naming the
// field: the table tests/data/run_limits_cases.yaml, which test_protocol_rig
// feeds to the rig too. --check refuses the same files with the same line.
TEST(TriaxRunCli, RunLimitsRefuseBeforeTheRunNamingTheField) {
  const std::string data = std::string(VT_SOURCE_DIR) + "/tests/data";
  const auto cases = vt::test::run_limits_cases(data, data + "/sample_200_100kPa.h5");
  ASSERT_GE(cases.size(), 5u);
  for (const auto& c : cases) {
    const fs::path out = tmpdir() / ("limits_" + c.name + ".h5");
    fs::remove(out);
    const std::string scene = write_scene("limits_" + c.name + ".yaml", c.yaml).string();
    const CliRun r = triax_run(scene + " --out " + out.string());
    EXPECT_EQ(r.code, 2) << c.name << ": " << r.err;
    EXPECT_EQ(r.err.rfind("triax_run: error: " + c.message, 0), 0u) << c.name << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << c.name << ": one-line error: " << r.err;
    EXPECT_FALSE(fs::exists(out)) << c.name << ": refused, yet it ran";
    const CliRun check = triax_run(scene + " --check");
    EXPECT_EQ(check.code, 2) << c.name << ": --check accepted it";
    EXPECT_EQ(check.err, r.err) << c.name << ": --check and the run refuse alike";
  }
}

// A blow-up before the first sample still leaves a last good state: the initial one.
TEST(TriaxRunCli, FailureBeforeTheFirstSampleSavesTheInitialStateAsLastGood) {
  const std::string yaml = dense_lattice_particles() + "time_step_ratio: 8.0\n" +
                           "stages:\n  - {name: shear, type: undrained_shear, strain_rate_dimensionless: 1.0e-5, "
                           "stop: {axial_strain: 0.3}}\noutput: {interval: 1000000, progress_seconds: 100}\n";
  const fs::path out = tmpdir() / "early.h5";
  const CliRun r = triax_run(write_scene("early.yaml", yaml).string() + " --out " + out.string());
  ASSERT_EQ(r.code, 3) << r.err;
  const auto series = vt::io::read_results_series(out.string());
  ASSERT_LE(series.size(), 1u) << "no sample tick before the blow-up";
  if (!series.empty()) {
    EXPECT_EQ(series.front().step, 0) << "only the initial state";
  }
  ASSERT_TRUE(fs::exists(out.string() + ".last_good.h5")) << r.err;
  const vt::dem::SimulationState s = vt::io::read_sample(out.string() + ".last_good.h5");
  EXPECT_EQ(s.particles.size(), 216u);
  for (std::size_t i = 0; i < s.particles.size(); ++i)
    ASSERT_TRUE(std::isfinite(vt::dem::norm(s.particles.velocity[i]))) << "the initial state is finite";
}

TEST(TriaxRunCli, BadInputExitsWithCode2AndNamesTheField) {
  struct Case {
    std::string name, yaml, field;
  } cases[] = {
      {"negative_radius", std::string(list_scene("", 0.3)).replace(list_scene("", 0.3).find("radius: 1.0e-3"), 14, "radius: -1.0e-3"),
       "particles.list[0].radius"},
      {"nu_half", list_scene("poisson_ratio: 0.5", 0.3), "material.poisson_ratio"},
      {"ct_zero", list_scene("", 0.0), "time_step_ratio"},
      {"unknown_key", list_scene("colour: 3", 0.3), "material.colour"},
  };
  for (const Case& c : cases) {
    const CliRun r = triax_run(write_scene(c.name + ".yaml", c.yaml).string() + " --out " + (tmpdir() / "x.h5").string());
    EXPECT_EQ(r.code, 2) << c.name << ": " << r.err;
    EXPECT_NE(r.err.find(c.field), std::string::npos) << c.name << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one-line error: " << r.err;
  }
  const CliRun missing = triax_run((tmpdir() / "no_such_scene.yaml").string());
  EXPECT_EQ(missing.code, 2);
  EXPECT_NE(missing.err.find("no_such_scene.yaml"), std::string::npos) << missing.err;
}

TEST(TriaxRunCli, CheckValidatesWithoutRunning) {
  // --check: a valid file exits 0 and writes no results; a bad one exits 2
  // with the same one-line error naming the field.
  const fs::path out = tmpdir() / "check_only.h5";
  const CliRun ok = triax_run(write_scene("check_ok.yaml", list_scene("", 0.3)).string() + " --check --out " + out.string());
  EXPECT_EQ(ok.code, 0) << ok.err;
  EXPECT_FALSE(fs::exists(out));
  const CliRun bad = triax_run(write_scene("check_bad.yaml", list_scene("colour: 3", 0.3)).string() + " --check");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("material.colour"), std::string::npos) << bad.err;
  EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
}

TEST(TriaxRunCli, TimeStepRatioAboveOneRunsWithAWarning) {
  const CliRun r = triax_run(write_scene("ct_high.yaml", list_scene("", 1.2)).string() + " --out " +
                          (tmpdir() / "ct_high.h5").string());
  EXPECT_NE(r.err.find("warning"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("critical"), std::string::npos) << r.err;
  EXPECT_EQ(r.code, 0) << r.err;  // two separated spheres: nothing to blow up
  EXPECT_NE(r.out.find("\"verdict\":\"completed\""), std::string::npos) << r.out;
}

TEST(TriaxRunCli, BlowUpIsDetectedAndHistoryKept) {
  const std::string particles = dense_lattice_particles();
  struct Case {
    std::string name, knobs;
  } cases[] = {{"large_ct", "time_step_ratio: 8.0\n"}};  // within the limit (io/run_limits.h), far above 1
  for (const Case& c : cases) {
    const std::string rate = "1.0e-5";
    const std::string yaml = particles + c.knobs +
                             "stages:\n  - {name: shear, type: undrained_shear, strain_rate_dimensionless: " + rate +
                             ", stop: {axial_strain: 0.3}}\noutput: {interval: 20, progress_seconds: 100}\n";
    const fs::path out = tmpdir() / (c.name + ".h5");
    const CliRun r = triax_run(write_scene(c.name + ".yaml", yaml).string() + " --out " + out.string());
    EXPECT_EQ(r.code, 3) << c.name << ": " << r.err;
    EXPECT_NE(r.out.find("\"verdict\":\"unstable\""), std::string::npos) << r.out;
    // The results keep the history up to the last good output, all finite.
    const std::vector<Measures> series = vt::io::read_results_series(out.string());
    ASSERT_GE(series.size(), 1u) << c.name;
    for (const Measures& m : series) EXPECT_TRUE(std::isfinite(m.p) && std::isfinite(m.energy.kinetic())) << c.name;
    // Detected within a few hundred steps.
    const std::int64_t first_step = series.front().step;
    EXPECT_LT(series.back().step - first_step, 400) << c.name;
    EXPECT_TRUE(fs::exists(out.string() + ".last_good.h5")) << c.name;
  }
}

TEST(TriaxRunCli, GovernorLogHasOneRowPerBlockOfTheRun) {
  // --governor-log: with --threads auto, one CSV row per block of the thread
  // governor (io/governor_log.h); with a fixed count it is refused
  const std::string sample = (fs::path(VT_SOURCE_DIR) / "config/samples/dense_4000.h5").string();
  const fs::path scene = write_scene("governed.yaml",
                                     "particles: {sample_file: " + sample + "}\n"
                                     "time_step_basis: contacts\n"
                                     "stages:\n  - {name: shear, type: drained_shear, confining_pressure: 100.0e3, "
                                     "strain_rate_dimensionless: 1.0e-5, stop: {axial_strain: 0.006}}\n"
                                     "output: {interval: 100, progress_seconds: 100}\n");
  const fs::path log = tmpdir() / "governor.csv";
  const CliRun fixed = triax_run(scene.string() + " --threads 2 --governor-log " + log.string());
  EXPECT_EQ(fixed.code, 2);
  EXPECT_NE(fixed.err.find("--governor-log"), std::string::npos) << fixed.err;
  EXPECT_FALSE(fs::exists(log));

  const CliRun r = vt::test::run_program(
      "triax_run", scene.string() + " --out " + (tmpdir() / "governed.h5").string() + " --governor-log " + log.string(),
      tmpdir(), "OMP_NUM_THREADS=2");
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream in(slurp(log));
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line, "end_step,threads,kind,timed_steps,untimed_steps,us_per_step,cost_one_us,cost_max_us,next");
  struct Row {
    long end, threads, timed, untimed, next;
    std::string kind;
    double us;
  };
  std::vector<Row> rows;
  while (std::getline(in, line)) {
    std::istringstream f(line);
    std::string c[9];
    for (std::string& x : c) std::getline(f, x, ',');
    rows.push_back({std::stol(c[0]), std::stol(c[1]), std::stol(c[3]), std::stol(c[4]), std::stol(c[8]), c[2],
                    std::stod(c[5])});
  }
  // 4000 particles: 8 chunks, two threads useful; blocks of >= 20 steps
  ASSERT_GE(rows.size(), 3u) << slurp(log);
  EXPECT_EQ(rows[0].kind, "start");
  EXPECT_EQ(rows[0].threads, 2);
  EXPECT_EQ(rows[0].end, rows[0].untimed);
  long one = 0;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    EXPECT_TRUE(rows[k].kind == (k == 0 ? "start" : "run") || (k > 0 && rows[k].kind == "probe")) << rows[k].kind;
    EXPECT_GT(rows[k].us, 0.0);
    EXPECT_GE(rows[k].timed + rows[k].untimed, 20);
    if (rows[k].threads == 1) one += rows[k].timed + rows[k].untimed;
    if (k == 0) continue;
    EXPECT_EQ(rows[k].threads, rows[k - 1].next) << "row " << k;
    EXPECT_EQ(rows[k].end - rows[k - 1].end, rows[k].timed + rows[k].untimed) << "row " << k;
  }
  // the run's own count of steps on one thread includes the unfinished last block
  long said_one = -1, said_max = -1;
  const std::size_t at = r.err.find("threads chosen at run time: ");
  ASSERT_NE(at, std::string::npos) << r.err;
  ASSERT_EQ(std::sscanf(r.err.c_str() + at, "threads chosen at run time: %ld steps on 1, %ld on 2", &said_one, &said_max), 2);
  EXPECT_GE(said_one, one);
  EXPECT_GE(said_one + said_max, rows.back().end);
  // every step of the run is counted on one count or the other
  const std::size_t steps_at = r.out.rfind("\"steps\":");
  ASSERT_NE(steps_at, std::string::npos) << r.out;
  EXPECT_EQ(said_one + said_max, std::stol(r.out.substr(steps_at + 8)));
}
