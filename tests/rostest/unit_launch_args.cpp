// protocol_rig.launch with a wrong argument: the node that takes it stops at
// start with one line naming the argument (its parameter: the same name,
// servo_X -> /servo ~X) and what it takes, also in the nodelet rig (where
// the manager itself only says "Failed to load nodelet"). Each launch runs
// on a master port of its own until the FATAL lines are there.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <set>
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

/// Parent pid of a process (0 if gone).
int parent_of(int pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!std::getline(in, line)) return 0;
  std::istringstream rest(line.substr(line.rfind(')') + 2));
  char state;
  int ppid = 0;
  rest >> state >> ppid;
  return ppid;
}

/// `root` and every process below it.
std::set<int> descendants(int root) {
  std::set<int> out{root};
  for (bool grew = true; grew;) {
    grew = false;
    for (const auto& e : fs::directory_iterator("/proc")) {
      const std::string name = e.path().filename().string();
      if (name.find_first_not_of("0123456789") != std::string::npos) continue;
      const int pid = std::stoi(name);
      if (!out.count(pid) && out.count(parent_of(pid))) grew = out.insert(pid).second;
    }
  }
  return out;
}

/// roslaunch protocol_rig.launch with ARGS in the background, on a master
/// port of its own; its log says what the nodes said.
class Launch {
 public:
  Launch(const std::string& args, int port) : args_(args) {
    dir_ = fs::temp_directory_path() / ("vt_launch_args_" + std::to_string(::getpid()) + "_" + std::to_string(port));
    fs::create_directories(dir_);
    log_ = dir_ / "launch.log";
    const std::string cmd = "set +u; source '" VT_PROGRAM_DIR "/../../setup.bash' && export ROS_MASTER_URI=http://127.0.0.1:" +
                            std::to_string(port) + " ROS_IP=127.0.0.1 ROS_HOME='" + dir_.string() +
                            "' && exec roslaunch virtual_triaxial protocol_rig.launch " + args + " > '" + log_.string() +
                            "' 2>&1";
    pid_ = ::fork();
    if (pid_ == 0) {
      ::setpgid(0, 0);
      ::execl("/bin/bash", "bash", "-c", cmd.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
  }
  ~Launch() {
    // roslaunch stops its nodes on SIGINT; whatever is left (a slow stop on
    // a busy machine) is killed, found as descendants before the stop.
    const std::set<int> tree = descendants(pid_);
    ::kill(-pid_, SIGINT);
    for (int i = 0; i < 300 && ::waitpid(pid_, nullptr, WNOHANG) == 0; ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    for (int p : tree) ::kill(p, SIGKILL);
    ::kill(-pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
    // the master roslaunch started detaches from it: found by its log path
    for (const auto& e : fs::directory_iterator("/proc")) {
      const std::string name = e.path().filename().string();
      if (name.find_first_not_of("0123456789") != std::string::npos) continue;
      std::string cmd = slurp(e.path() / "cmdline");
      if (cmd.find(dir_.string() + "/") != std::string::npos) ::kill(std::stoi(name), SIGKILL);
    }
    fs::remove_all(dir_);
  }
  /// The FATAL line of `node` ("" when none yet).
  std::string fatal(const std::string& node) const {
    std::istringstream in(slurp(log_));
    for (std::string line; std::getline(in, line);)
      if (line.find("[FATAL]") != std::string::npos && line.find(" " + node + ": ") != std::string::npos) return line;
    return "";
  }
  std::string log() const { return args_ + ":\n" + slurp(log_); }

 private:
  std::string args_;
  fs::path dir_, log_;
  pid_t pid_ = -1;
};

}  // namespace

// Two launches side by side (a roslaunch start takes seconds): the nodelet
// rig with two wrong arguments (dem_node's and the servo's) and the
// three-process rig with a third.
TEST(LaunchArgs, AWrongArgumentIsNamedWithWhatItTakes) {
  const int port = 21000 + static_cast<int>(::getpid() % 2000);
  const struct {
    int launch;
    std::string node, message;
  } cases[] = {
      {0, "dem_node", "~publish_every: must be a whole number"},
      {0, "servo", "unknown servo strategy 'foo' (known: proportional, pid)"},
      {1, "dem_node", "~max_dimensionless_rate: must be > 0 and at most the run limit 0.001"},
  };
  Launch launches[] = {Launch("publish_every:=abc servo_strategy:=foo", port),
                       Launch("nodelets:=false max_dimensionless_rate:=0.01", port + 1)};
  std::string lines[3];
  const auto t0 = Clock::now();
  while (std::chrono::duration<double>(Clock::now() - t0).count() < 120.0) {
    bool all = true;
    for (int i = 0; i < 3; ++i) {
      if (lines[i].empty()) lines[i] = launches[cases[i].launch].fatal(cases[i].node);
      all = all && !lines[i].empty();
    }
    if (all) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  for (int i = 0; i < 3; ++i) {
    ASSERT_FALSE(lines[i].empty()) << cases[i].node << " said nothing fatal; " << launches[cases[i].launch].log();
    EXPECT_NE(lines[i].find(cases[i].message), std::string::npos) << lines[i];
  }
}
