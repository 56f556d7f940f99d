// Running the built command-line programs from tests.
#pragma once

#include <filesystem>
#include <string>

namespace vt::test {

struct CliRun {
  int code = -1;        ///< exit code, -1 if the program did not exit normally
  std::string out, err; ///< captured stdout and stderr
};

/// A per-process scratch directory under the system temp dir.
std::filesystem::path scratch_dir(const std::string& tag);
std::string slurp(const std::filesystem::path& p);
/// Run build/devel/lib/virtual_triaxial/<program> with the given arguments.
/// `env`: VAR=value words put before the program (e.g. a test hook).
CliRun run_program(const std::string& program, const std::string& args, const std::filesystem::path& scratch,
                   const std::string& env = "");

}  // namespace vt::test
