// DemReconfigure: dem_node's live tuning. See dem_reconfigure.h.
#include "virtual_triaxial/ros/dem_reconfigure.h"

#include <cmath>
#include <sstream>
#include <string>
#include <utility>

#include <ros/console.h>

#include "virtual_triaxial/dem/mass_damping.h"

namespace vt::ros {

DemReconfigure::DemReconfigure(const ::ros::NodeHandle& pnh, std::function<dem::Simulation*()> sim)
    : sim_(std::move(sim)), server_(mutex_, pnh) {
  // The server started from the .cfg defaults (and wrote them to the
  // parameter server): show the simulation's values before the callback is
  // attached (setCallback calls it once with the current config).
  sync();
  server_.setCallback([this](virtual_triaxial::DemConfig& c, std::uint32_t level) { on_reconfigure(c, level); });
}

void DemReconfigure::sync() {
  const dem::MassDamping& d = sim_()->settings().damping;
  virtual_triaxial::DemConfig c;
  c.damping_model = dem::to_string(d.model());
  c.damping_ratio = d.ratio();
  server_.updateConfig(c);
}

void DemReconfigure::on_reconfigure(virtual_triaxial::DemConfig& c, std::uint32_t) {
  dem::Simulation& sim = *sim_();
  const dem::MassDamping old = sim.settings().damping;
  const std::string old_model = dem::to_string(old.model());

  dem::DampingModel model = old.model();
  if (!dem::parse_damping_model(c.damping_model, model)) {
    ROS_WARN("dem_node: live tuning: ~damping_model '%s' refused (damping_model: must be %s); keeping %s",
             c.damping_model.c_str(), dem::damping_model_names(), old_model.c_str());
    model = old.model();
  }
  c.damping_model = dem::to_string(model);

  double ratio = c.damping_ratio;
  if (const std::string bad = dem::damping_parameter_error(model, ratio); !bad.empty()) {
    ROS_WARN("dem_node: live tuning: ~damping_ratio %g refused (damping_ratio: %s for damping model %s); "
             "keeping %s %g",
             ratio, bad.c_str(), dem::to_string(model), old_model.c_str(), old.ratio());
    model = old.model();
    c.damping_model = old_model;
    ratio = old.ratio();
  }
  c.damping_ratio = ratio;

  if (model == old.model() && ratio == old.ratio()) return;
  sim.set_damping(dem::MassDamping(model, ratio));
  std::ostringstream text;
  if (model != old.model()) text << "damping_model " << old_model << " -> " << c.damping_model;
  if (ratio != old.ratio())
    text << (model != old.model() ? ", " : "") << "damping_ratio " << old.ratio() << " -> " << ratio;
  ROS_INFO("dem_node: live tuning: %s (from the next control tick)", text.str().c_str());
}

}  // namespace vt::ros
