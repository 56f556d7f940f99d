// DemDiagnostics: /diagnostics report of dem_node. See dem_diagnostics.h.
#include "virtual_triaxial/ros/dem_diagnostics.h"

#include <algorithm>
#include <sstream>

#include <diagnostic_msgs/DiagnosticStatus.h>
#include <diagnostic_msgs/KeyValue.h>

namespace vt::ros {

namespace {

diagnostic_msgs::KeyValue kv(const std::string& key, const std::string& value) {
  diagnostic_msgs::KeyValue k;
  k.key = key;
  k.value = value;
  return k;
}

template <class T>
std::string str(T v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

}  // namespace

void DemDiagnostics::count_timeout(const std::string& owner) {
  ++timeouts_;
  ++timeouts_by_owner_[owner];
}

void DemDiagnostics::count_rejected(const std::string& reason) {
  ++rejected_;
  last_rejection_ = reason;
}

void DemDiagnostics::add_tick(double stepping, double publishing, double waiting) {
  for (TickTimes* t : {&since_report_, &since_start_}) {
    t->wall[0] += stepping;
    t->wall[1] += publishing;
    t->wall[2] += waiting;
    ++t->ticks;
  }
}

std::string DemDiagnostics::tick_summary() const {
  const TickTimes& t = since_start_;
  const double n = static_cast<double>(std::max<std::uint64_t>(t.ticks, 1));
  std::ostringstream s;
  s.precision(4);
  s << t.ticks << " control ticks; wall per tick: DEM steps " << 1e3 * t.wall[0] / n << " ms, measures + messages "
    << 1e3 * t.wall[1] / n << " ms, lockstep wait " << 1e3 * t.wall[2] / n << " ms";
  return s.str();
}

diagnostic_msgs::DiagnosticArray DemDiagnostics::report(const DemStatus& s, ::ros::WallTime now) {
  diagnostic_msgs::DiagnosticStatus st;
  st.name = s.name;
  st.hardware_id = "virtual_triaxial DEM cell";
  const double ct = s.t0 > 0 ? s.dt / s.t0 : 0.0;
  double rtf = 0.0;
  if (last_time_ >= 0.0) {
    const double wall = (now - last_wall_).toSec();
    if (wall > 0) rtf = (s.time - last_time_) / wall;
  }
  last_time_ = s.time;
  last_wall_ = now;

  const bool new_timeouts = timeouts_ > timeouts_reported_;
  const bool new_rejections = rejected_ > rejected_reported_;
  std::ostringstream msg;
  if (s.unstable) {
    st.level = diagnostic_msgs::DiagnosticStatus::ERROR;
    msg << "numerical failure, stepping stopped: " << s.failure;
  } else if (ct >= 1.0 || new_timeouts || new_rejections) {
    st.level = diagnostic_msgs::DiagnosticStatus::WARN;
    if (ct >= 1.0) msg << "time step at or above the critical estimate (c_t = " << ct << "); ";
    if (new_timeouts) msg << (timeouts_ - timeouts_reported_) << " lockstep timeout(s), last command held; ";
    if (new_rejections) msg << (rejected_ - rejected_reported_) << " cell command(s) refused; ";
  } else {
    st.level = diagnostic_msgs::DiagnosticStatus::OK;
    msg << (s.paused ? "paused" : "running");
  }
  st.message = msg.str();
  timeouts_reported_ = timeouts_;
  rejected_reported_ = rejected_;

  st.values.push_back(kv("T0 [s]", str(s.t0)));
  st.values.push_back(kv("dt [s]", str(s.dt)));
  st.values.push_back(kv("dt / T0 (c_t)", str(ct)));
  st.values.push_back(kv("real-time factor", str(rtf)));
  st.values.push_back(kv("simulation time [s]", str(s.time)));
  st.values.push_back(kv("tick", str(s.tick)));
  st.values.push_back(kv("step", str(s.step)));
  st.values.push_back(kv("particles", str(s.particles)));
  st.values.push_back(kv("mode", s.lockstep ? "lockstep" : "free-running"));
  st.values.push_back(kv("paused", s.paused ? "true" : "false"));
  st.values.push_back(kv("unstable", s.unstable ? "true" : "false"));
  if (s.unstable) st.values.push_back(kv("failure", s.failure));
  st.values.push_back(kv("lockstep timeouts", str(timeouts_)));
  for (const auto& [owner, n] : timeouts_by_owner_) st.values.push_back(kv("lockstep timeouts: " + owner, str(n)));
  st.values.push_back(kv("refused cell commands", str(rejected_)));
  if (!last_rejection_.empty()) st.values.push_back(kv("last refused command", last_rejection_));
  const char* part[3] = {"DEM steps", "measures + messages", "lockstep wait"};
  for (const auto& [label, t] : {std::pair<const char*, const TickTimes&>{"recent", since_report_},
                                 std::pair<const char*, const TickTimes&>{"since start", since_start_}}) {
    if (t.ticks == 0) continue;
    const double total = t.wall[0] + t.wall[1] + t.wall[2];
    for (int k = 0; k < 3; ++k)
      st.values.push_back(kv(std::string("wall per tick, ") + label + ": " + part[k] + " [ms]",
                             str(1e3 * t.wall[k] / static_cast<double>(t.ticks))));
    st.values.push_back(kv(std::string("lockstep wait share, ") + label + " [%]",
                           str(total > 0 ? 100.0 * t.wall[2] / total : 0.0)));
  }
  since_report_ = TickTimes{};

  diagnostic_msgs::DiagnosticArray arr;
  arr.header.stamp.fromSec(s.time);
  arr.status.push_back(st);
  return arr;
}

}  // namespace vt::ros
