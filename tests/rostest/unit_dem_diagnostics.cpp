// DemDiagnostics without a master: the wall-time split of a control tick
// (DEM steps / measures + messages / lockstep wait) that dem_node reports on
// /diagnostics and logs when paused, i.e. where the rig's overhead goes.
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "virtual_triaxial/ros/dem_diagnostics.h"

using vt::ros::DemDiagnostics;
using vt::ros::DemStatus;

namespace {

std::map<std::string, std::string> values(const diagnostic_msgs::DiagnosticArray& a) {
  std::map<std::string, std::string> v;
  for (const auto& kv : a.status.at(0).values) v[kv.key] = kv.value;
  return v;
}

double number(const std::map<std::string, std::string>& v, const std::string& key) {
  const auto it = v.find(key);
  if (it == v.end()) throw std::runtime_error("missing key: " + key);
  return std::stod(it->second);
}

DemStatus status() {
  DemStatus s;
  s.name = "/dem_node: simulation";
  s.t0 = 1e-6;
  s.dt = 3e-7;
  return s;
}

}  // namespace

TEST(DemDiagnostics, TickWallTimesAreMeansPerTickWithTheWaitShare) {
  DemDiagnostics d;
  // 4 ticks of 1 ms DEM, 0.2 ms publishing, 0.5 ms waiting: wait share 0.5 / 1.7.
  for (int k = 0; k < 4; ++k) d.add_tick(1e-3, 2e-4, 5e-4);
  const auto v = values(d.report(status(), ::ros::WallTime(10.0)));
  EXPECT_NEAR(number(v, "wall per tick, recent: DEM steps [ms]"), 1.0, 1e-9);
  EXPECT_NEAR(number(v, "wall per tick, recent: measures + messages [ms]"), 0.2, 1e-9);
  EXPECT_NEAR(number(v, "wall per tick, recent: lockstep wait [ms]"), 0.5, 1e-9);
  EXPECT_NEAR(number(v, "lockstep wait share, recent [%]"), 100.0 * 0.5 / 1.7, 1e-3);
  EXPECT_NEAR(number(v, "wall per tick, since start: lockstep wait [ms]"), 0.5, 1e-9);
}

TEST(DemDiagnostics, RecentTimesRestartAtEachReportWhileTheTotalsAccumulate) {
  DemDiagnostics d;
  d.add_tick(1e-3, 0.0, 1e-3);
  d.report(status(), ::ros::WallTime(1.0));
  const auto idle = values(d.report(status(), ::ros::WallTime(2.0)));
  EXPECT_EQ(idle.count("wall per tick, recent: DEM steps [ms]"), 0u) << "no tick since the last report";
  EXPECT_NEAR(number(idle, "wall per tick, since start: DEM steps [ms]"), 1.0, 1e-9);
  d.add_tick(3e-3, 0.0, 0.0);
  const auto v = values(d.report(status(), ::ros::WallTime(3.0)));
  EXPECT_NEAR(number(v, "wall per tick, recent: DEM steps [ms]"), 3.0, 1e-9);
  EXPECT_NEAR(number(v, "wall per tick, since start: DEM steps [ms]"), 2.0, 1e-9);
  EXPECT_NEAR(number(v, "lockstep wait share, since start [%]"), 100.0 * 1.0 / 5.0, 1e-3);
  const std::string line = d.tick_summary();
  EXPECT_NE(line.find("2 control ticks"), std::string::npos) << line;
  EXPECT_NE(line.find("DEM steps 2 ms"), std::string::npos) << line;
  EXPECT_NE(line.find("lockstep wait 0.5 ms"), std::string::npos) << line;
}
