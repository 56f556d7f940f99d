// protocol_rig.launch with a wrong argument: the node that takes it stops at
// start with one line naming the argument (its parameter: the same name,
// servo_X -> /servo ~X) and what it takes, also in the nodelet rig (where
// the manager itself only says "Failed to load nodelet"). Each case starts
// roslaunch on a master port of its own, waits for the FATAL line and stops
// the launch.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include <gtest/gtest.h>

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The first line of `log` holding `what` ("" when none).
std::string line_with(const std::string& log, const std::string& what) {
  const std::size_t at = log.find(what);
  if (at == std::string::npos) return "";
  const std::size_t b = log.rfind('\n', at), e = log.find('\n', at);
  return log.substr(b == std::string::npos ? 0 : b + 1, e == std::string::npos ? std::string::npos : e - b - 1);
}

/// roslaunch protocol_rig.launch ARGS until its log names `node` in a FATAL
/// line (or 60 s); returns that line.
std::string fatal_line(const std::string& args, const std::string& node, int port) {
  const fs::path dir = fs::temp_directory_path() / ("vt_launch_args_" + std::to_string(::getpid()) + "_" +
                                                    std::to_string(port));
  fs::create_directories(dir);
  const fs::path log = dir / "launch.log";
  const std::string cmd = "set +u; source '" VT_PROGRAM_DIR "/../../setup.bash' && export ROS_MASTER_URI=http://127.0.0.1:" +
                          std::to_string(port) + " ROS_IP=127.0.0.1 ROS_HOME='" + dir.string() +
                          "' && exec roslaunch virtual_triaxial protocol_rig.launch " + args + " > '" + log.string() +
                          "' 2>&1";
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::setpgid(0, 0);
    ::execl("/bin/bash", "bash", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  std::string line;
  const auto t0 = Clock::now();
  while (std::chrono::duration<double>(Clock::now() - t0).count() < 60.0) {
    line = line_with(slurp(log), "[FATAL]");
    if (!line.empty() && line.find(node + ":") != std::string::npos) break;
    if (::waitpid(pid, nullptr, WNOHANG) == pid) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  ::kill(-pid, SIGINT);
  for (int i = 0; i < 100 && ::waitpid(pid, nullptr, WNOHANG) == 0; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ::kill(-pid, SIGKILL);
  ::waitpid(pid, nullptr, WNOHANG);
  if (line.empty()) ADD_FAILURE() << args << ": no FATAL line; log:\n" << slurp(log);
  fs::remove_all(dir);
  return line;
}

int free_port(int base) { return base + static_cast<int>(::getpid() % 2000); }

}  // namespace

TEST(LaunchArgs, AWrongArgumentIsNamedWithWhatItTakes) {
  const struct {
    std::string args, node, message;
  } cases[] = {
      {"publish_every:=abc", "dem_node", "~publish_every: must be a whole number"},
      {"max_dimensionless_rate:=0.01", "dem_node",
       "~max_dimensionless_rate: must be > 0 and at most the run limit 0.001"},
      {"servo_strategy:=foo", "servo", "unknown servo strategy 'foo' (known: proportional, pid)"},
      {"nodelets:=false lockstep_timeout:=soon", "dem_node", "~lockstep_timeout: must be a number"},
  };
  int port = free_port(21000);
  for (const auto& c : cases) {
    const std::string line = fatal_line(c.args, c.node, port++);
    EXPECT_NE(line.find(c.node + ": "), std::string::npos) << c.args << ": " << line;
    EXPECT_NE(line.find(c.message), std::string::npos) << c.args << ": " << line;
  }
}
