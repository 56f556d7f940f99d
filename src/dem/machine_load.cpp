#include "virtual_triaxial/dem/machine_load.h"

#include <algorithm>
#include <array>
#include <fstream>
#include <sstream>

#ifdef __linux__
#include <dirent.h>
#include <sched.h>
#include <unistd.h>
#endif

namespace vt::dem {

std::optional<int> loadavg_running(const std::string& line) {
  std::istringstream in(line);
  std::string l1, l5, l15, counts;  // the averages as text: no locale in the way
  if (!(in >> l1 >> l5 >> l15 >> counts)) return std::nullopt;
  const std::size_t slash = counts.find('/');
  if (slash == 0 || slash == std::string::npos || slash + 1 == counts.size()) return std::nullopt;
  const auto digits = [](const std::string& s) {
    return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  const std::string running = counts.substr(0, slash);
  if (!digits(running) || !digits(counts.substr(slash + 1)) || running.size() > 9) return std::nullopt;
  return std::stoi(running);
}

char task_state(const std::string& stat_line) {
  const std::size_t close = stat_line.rfind(')');
  if (close == std::string::npos || close + 2 >= stat_line.size() || stat_line[close + 1] != ' ') return '\0';
  return stat_line[close + 2];
}

std::optional<int> own_running_threads() {
#ifdef __linux__
  DIR* dir = opendir("/proc/self/task");
  if (dir == nullptr) return std::nullopt;
  int running = 0;
  while (const dirent* e = readdir(dir)) {
    if (e->d_name[0] == '.') continue;
    std::ifstream stat(std::string("/proc/self/task/") + e->d_name + "/stat");
    std::string line;
    // a thread that ended since readdir has no stat: not running
    if (std::getline(stat, line) && task_state(line) == 'R') ++running;
  }
  closedir(dir);
  return running;
#else
  return std::nullopt;
#endif
}

std::optional<int> other_runnable_tasks() {
  // this process's threads first: one that stops running between the two
  // reads (an OpenMP thread ending its spin-wait) is then subtracted though
  // R no longer holds it (others errs low: room); one that starts running
  // between them (a ROS spinner woken) makes others err high by one
  const std::optional<int> own = own_running_threads();
  std::ifstream loadavg("/proc/loadavg");
  std::string line;
  if (!std::getline(loadavg, line)) return std::nullopt;
  const std::optional<int> all = loadavg_running(line);
  if (!all || !own) return std::nullopt;
  return std::max(0, *all - *own);
}

namespace {
constexpr std::size_t kIowait = 4;  // user nice system idle iowait irq softirq steal

/// The first eight counters of an aggregate "cpu " line of /proc/stat.
std::optional<std::array<unsigned long long, 8>> cpu_counters(const std::string& line) {
  std::istringstream in(line);
  std::string label;
  if (!(in >> label) || label != "cpu") return std::nullopt;
  std::array<unsigned long long, 8> c{};
  for (auto& v : c) {
    std::string field;
    if (!(in >> field) || field.empty() || field.size() > 19 ||
        !std::all_of(field.begin(), field.end(), [](char ch) { return ch >= '0' && ch <= '9'; }))
      return std::nullopt;
    v = std::stoull(field);
  }
  return c;
}
}  // namespace

std::optional<double> steal_share(const std::string& stat_before, const std::string& stat_after) {
  const auto b = cpu_counters(stat_before), a = cpu_counters(stat_after);
  if (!b || !a) return std::nullopt;
  unsigned long long total = 0;
  for (std::size_t k = 0; k < 8; ++k) {
    if ((*a)[k] < (*b)[k]) {
      if (k == kIowait) continue;  // iowait may go back (proc(5)): counted as none
      return std::nullopt;         // the others only grow
    }
    total += (*a)[k] - (*b)[k];
  }
  if (total == 0) return std::nullopt;
  return static_cast<double>((*a)[7] - (*b)[7]) / static_cast<double>(total);
}

bool room_for(int threads, int others, int cpus) { return threads > 1 && others <= cpus - 2; }

int checked_cpus() {
#ifdef __linux__
  const long online = sysconf(_SC_NPROCESSORS_ONLN);
  cpu_set_t mask;
  CPU_ZERO(&mask);
  if (online < 1 || sched_getaffinity(0, sizeof(mask), &mask) != 0) return 0;
  return CPU_COUNT(&mask) < online ? 0 : static_cast<int>(online);
#else
  return 0;
#endif
}

ThreadGovernor governor_on_this_machine(int max_threads) {
  ThreadGovernor g(max_threads);
  g.set_room_check([](int threads) {
    const int cpus = checked_cpus();
    if (cpus == 0) return true;
    const std::optional<int> others = other_runnable_tasks();
    return !others || room_for(threads, *others, cpus);
  });
  return g;
}

}  // namespace vt::dem
