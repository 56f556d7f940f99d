// ServoControllerNode: servo strategy behind ROS. See servo_controller_node.h.
#include "virtual_triaxial/ros/servo_controller_node.h"
#include "virtual_triaxial/ros/controller_memory.h"
#include "virtual_triaxial/ros/idempotent_call.h"
#include "virtual_triaxial/ros/lockstep_subscription.h"
#include "virtual_triaxial/ros/rig_reply_words.h"

#include <cmath>

#include <boost/make_shared.hpp>
#include <functional>
#include <sstream>
#include <stdexcept>

#include "virtual_triaxial/CellCommand.h"
#include "virtual_triaxial/ClaimAxes.h"
#include "virtual_triaxial/GetInfo.h"
#include "virtual_triaxial/ReleaseAxes.h"
#include "virtual_triaxial/ServoState.h"
#include "virtual_triaxial/ros/parameters.h"

namespace vt::ros {

namespace {

std::string axes_text(const std::vector<int>& axes) {
  std::ostringstream s;
  s << "[";
  for (std::size_t i = 0; i < axes.size(); ++i) s << (i ? ", " : "") << axes[i];
  s << "]";
  return s.str();
}

bool valid_stress_target(double v) { return std::isfinite(v) && v >= 0.0; }

}  // namespace

ServoControllerNode::ServoControllerNode(const ::ros::NodeHandle& nh, const ::ros::NodeHandle& pnh,
                                         bool inline_stress)
    : nh_(nh), pnh_(pnh) {
  read_parameters();
  stress_sub_ = subscribe_lockstep<virtual_triaxial::Stress>(
      nh_, "stress", [this](const virtual_triaxial::Stress::ConstPtr& m) { on_stress(m); }, inline_stress, mutex_,
      express_);
  // Latched: a dem_node whose subscription connects after our claim (the
  // claim only needs one cell_command subscriber, maybe another node) still
  // gets the answer we already sent for the tick it waits on.
  command_pub_ = nh_.advertise<virtual_triaxial::CellCommand>("cell_command", 1000, true);
  state_pub_ = nh_.advertise<virtual_triaxial::ServoState>("servo_state", 1000);
  info_client_ = nh_.serviceClient<virtual_triaxial::GetInfo>("get_info");
  claim_client_ = nh_.serviceClient<virtual_triaxial::ClaimAxes>("claim_axes");
  release_client_ = nh_.serviceClient<virtual_triaxial::ReleaseAxes>("release_axes");
  // The servo's own services are private (~), so several controllers can share a rig.
  services_.push_back(
      pnh_.advertiseService("set_confining_pressure", &ServoControllerNode::on_set_confining_pressure, this));
  services_.push_back(pnh_.advertiseService("set_axis_targets", &ServoControllerNode::on_set_axis_targets, this));
  services_.push_back(pnh_.advertiseService("set_axes", &ServoControllerNode::on_set_axes, this));
  services_.push_back(pnh_.advertiseService("enable", &ServoControllerNode::on_enable, this));
  services_.push_back(pnh_.advertiseService("disable", &ServoControllerNode::on_disable, this));
  services_.push_back(pnh_.advertiseService("get_memory", &ServoControllerNode::on_get_memory, this));
  services_.push_back(pnh_.advertiseService("set_memory", &ServoControllerNode::on_set_memory, this));
  retry_timer_ = nh_.createWallTimer(::ros::WallDuration(0.2), &ServoControllerNode::on_retry, this);
  // Live tuning in the private namespace. The server first loads the .cfg
  // defaults (and writes them to ~gain, ...): overwrite them with the values
  // read above before the callback is attached (which calls it once).
  reconfigure_ = std::make_unique<dynamic_reconfigure::Server<virtual_triaxial::ServoConfig>>(reconfigure_mutex_, pnh_);
  reconfigure_->updateConfig(current_config());
  reconfigure_->setCallback(
      [this](virtual_triaxial::ServoConfig& c, std::uint32_t level) { on_reconfigure(c, level); });
}

control::ServoParameters ServoControllerNode::tuning(double t0) const {
  control::ServoParameters p;
  p.gain = gain_;
  p.ki = ki_;
  p.kd = kd_;
  p.max_strain_rate = max_dimensionless_rate_ / t0;
  p.max_rate_change = max_rate_change_ / t0;
  return p;
}

virtual_triaxial::ServoConfig ServoControllerNode::current_config() const {
  virtual_triaxial::ServoConfig c;
  c.gain = gain_;
  c.ki = ki_;
  c.kd = kd_;
  c.max_dimensionless_rate = max_dimensionless_rate_;
  c.max_rate_change = max_rate_change_;
  return c;
}

void ServoControllerNode::on_reconfigure(virtual_triaxial::ServoConfig& c, std::uint32_t) {
  const std::lock_guard<std::recursive_mutex> lock(mutex_);
  // Each requested field is checked against the settings accepted so far; a
  // refused one keeps its old value (written back into `c`, which the server
  // replies with and publishes on ~parameter_updates).
  std::string changes;
  auto take = [&](const char* name, double& requested, double& current, const std::function<std::string()>& check) {
    if (requested == current) return;
    const double old = current;
    current = requested;
    const std::string why = check();
    if (!why.empty()) {
      current = old;
      ROS_WARN("servo_controller_node: live tuning: ~%s %g refused (%s); keeping %g", name, requested,
               why.c_str(), old);
      requested = old;
      return;
    }
    std::ostringstream text;
    text << (changes.empty() ? "" : ", ") << name << " " << old << " -> " << current;
    changes += text.str();
  };
  // gain, ki, kd: the control library's rules (messages name the field)
  auto law_check = [&]() -> std::string {
    try {
      control::validate_servo_parameters(tuning(t0_ > 0.0 ? t0_ : 1.0));
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  take("gain", c.gain, gain_, law_check);
  take("ki", c.ki, ki_, law_check);
  take("kd", c.kd, kd_, law_check);
  take("max_dimensionless_rate", c.max_dimensionless_rate, max_dimensionless_rate_, [&]() -> std::string {
    if (!(std::isfinite(max_dimensionless_rate_) && max_dimensionless_rate_ > 0.0))
      return "max_dimensionless_rate: must be a finite number > 0";
    if (dem_max_dimensionless_rate_ > 0.0 && max_dimensionless_rate_ > dem_max_dimensionless_rate_)
      return "max_dimensionless_rate: above dem_node's limit " + std::to_string(dem_max_dimensionless_rate_);
    return "";
  });
  take("max_rate_change", c.max_rate_change, max_rate_change_, [&]() -> std::string {
    if (!(std::isfinite(max_rate_change_) && max_rate_change_ >= 0.0))
      return "max_rate_change: must be a finite number >= 0 (0 = no rate limit)";
    return "";
  });
  if (changes.empty()) return;
  if (t0_ > 0.0) {
    params_ = tuning(t0_);
    if (strategy_) {
      try {
        strategy_->set_parameters(params_);
      } catch (const std::exception& e) {  // not expected: every field was checked
        ROS_ERROR("servo_controller_node: live tuning: %s", e.what());
      }
    }
  } else {
    params_.gain = gain_;  // the rates follow when T0 is known (claim)
    params_.ki = ki_;
    params_.kd = kd_;
  }
  const bool unused = strategy_name_ == "proportional" && (ki_ != 0.0 || kd_ != 0.0 || max_rate_change_ != 0.0);
  ROS_INFO("servo_controller_node: live tuning: %s (from the next control update)%s", changes.c_str(),
           unused ? "; ki, kd, max_rate_change are not used by 'proportional'" : "");
}

void ServoControllerNode::read_parameters() {
  pnh_.param<std::string>("strategy", strategy_name_, "proportional");
  pnh_.param<std::string>("owner", owner_, pnh_.getNamespace());
  if (owner_.empty()) throw std::invalid_argument("~owner: must not be empty");
  gain_ = optional_double(pnh_, "gain").value_or(0.5);
  ki_ = optional_double(pnh_, "ki").value_or(0.0);
  kd_ = optional_double(pnh_, "kd").value_or(0.0);
  max_rate_change_ = optional_double(pnh_, "max_rate_change").value_or(0.0);
  max_dimensionless_rate_ = optional_double(pnh_, "max_dimensionless_rate").value_or(1e-4);
  if (!(std::isfinite(max_dimensionless_rate_) && max_dimensionless_rate_ > 0.0))
    throw std::invalid_argument("~max_dimensionless_rate: must be a finite number > 0");
  // Validates ~strategy, ~gain, ~ki, ~kd, ~max_rate_change now (the messages
  // name the field); the real rates need T0 from dem_node.
  try {
    control::make_servo(strategy_name_, tuning(1.0));
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("~strategy / ~gain / ~ki / ~kd / ~max_rate_change: ") + e.what());
  }
  params_ = tuning(1.0);
  params_.max_strain_rate = 0.0;  // set from T0 at the claim
  params_.max_rate_change = 0.0;

  const auto target = optional_double(pnh_, "target");
  if (!target) throw std::invalid_argument("~target: required (stress target in Pa)");
  if (!valid_stress_target(*target)) throw std::invalid_argument("~target: must be a finite number >= 0 Pa");
  ramp_.reset(dem::Vec3{*target, *target, *target});

  axes_ = {0, 1};
  if (pnh_.hasParam("axes") && !pnh_.getParam("axes", axes_))
    throw std::invalid_argument("~axes: must be a list of integers (0 = x, 1 = y, 2 = z)");
  if (axes_.empty()) throw std::invalid_argument("~axes: no axis given");
  for (int a : axes_) {
    if (a < 0 || a > 2) throw std::invalid_argument("~axes: " + std::to_string(a) + " is not 0, 1 or 2");
    if ((a == 0 && mask_.x) || (a == 1 && mask_.y) || (a == 2 && mask_.z))
      throw std::invalid_argument("~axes: axis " + std::to_string(a) + " listed twice");
    (a == 0 ? mask_.x : a == 1 ? mask_.y : mask_.z) = true;
  }
  pnh_.param("start_enabled", enabled_, true);
}

std::string ServoControllerNode::try_claim() {
  if (stress_sub_.getNumPublishers() == 0 || command_pub_.getNumSubscribers() == 0)
    return "waiting for dem_node's stress / cell_command connections";
  virtual_triaxial::GetInfo info;
  if (!call_idempotent(info_client_, info)) return "get_info not available yet";
  if (!(std::isfinite(info.response.t0) && info.response.t0 > 0.0)) return "get_info: T0 is not > 0";
  t0_ = info.response.t0;
  dem_max_dimensionless_rate_ = info.response.max_dimensionless_rate;
  params_ = tuning(t0_);
  try {
    strategy_ = control::make_servo(strategy_name_, params_);
    strategy_->init(ramp_.value(info.response.time), mask_);
    strategy_->start(info.response.time);
  } catch (const std::exception& e) {
    return std::string("servo: ") + e.what();
  }
  last_time_ = info.response.time;
  virtual_triaxial::ClaimAxes claim;
  claim.request.owner = owner_;
  claim.request.axes.assign(axes_.begin(), axes_.end());
  if (!call_idempotent(claim_client_, claim)) return "claim_axes not available yet";
  if (!claim.response.success) return "claim_axes refused: " + claim.response.message;
  claim_tick_ = claim.response.tick;
  claimed_ = true;
  ROS_INFO("servo_controller_node: '%s' controls axes %s (%s, gain %g, ki %g, kd %g, |eps'| <= %g, "
           "|delta eps'| <= %g per update, T0 %.4g s)",
           owner_.c_str(), axes_text(axes_).c_str(), strategy_name_.c_str(), params_.gain, params_.ki, params_.kd,
           max_dimensionless_rate_, max_rate_change_, info.response.t0);
  // A state that came while the claim was pending, for a tick dem_node waits
  // on us for (an earlier claim of ours took effect, its answer lost).
  virtual_triaxial::Stress::ConstPtr pending;
  pending.swap(pending_);
  if (pending && pending->tick > claim_tick_) answer(*pending);
  return "";
}

std::string ServoControllerNode::release() {
  if (strategy_ && strategy_->running()) strategy_->stop();
  virtual_triaxial::ReleaseAxes rel;
  rel.request.owner = owner_;
  rel.request.axes.assign(axes_.begin(), axes_.end());
  const bool held = claimed_;  // asked even without a claim (ReleaseAnswer::why)
  const ReleaseAnswer a = call_release_axes(release_client_, rel);
  if (!a.answered) return a.why(held);
  claimed_ = false;  // refused means we do not own them any more either
  pending_.reset();
  if (!a.released) return a.why(held);
  if (!held)
    ROS_WARN("servo_controller_node: released axes %s that dem_node still listed for '%s'", axes_text(axes_).c_str(),
             owner_.c_str());
  return "";
}

void ServoControllerNode::on_retry(const ::ros::WallTimerEvent&) {
  const std::lock_guard<std::recursive_mutex> lock(mutex_);
  if (!enabled_ || claimed_) return;
  const std::string why = try_claim();
  if (!why.empty() && why != last_wait_reason_) {
    ROS_INFO("servo_controller_node: %s; retrying", why.c_str());
    last_wait_reason_ = why;
  }
}

void ServoControllerNode::on_stress(const virtual_triaxial::Stress::ConstPtr& msg) {
  const std::lock_guard<std::recursive_mutex> lock(mutex_);
  last_time_ = msg->time;
  // Ticks keep counting across load_sample; one going backwards means a new
  // dem_node process, which knows nothing of our claim: claim again.
  const std::uint64_t previous = last_tick_;
  const bool restarted = has_tick_ && msg->tick <= previous;
  last_tick_ = msg->tick;
  has_tick_ = true;
  if (restarted && claimed_) {
    ROS_WARN("servo_controller_node: tick %llu after %llu: dem_node restarted, claiming the axes again",
             static_cast<unsigned long long>(msg->tick), static_cast<unsigned long long>(previous));
    claimed_ = false;
    pending_.reset();
    return;
  }
  if (enabled_ && !claimed_) pending_ = msg;  // answered if the claim, when made, makes it ours
  if (!enabled_ || !claimed_ || !strategy_) return;
  // States published before the claim (a backlog in our queue) need no answer.
  if (msg->tick <= claim_tick_) return;
  answer(*msg);
}

void ServoControllerNode::answer(const virtual_triaxial::Stress& state) {
  control::ServoInput in;
  in.time = state.time;
  in.dt = state.control_period;
  in.stress = {state.stress[0], state.stress[4], state.stress[8]};
  in.stiffness = {state.stiffness[0], state.stiffness[1], state.stiffness[2]};
  control::ServoOutput out;
  try {
    strategy_->set_targets(ramp_.value(state.time));
    out = strategy_->update(in);
  } catch (const std::exception& e) {
    ROS_ERROR_THROTTLE(1.0, "servo_controller_node: tick %llu: no command: %s",
                       static_cast<unsigned long long>(state.tick), e.what());
    return;
  }
  virtual_triaxial::CellCommand cmd;
  cmd.header = state.header;
  cmd.tick = state.tick;
  cmd.owner = owner_;
  for (int a : axes_) {
    cmd.axes.push_back(static_cast<std::uint8_t>(a));
    cmd.strain_rate.push_back(out.strain_rate[a]);
  }
  // Shared pointers: a dem_node in the same process (nodelet rig) gets the
  // command at once, in this call; a copy would be handed over by roscpp's
  // network thread later.
  command_pub_.publish(boost::make_shared<virtual_triaxial::CellCommand>(std::move(cmd)));

  virtual_triaxial::ServoState st;
  st.header = state.header;
  st.tick = state.tick;
  st.strategy = strategy_->name();
  st.enabled = enabled_;
  const dem::Vec3 targets = strategy_->targets();
  for (int i = 0; i < 3; ++i) {
    const auto k = static_cast<std::size_t>(i);
    st.controlled[k] = controls(i);
    st.targets[k] = controls(i) ? targets[i] : 0.0;  // an earlier stage's target of an axis let go is no state
    st.errors[k] = out.error[i];
    st.saturated[k] = out.saturated[i];
    st.strain_rate[k] = out.strain_rate[i];
  }
  const control::ServoParameters& p = strategy_->parameters();
  st.gain = p.gain;
  st.max_strain_rate = p.max_strain_rate;
  st.ki = p.ki;
  st.kd = p.kd;
  st.max_rate_change = p.max_rate_change;
  state_pub_.publish(boost::make_shared<virtual_triaxial::ServoState>(std::move(st)));
}

bool ServoControllerNode::on_set_confining_pressure(virtual_triaxial::SetConfiningPressure::Request& rq,
                                                    virtual_triaxial::SetConfiningPressure::Response& rs) {
  const std::lock_guard<std::recursive_mutex> lock(mutex_);
  rs.success = false;
  if (!valid_stress_target(rq.target)) {
    rs.message = "target: must be a finite number >= 0 Pa (compression positive)";
  } else if (!(std::isfinite(rq.ramp_seconds) && rq.ramp_seconds >= 0.0)) {
    rs.message = "ramp_seconds: must be a finite number >= 0 (simulation seconds)";
  } else {
    for (int a : axes_) ramp_.ramp(a, rq.target, last_time_, rq.ramp_seconds);
    rs.success = true;
    rs.message = "target " + std::to_string(rq.target) + " Pa on axes " + axes_text(axes_) + " over " +
                 std::to_string(rq.ramp_seconds) + " s";
  }
  return true;
}

bool ServoControllerNode::on_set_axis_targets(virtual_triaxial::SetAxisTargets::Request& rq,
                                              virtual_triaxial::SetAxisTargets::Response& rs) {
  const std::lock_guard<std::recursive_mutex> lock(mutex_);
  rs.success = false;
  if (rq.axes.empty()) {
    rs.message = "axes: no axis given";
    return true;
  }
  for (std::uint8_t a : rq.axes) {
    if (a > 2 || !controls(a)) {
      rs.message = "axes: axis " + std::to_string(a) + " is not controlled by this servo (axes " +
                   axes_text(axes_) + ")";
      return true;
    }
    if (!valid_stress_target(rq.targets[a])) {
      rs.message = "targets[" + std::to_string(a) + "]: must be a finite number >= 0 Pa";
      return true;
    }
  }
  if (!(std::isfinite(rq.ramp_seconds) && rq.ramp_seconds >= 0.0)) {
    rs.message = "ramp_seconds: must be a finite number >= 0 (simulation seconds)";
    return true;
  }
  for (std::uint8_t a : rq.axes) ramp_.ramp(a, rq.targets[a], last_time_, rq.ramp_seconds);
  rs.success = true;
  rs.message = "targets set";
  return true;
}

bool ServoControllerNode::on_set_axes(virtual_triaxial::SetServoAxes::Request& rq,
                                      virtual_triaxial::SetServoAxes::Response& rs) {
  const std::lock_guard<std::recursive_mutex> lock(mutex_);
  rs.success = false;
  control::AxisMask mask{false, false, false};
  std::vector<int> axes;
  if (rq.axes.empty()) {
    rs.message = "axes: no axis given";
    return true;
  }
  for (std::uint8_t a : rq.axes) {
    bool* m = a == 0 ? &mask.x : a == 1 ? &mask.y : a == 2 ? &mask.z : nullptr;
    if (!m) {
      rs.message = "axes: " + std::to_string(a) + " is not a cell axis (0 = x, 1 = y, 2 = z)";
      return true;
    }
    if (*m) {
      rs.message = "axes: axis " + std::to_string(a) + " listed twice";
      return true;
    }
    *m = true;
    axes.push_back(a);
  }
  const std::string why_release = release();
  if (!why_release.empty()) ROS_WARN("servo_controller_node: set_axes: %s", why_release.c_str());
  // New axes start at the current target of the first old axis.
  const dem::Vec3 now = ramp_.value(last_time_);
  const double base = now[axes_.front()];
  for (int a : axes)
    if (!controls(a)) ramp_.ramp(a, base, last_time_, 0.0);
  axes_ = axes;
  mask_ = mask;
  strategy_.reset();
  if (!enabled_) {
    rs.success = true;
    rs.message = "axes " + axes_text(axes_) + " (disabled: not claimed)";
    return true;
  }
  const std::string why = try_claim();
  rs.success = why.empty();
  rs.message = why.empty() ? "axes " + axes_text(axes_) + " claimed" : "axes: " + why;
  return true;
}

bool ServoControllerNode::on_enable(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& rs) {
  const std::lock_guard<std::recursive_mutex> lock(mutex_);
  enabled_ = true;
  rs.success = true;
  if (claimed_) {
    rs.message = "already enabled; axes " + axes_text(axes_) + " claimed";
    return true;
  }
  const std::string why = try_claim();
  rs.message = why.empty() ? "enabled; axes " + axes_text(axes_) + " claimed"
                           : reply_words::enabled_not_claimed_yet(why);
  return true;
}

bool ServoControllerNode::on_disable(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& rs) {
  const std::lock_guard<std::recursive_mutex> lock(mutex_);
  enabled_ = false;
  const bool held = claimed_;
  const std::string why = release();
  rs.success = why.empty();
  rs.message = !why.empty() ? "disabled; " + why : held ? "disabled; axes released" : "disabled; no claim recorded";
  return true;
}

bool ServoControllerNode::on_get_memory(virtual_triaxial::GetMemory::Request&,
                                        virtual_triaxial::GetMemory::Response& rs) {
  const std::lock_guard<std::recursive_mutex> lock(mutex_);
  rs.strategy = strategy_name_;
  if (!strategy_) {
    rs.success = true;  // not running: no memory
    rs.message = "not running (no memory)";
    return true;
  }
  rs.memory = strategy_->memory();
  rs.success = true;
  rs.message = std::to_string(rs.memory.size()) + " numbers at tick " + std::to_string(last_tick_);
  return true;
}

bool ServoControllerNode::on_set_memory(virtual_triaxial::SetMemory::Request& rq,
                                        virtual_triaxial::SetMemory::Response& rs) {
  const std::lock_guard<std::recursive_mutex> lock(mutex_);
  rs.success = false;
  if (!enabled_ || !claimed_ || !strategy_) {
    rs.message = "memory: the servo is not running (enable it first; axes claimed)";
    return true;
  }
  answer_set_memory(*strategy_, rq.memory, rs);
  return true;
}

}  // namespace vt::ros
