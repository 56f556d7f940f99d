#include "support/cli.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <iterator>

namespace vt::test {

std::filesystem::path scratch_dir(const std::string& tag) {
  const auto p = std::filesystem::temp_directory_path() / ("vt_" + tag + "_" + std::to_string(::getpid()));
  std::filesystem::create_directories(p);
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
