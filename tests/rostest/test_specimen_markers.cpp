// rostest specimen_markers.test: dem_node publishes the specimen on the
// latched topic specimen_markers: one SPHERE marker per particle (200, no
// decimation), frame "cell", scale 2 R in every direction (spheres), pose
// x = H s of the sample file; the cell box (12 edges); the 10 strongest
// contacts as lines, strongest first in the colour ramp; after stepping and
// pausing, a new array stamped with the simulation time. A dem_node without
// ~markers advertises nothing.
#include <cmath>
#include <mutex>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>
#include <visualization_msgs/MarkerArray.h>

#include "virtual_triaxial/GetInfo.h"
#include "virtual_triaxial/Step.h"
#include "virtual_triaxial/io/sample_file.h"

#include "support/rig_test_helpers.h"

namespace vtm = virtual_triaxial;
using vt::rostest::wait_until;

namespace {

std::mutex g_mutex;
std::vector<visualization_msgs::MarkerArray> g_arrays;

void on_markers(const visualization_msgs::MarkerArray::ConstPtr& m) {
  std::lock_guard<std::mutex> lock(g_mutex);
  g_arrays.push_back(*m);
}

std::size_t received() {
  std::lock_guard<std::mutex> lock(g_mutex);
  return g_arrays.size();
}

visualization_msgs::MarkerArray last() {
  std::lock_guard<std::mutex> lock(g_mutex);
  return g_arrays.back();
}

std::vector<const visualization_msgs::Marker*> in_ns(const visualization_msgs::MarkerArray& a, const std::string& ns) {
  std::vector<const visualization_msgs::Marker*> out;
  for (const auto& m : a.markers)
    if (m.ns == ns && m.action == visualization_msgs::Marker::ADD) out.push_back(&m);
  return out;
}

}  // namespace

TEST(SpecimenMarkers, OneSpherePerParticleInTheCellFrameSizedByItsRadius) {
  ASSERT_TRUE(wait_until([] { return received() > 0; }, 30.0)) << "no latched specimen_markers";
  const visualization_msgs::MarkerArray a = last();
  std::string path;
  ASSERT_TRUE(ros::param::get("/test_sample", path));
  const vt::dem::SimulationState s = vt::io::read_sample(path);
  const auto particles = in_ns(a, "particles");
  ASSERT_EQ(particles.size(), s.particles.size());
  ASSERT_EQ(a.markers.front().action, visualization_msgs::Marker::DELETEALL);
  for (std::size_t k = 0; k < particles.size(); ++k) {
    const visualization_msgs::Marker& m = *particles[k];
    const auto i = static_cast<std::size_t>(m.id);  // storage index = file order
    ASSERT_LT(i, s.particles.size());
    EXPECT_EQ(m.header.frame_id, "cell");
    EXPECT_EQ(m.type, visualization_msgs::Marker::SPHERE);
    const double d = 2.0 * s.particles.radius[i];
    EXPECT_EQ(m.scale.x, d);
    EXPECT_EQ(m.scale.y, d);
    EXPECT_EQ(m.scale.z, d);
    const vt::dem::Vec3 x = s.h * s.particles.frac[i];
    EXPECT_NEAR(m.pose.position.x, x.x, 1e-15);
    EXPECT_NEAR(m.pose.position.y, x.y, 1e-15);
    EXPECT_NEAR(m.pose.position.z, x.z, 1e-15);
    EXPECT_EQ(m.pose.orientation.w, 1.0);
  }
  const auto cell = in_ns(a, "cell");
  ASSERT_EQ(cell.size(), 1u);
  EXPECT_EQ(cell[0]->points.size(), 24u);  // 12 edges
  const auto forces = in_ns(a, "forces");
  ASSERT_EQ(forces.size(), 1u);
  ASSERT_EQ(forces[0]->points.size(), 20u);  // 10 strongest contacts
  ASSERT_EQ(forces[0]->colors.size(), 20u);
  EXPECT_FLOAT_EQ(forces[0]->colors[0].r, 1.0f);  // the strongest is full red
  for (std::size_t k = 2; k < 20; k += 2) EXPECT_LE(forces[0]->colors[k].r, forces[0]->colors[k - 2].r);
}

TEST(SpecimenMarkers, SteppingAndPausingPublishesTheNewState) {
  ASSERT_TRUE(wait_until([] { return received() > 0; }, 30.0));
  const std::size_t before = received();
  vtm::Step st;
  st.request.count = 20;
  ASSERT_TRUE(vt::rostest::call_service("/step", st, 30.0));
  ASSERT_TRUE(st.response.success) << st.response.message;
  vtm::GetInfo info;
  ASSERT_TRUE(wait_until([&] { return vt::rostest::call_service_again("/get_info", info, 5.0) && info.response.tick >= 20; }, 30.0));
  std_srvs::Trigger pause;
  ASSERT_TRUE(vt::rostest::call_service_again("/pause", pause, 30.0));
  ASSERT_TRUE(vt::rostest::call_service_again("/get_info", info, 5.0));
  ASSERT_GT(info.response.time, 0.0);
  const double t = ros::Time().fromSec(info.response.time).toSec();
  EXPECT_TRUE(wait_until([&] { return received() > before && last().markers.back().header.stamp.toSec() == t; }, 30.0))
      << "no marker array stamped with the paused simulation time " << t;
  EXPECT_EQ(in_ns(last(), "particles").size(), 200u);
}

TEST(SpecimenMarkers, OffByDefault) {
  ros::master::V_TopicInfo topics;
  ASSERT_TRUE(ros::master::getTopics(topics));
  bool on = false, off = false;
  for (const auto& t : topics) {
    on = on || t.name == "/specimen_markers";
    off = off || t.name == "/off/specimen_markers";
  }
  EXPECT_TRUE(on);
  EXPECT_FALSE(off);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_specimen_markers");
  ros::NodeHandle nh;
  ros::Subscriber sub = nh.subscribe("/specimen_markers", 100, on_markers);
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const int rc = RUN_ALL_TESTS();
  spinner.stop();
  ros::shutdown();
  return rc;
}
