#include "virtual_triaxial/ros/specimen_views.h"

#include <cmath>
#include <stdexcept>

#include "virtual_triaxial/ros/parameters.h"

namespace vt::ros {

SpecimenViews::SpecimenViews(::ros::NodeHandle& nh, const ::ros::NodeHandle& pnh) {
  const std::string dir = optional_string(pnh, "snapshot_dir").value_or("");
  int interval = 0;
  interval_given_ = pnh.getParam("snapshot_interval", interval);
  if (interval < 0) throw std::invalid_argument("~snapshot_interval: must be an integer >= 0 steps (0: none)");
  interval_ = interval;
  if (!dir.empty()) {
    try {
      series_ = std::make_unique<io::VtkSnapshotSeries>(dir);
    } catch (const std::exception& e) {
      throw std::invalid_argument(std::string("~snapshot_dir: ") + e.what());
    }
  }
  pnh.param("markers", markers_, false);
  marker_period_ = optional_double(pnh, "marker_period").value_or(1.0);
  if (!(std::isfinite(marker_period_) && marker_period_ > 0.0))
    throw std::invalid_argument("~marker_period: must be > 0 wall seconds");
  int forces = 0, max_particles = 20000;
  pnh.param("marker_forces", forces, 0);
  if (forces < 0) throw std::invalid_argument("~marker_forces: must be an integer >= 0");
  pnh.param("marker_max_particles", max_particles, 20000);
  if (max_particles < 1) throw std::invalid_argument("~marker_max_particles: must be an integer >= 1");
  marker_options_.strongest_contacts = static_cast<std::size_t>(forces);
  marker_options_.max_particles = static_cast<std::size_t>(max_particles);
  marker_options_.frame = optional_string(pnh, "marker_frame").value_or("cell");
  if (marker_options_.frame.empty()) throw std::invalid_argument("~marker_frame: must not be empty");
  if (markers_) marker_pub_ = nh.advertise<visualization_msgs::MarkerArray>("specimen_markers", 1, true);
}

void SpecimenViews::on_load(const dem::Simulation& sim, std::int64_t scene_interval, const std::string& source) {
  if (!interval_given_) interval_ = scene_interval;
  base_step_ = sim.steps();
  last_block_ = 0;
  // A protocol goal reloads the file the node started with: one snapshot per step.
  if (series_ && series_->last_step() != sim.steps())
    snapshot(sim, "load " + source.substr(source.find_last_of('/') + 1));
  if (markers_) publish_markers(sim);
}

void SpecimenViews::on_pause(const dem::Simulation& sim) {
  if (series_ && series_->last_step() != sim.steps()) snapshot(sim, "pause");
  if (markers_) publish_markers(sim);
}

void SpecimenViews::snapshot(const dem::Simulation& sim, const std::string& label) {
  if (interval_ > 0) last_block_ = (sim.steps() - base_step_) / interval_;
  try {
    series_->write(dem::SpecimenSnapshot::of(sim), label + " at step " + std::to_string(sim.steps()));
  } catch (const std::exception& e) {
    ROS_ERROR_THROTTLE(10.0, "dem_node: snapshot not written: %s", e.what());
  }
}

void SpecimenViews::publish_markers(const dem::Simulation& sim) {
  last_markers_ = ::ros::WallTime::now();
  ::ros::Time stamp;
  stamp.fromSec(sim.time());
  marker_pub_.publish(to_marker_array(dem::SpecimenSnapshot::of(sim), marker_options_, stamp));
}

}  // namespace vt::ros
