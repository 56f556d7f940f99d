// triax_run on a full disk: a 256 KiB tmpfs mounted in a private mount
// namespace (`unshare -m` as root, `unshare -rm` otherwise; the mount
// vanishes with the namespace). Asserts:
//   - a first run fills in results.h5 on it (exit 0);
//   - with the disk then full, the same run exits 6 with one error line
//     naming the file and "No space left on device", never a crash, and
//     the results.h5 of the first run is still there byte for byte (atomic
//     replacement), readable, with no temporary file left behind;
//   - --save-sample onto the full disk: exit 6, and the results written
//     before it (on a disk with space) are complete and readable.
// If no tmpfs can be mounted the test FAILS (it is never skipped).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "support/cli.h"
#include "virtual_triaxial/io/results_file.h"

namespace fs = std::filesystem;

namespace {

using vt::test::slurp;

const char* kScene = R"(material: {}
particles:
  list:
    - {id: 0, radius: 1.0e-3, position: [0.002, 0.005, 0.005]}
    - {id: 1, radius: 1.0e-3, position: [0.008, 0.005, 0.005]}
cell: {lengths: [0.012, 0.012, 0.012]}
time_step_ratio: 0.3
stages:
  - {name: shear, type: undrained_shear, strain_rate_dimensionless: 1.0e-5, stop: {axial_strain: 0.01}}
output: {interval: 20, progress_seconds: 100}
)";

std::string trim(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  return s;
}

TEST(FullDisk, TriaxRunStopsWithExitCode6AndKeepsEarlierOutputs) {
  const fs::path dir = vt::test::scratch_dir("full_disk");
  const fs::path scene = dir / "scene.yaml";
  std::ofstream(scene) << kScene;
  const fs::path disk = dir / "disk";
  fs::create_directories(disk);
  const std::string exe = VT_BINARY_DIR "/devel/lib/virtual_triaxial/triax_run";
  const std::string d = dir.string(), m = disk.string();
  const std::string script =
      "set -u\n"
      "mount -t tmpfs -o size=256k tmpfs '" + m + "' 2> '" + d + "/mount.err' || exit 90\n"
      "run() { local tag=$1; shift; '" + exe + "' '" + scene.string() + "' --quiet \"$@\" > '" + d +
      "'/$tag.out 2> '" + d + "'/$tag.err; echo $? > '" + d + "'/$tag.code; }\n"
      "run first --out '" + m + "/results.h5'\n"
      "cp '" + m + "/results.h5' '" + d + "/first.h5'\n"
      "head -c 4M /dev/zero > '" + m + "/filler' 2>/dev/null\n"
      "run full --out '" + m + "/results.h5'\n"
      "cmp -s '" + m + "/results.h5' '" + d + "/first.h5'; echo $? > '" + d + "/same.code'\n"
      "ls -a '" + m + "' > '" + d + "/listing'\n"
      "run sample --out '" + d + "/third.h5' --save-sample '" + m + "/final.h5'\n";
  std::ofstream(dir / "full_disk.sh") << script;
  const std::string ns = ::geteuid() == 0 ? "unshare -m" : "unshare -rm";
  const int status = std::system((ns + " /bin/bash '" + (dir / "full_disk.sh").string() + "'").c_str());
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  ASSERT_NE(code, 90) << "cannot mount a tmpfs in a private mount namespace (" << ns
                      << "): " << slurp(dir / "mount.err") << "; this test needs it and is not skipped";
  ASSERT_EQ(code, 0) << "the " << ns << " shell failed";

  ASSERT_EQ(trim(slurp(dir / "first.code")), "0") << slurp(dir / "first.err");
  // The full disk: exit 6, one line naming the file and the reason.
  EXPECT_EQ(trim(slurp(dir / "full.code")), "6") << slurp(dir / "full.err");
  const std::string err = slurp(dir / "full.err");
  const std::string line = "triax_run: output: " + m + "/results.h5: cannot write";
  EXPECT_NE(err.find(line), std::string::npos) << err;
  EXPECT_NE(err.find("No space left on device"), std::string::npos) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 2) << "the banner line and one error line:\n" << err;
  // The earlier output is intact, byte for byte, and readable; no temporary file left.
  EXPECT_EQ(trim(slurp(dir / "same.code")), "0") << "results.h5 of the first run was changed";
  EXPECT_FALSE(vt::io::read_results_series((dir / "first.h5").string()).empty());
  const std::string listing = slurp(dir / "listing");
  EXPECT_EQ(listing.find(".tmp."), std::string::npos) << listing;
  // --save-sample on the full disk: exit 6; the results before it are complete.
  EXPECT_EQ(trim(slurp(dir / "sample.code")), "6") << slurp(dir / "sample.err");
  EXPECT_NE(slurp(dir / "sample.err").find("final.h5: cannot write"), std::string::npos) << slurp(dir / "sample.err");
  const auto series = vt::io::read_results_series((dir / "third.h5").string());
  ASSERT_FALSE(series.empty());
  EXPECT_GE(series.back().strain[2], 0.01 * (1 - 1e-9)) << "the run's results end at its stop criterion";
}

}  // namespace
