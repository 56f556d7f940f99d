// /diagnostics report of dem_node (diagnostic_msgs/DiagnosticArray, one
// status "<node name>: simulation").
//
// Reports the time scale (T0, dt, c_t = dt/T0; WARN when c_t >= 1, i.e. the
// step is at or above the critical estimate), the real-time factor (simulated
// seconds per wall second since the previous report), tick and step counts,
// lockstep timeouts per owner, refused cell commands and numerical failure
// (ERROR), and where the wall time of a control tick goes: the DEM steps,
// measuring and publishing the state, and the lockstep wait for the
// claimants' commands (means per tick since the previous report and since
// the start; the wait is the rig's overhead over a headless run). Level: ERROR when unstable, WARN on c_t >= 1 or when timeouts or
// refused commands happened since the previous report, OK otherwise.
#pragma once

#include <cstdint>
#include <map>
#include <string>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <ros/time.h>

namespace vt::ros {

/// Snapshot of the node state that goes into a report.
struct DemStatus {
  std::string name;          ///< status name
  double t0 = 0, dt = 0;     ///< [s]
  std::uint64_t tick = 0;
  std::int64_t step = 0;
  double time = 0;           ///< simulation time [s]
  std::uint64_t particles = 0;
  bool paused = false, lockstep = true, unstable = false;
  std::string failure;
};

class DemDiagnostics {
 public:
  void count_timeout(const std::string& owner);
  void count_rejected(const std::string& reason);
  /// Wall time of one control tick [s]: DEM steps, measures + messages, lockstep wait.
  void add_tick(double stepping, double publishing, double waiting);
  /// One line: ticks and mean wall time per tick of each part since the start.
  std::string tick_summary() const;
  std::uint64_t timeouts() const { return timeouts_; }
  std::uint64_t rejected() const { return rejected_; }

  /// Builds the report; stamp = simulation time (the rig's clock). The
  /// real-time factor is measured between consecutive calls.
  diagnostic_msgs::DiagnosticArray report(const DemStatus& s, ::ros::WallTime now);

 private:
  std::map<std::string, std::uint64_t> timeouts_by_owner_;
  std::uint64_t timeouts_ = 0, rejected_ = 0;
  std::uint64_t timeouts_reported_ = 0, rejected_reported_ = 0;
  std::string last_rejection_;
  /// Tick wall-time sums: [0] stepping, [1] publishing, [2] waiting; ticks.
  struct TickTimes {
    double wall[3] = {0, 0, 0};
    std::uint64_t ticks = 0;
  };
  TickTimes since_report_, since_start_;
  double last_time_ = -1.0;
  ::ros::WallTime last_wall_;
};

}  // namespace vt::ros
