// run_triaxial.sh driven from a test (tests/rostest/unit_rig_*.cpp): one run
// in the background, in a process group of its own, with the helpers to find
// its processes, wait for its stages and its exit, and clean up after it
// whatever happened (nothing it started survives the test).
#pragma once

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace vt::test {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;


inline std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/// Parent pid of a process (0 if gone).
inline int parent_of(int pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!std::getline(in, line)) return 0;
  const auto close = line.rfind(')');
  std::istringstream rest(line.substr(close + 2));
  char state;
  int ppid = 0;
  rest >> state >> ppid;
  return ppid;
}

inline std::string cmdline_of(int pid) {
  std::string s = slurp("/proc/" + std::to_string(pid) + "/cmdline");
  for (char& c : s)
    if (c == '\0') c = ' ';
  return s;
}

/// `root` and every process below it.
inline std::set<int> descendants(int root) {
  std::set<int> out{root};
  bool grew = true;
  while (grew) {
    grew = false;
    for (const auto& e : fs::directory_iterator("/proc")) {
      const std::string name = e.path().filename().string();
      if (name.find_first_not_of("0123456789") != std::string::npos) continue;
      const int pid = std::stoi(name);
      if (!out.count(pid) && out.count(parent_of(pid))) {
        out.insert(pid);
        grew = true;
      }
    }
  }
  return out;
}

inline bool alive(int pid) { return ::kill(pid, 0) == 0 && slurp("/proc/" + std::to_string(pid) + "/stat").find(") Z") == std::string::npos; }

/// One run of run_triaxial.sh in the background, in a process group of its
/// own (so that the test can always clean up after it).
class ScriptRun {
 public:
  /// `args`: the script's arguments (a protocol, or --resume DIR); the
  /// output folder is a fresh temporary one named after `tag` (a resume
  /// writes into the folder it names; `out()` is then unused).
  ScriptRun(const std::string& tag, const std::string& env,
            const std::string& args = "tests/data/protocols/rig_faults.yaml") {
    out_ = fs::temp_directory_path() / ("vt_rig_" + tag + "_" + std::to_string(::getpid()));
    fs::remove_all(out_);
    log_ = out_.string() + ".log";
    // The suite has built everything: no build check in each run.
    const std::string cmd = "cd '" VT_SOURCE_DIR "' && VT_SKIP_BUILD=1 OUT='" + out_.string() + "' " + env +
                            " exec launch_equiv_scripts/run_triaxial.sh " + args + " > '" + log_.string() + "' 2>&1";
    pid_ = ::fork();
    if (pid_ == 0) {
      ::setpgid(0, 0);
      ::execl("/bin/bash", "bash", "-c", cmd.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
  }
  ~ScriptRun() {
    // Whatever happened: nothing started here survives the test.
    for (int p : descendants(pid_)) ::kill(p, SIGKILL);
    for (int p : seen_) ::kill(p, SIGKILL);
    if (code_ == kRunning) ::waitpid(pid_, nullptr, 0);
  }
  /// Waits until the log shows the shear stage running; false after `seconds`.
  bool wait_for_shear(double seconds) { return wait_for_log("[shear] eps_a", seconds); }
  /// Waits until the log holds `needle` (then notes the processes); false after `seconds`.
  bool wait_for_log(const std::string& needle, double seconds) {
    const auto t0 = Clock::now();
    while (seconds_since(t0) < seconds) {
      if (slurp(log_).find(needle) != std::string::npos) {
        seen_ = descendants(pid_);
        return true;
      }
      if (exited()) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    return false;
  }
  /// Seconds until the script exits, or -1 after `limit` seconds; also
  /// notes when summary.json got its verdict (verdict_seconds()): while the
  /// test runs it is the protocol node's partial summary, written at every
  /// results flush in compact JSON with "partial":true; the verdict replaces
  /// it (the protocol node's final summary has no "partial", the script's
  /// merge after a death writes Python's "partial": true).
  double wait_exit(double limit) {
    const auto t0 = Clock::now();
    verdict_seconds_ = -1;
    while (seconds_since(t0) < limit) {
      if (verdict_seconds_ < 0 && fs::exists(out_ / "summary.json") &&
          slurp(out_ / "summary.json").find("\"partial\":true") == std::string::npos)
        verdict_seconds_ = seconds_since(t0);
      if (exited()) return seconds_since(t0);
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return -1;
  }
  double verdict_seconds() const { return verdict_seconds_; }
  bool exited() {
    if (code_ != kRunning) return true;
    int status = 0;
    if (::waitpid(pid_, &status, WNOHANG) != pid_) return false;
    code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return true;
  }
  /// A process of the rig whose command line holds `needle` (0: none).
  int find(const std::string& needle) const {
    for (int p : descendants(pid_))
      if (cmdline_of(p).find(needle) != std::string::npos) return p;
    return 0;
  }
  /// Processes seen at the fault that still run.
  std::vector<int> left_behind() const {
    std::vector<int> left;
    for (int p : seen_)
      if (p != pid_ && alive(p)) left.push_back(p);
    return left;
  }
  /// Removes the output folder and the log (a passed test keeps nothing).
  void remove_outputs() const {
    std::error_code ec;
    fs::remove_all(out_, ec);
    fs::remove(log_, ec);
  }
  int pid() const { return pid_; }
  int code() const { return code_; }
  const fs::path& out() const { return out_; }
  std::string log() const { return slurp(log_); }
  const std::set<int>& seen() const { return seen_; }

 private:
  static constexpr int kRunning = -1000;
  fs::path out_, log_;
  int pid_ = -1;
  int code_ = kRunning;
  double verdict_seconds_ = -1;
  std::set<int> seen_;
};

/// stdout of a shell command.
inline std::string run(const std::string& cmd) {
  std::string out;
  FILE* f = ::popen(cmd.c_str(), "r");
  if (!f) return out;
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) out.append(buf, n);
  ::pclose(f);
  return out;
}

}  // namespace vt::test
