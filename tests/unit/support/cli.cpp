#include "support/cli.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <system_error>
#include <vector>

namespace vt::test {

namespace {
/// The scratch directories of this test program, removed when it exits
/// (kept with VT_KEEP_SCRATCH=1 to look at a failure).
struct ScratchDirs {
  std::vector<std::filesystem::path> dirs;
  ~ScratchDirs() {
    if (std::getenv("VT_KEEP_SCRATCH") != nullptr) return;
    for (const auto& d : dirs) {
      std::error_code ec;
      std::filesystem::remove_all(d, ec);
    }
  }
};
}  // namespace

std::filesystem::path scratch_dir(const std::string& tag) {
  static ScratchDirs made;
  const auto p = std::filesystem::temp_directory_path() / ("vt_" + tag + "_" + std::to_string(::getpid()));
  std::filesystem::create_directories(p);
  made.dirs.push_back(p);
  return p;
}

std::string slurp(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

CliRun run_program(const std::string& program, const std::string& args, const std::filesystem::path& scratch,
                   const std::string& env) {
  const auto exe = std::filesystem::path(VT_BINARY_DIR) / "devel/lib/virtual_triaxial" / program;
  const auto o = scratch / "stdout.txt", e = scratch / "stderr.txt";
  const std::string cmd = (env.empty() ? "" : env + " ") + "exec " + exe.string() + " " + args + " >" + o.string() +
                          " 2>" + e.string();
  const int st = std::system(cmd.c_str());
  return {WIFEXITED(st) ? WEXITSTATUS(st) : -1, slurp(o), slurp(e)};
}

}  // namespace vt::test
