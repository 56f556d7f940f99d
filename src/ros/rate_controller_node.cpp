// RateControllerNode: a rate strategy behind ROS. See rate_controller_node.h.
#include "virtual_triaxial/ros/rate_controller_node.h"
#include "virtual_triaxial/ros/controller_memory.h"
#include "virtual_triaxial/ros/idempotent_call.h"
#include "virtual_triaxial/ros/lockstep_subscription.h"

#include <cmath>
#include <stdexcept>

#include <boost/make_shared.hpp>

#include "virtual_triaxial/CellCommand.h"
#include "virtual_triaxial/ClaimAxes.h"
#include "virtual_triaxial/RateState.h"
#include "virtual_triaxial/ReleaseAxes.h"

namespace vt::ros {

RateControllerNode::RateControllerNode(const ::ros::NodeHandle& nh, const ::ros::NodeHandle& pnh, bool inline_index)
    : nh_(nh), pnh_(pnh) {
  pnh_.param<std::string>("owner", owner_, pnh_.getNamespace());
  if (owner_.empty()) throw std::invalid_argument("~owner: must not be empty");
  index_sub_ = subscribe_lockstep<virtual_triaxial::MomentIndex>(
      nh_, "moment_index", [this](const virtual_triaxial::MomentIndex::ConstPtr& m) { on_index(m); }, inline_index,
      mutex_, express_);
  command_pub_ = nh_.advertise<virtual_triaxial::CellCommand>("cell_command", 1000, true);
  state_pub_ = nh_.advertise<virtual_triaxial::RateState>("rate_state", 1000);
  claim_client_ = nh_.serviceClient<virtual_triaxial::ClaimAxes>("claim_axes");
  release_client_ = nh_.serviceClient<virtual_triaxial::ReleaseAxes>("release_axes");
  services_.push_back(pnh_.advertiseService("configure", &RateControllerNode::on_configure, this));
  services_.push_back(pnh_.advertiseService("enable", &RateControllerNode::on_enable, this));
  services_.push_back(pnh_.advertiseService("disable", &RateControllerNode::on_disable, this));
  services_.push_back(pnh_.advertiseService("get_memory", &RateControllerNode::on_get_memory, this));
  services_.push_back(pnh_.advertiseService("set_memory", &RateControllerNode::on_set_memory, this));
}

bool RateControllerNode::on_configure(virtual_triaxial::ConfigureRate::Request& rq,
                                      virtual_triaxial::ConfigureRate::Response& rs) {
  const std::lock_guard<std::recursive_mutex> lock(mutex_);
  rs.success = false;
  if (claimed_) {
    rs.message = "strategy: refused while enabled (disable first)";
    return true;
  }
  control::RateSpec spec;
  if (!control::parse_rate_strategy(rq.strategy, spec.strategy)) {
    rs.message = "strategy: unknown '" + rq.strategy + "'; allowed: fixed, predicted, adaptive";
    return true;
  }
  if (rq.axis > 2) {
    rs.message = "axis: must be 0, 1 or 2";
    return true;
  }
  if (!(std::isfinite(rq.t0) && rq.t0 > 0.0)) {
    rs.message = "t0: must be finite and > 0";
    return true;
  }
  if (!(std::isfinite(rq.quasi_static_threshold) && rq.quasi_static_threshold > 0.0)) {
    rs.message = "quasi_static_threshold: must be finite and > 0";
    return true;
  }
  control::AdaptiveRateParameters& a = spec.adaptive;
  a.target = rq.target;
  a.min_dimensionless = rq.min_dimensionless;
  a.max_dimensionless = rq.max_dimensionless;
  a.max_change = rq.max_change;
  a.smoothing_ticks = rq.smoothing_ticks;
  a.response_ticks = rq.response_ticks;
  a.sensitivity = rq.sensitivity;
  try {
    std::unique_ptr<control::RateStrategy> s = control::make_rate_strategy(spec, rq.t0);
    s->start(rq.rate0);
    strategy_ = std::move(s);
  } catch (const std::invalid_argument& e) {
    rs.message = e.what();  // "<field>: <reason>"
    return true;
  }
  rate0_ = rq.rate0;
  t0_ = rq.t0;
  threshold_ = rq.quasi_static_threshold;
  axis_ = rq.axis;
  rs.success = true;
  rs.message = std::string(strategy_->name()) + " on axis " + std::to_string(axis_) + ", first eps' " +
               std::to_string(strategy_->rate() * t0_);
  return true;
}

bool RateControllerNode::on_enable(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& rs) {
  const std::lock_guard<std::recursive_mutex> lock(mutex_);
  rs.success = false;
  if (!strategy_) {
    rs.message = "not configured (call ~configure first)";
    return true;
  }
  if (claimed_) {
    rs.success = true;
    rs.message = "already enabled";
    return true;
  }
  virtual_triaxial::ClaimAxes claim;
  claim.request.owner = owner_;
  claim.request.axes.push_back(static_cast<std::uint8_t>(axis_));
  if (!call_idempotent(claim_client_, claim)) {
    rs.message = "claim_axes: dem_node does not answer";
    return true;
  }
  if (!claim.response.success) {
    rs.message = "claim_axes refused: " + claim.response.message;
    return true;
  }
  claim_tick_ = claim.response.tick;
  claimed_ = true;
  rs.success = true;
  rs.message = std::string("enabled: ") + strategy_->name() + " controls axis " + std::to_string(axis_) +
               " from tick " + std::to_string(claim_tick_ + 1);
  ROS_INFO("rate_controller_node: '%s' %s (first eps' %.4g)", owner_.c_str(), rs.message.c_str(),
           strategy_->rate() * t0_);
  return true;
}

std::string RateControllerNode::release() {
  virtual_triaxial::ReleaseAxes rel;
  rel.request.owner = owner_;
  rel.request.axes.push_back(static_cast<std::uint8_t>(axis_));
  const bool held = claimed_;  // asked even without a claim (ReleaseAnswer::why)
  claimed_ = false;
  return call_release_axes(release_client_, rel).why(held);
}

bool RateControllerNode::on_disable(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& rs) {
  const std::lock_guard<std::recursive_mutex> lock(mutex_);
  const std::string why = release();
  strategy_.reset();
  rs.success = why.empty();
  rs.message = why.empty() ? "disabled; axis released" : "disabled; " + why;
  return true;
}

bool RateControllerNode::on_get_memory(virtual_triaxial::GetMemory::Request&,
                                       virtual_triaxial::GetMemory::Response& rs) {
  const std::lock_guard<std::recursive_mutex> lock(mutex_);
  rs.success = true;
  if (!strategy_) {
    rs.message = "not configured (no memory)";
    return true;
  }
  rs.strategy = strategy_->name();
  rs.memory = strategy_->memory();
  rs.message = std::to_string(rs.memory.size()) + " numbers";
  return true;
}

bool RateControllerNode::on_set_memory(virtual_triaxial::SetMemory::Request& rq,
                                       virtual_triaxial::SetMemory::Response& rs) {
  const std::lock_guard<std::recursive_mutex> lock(mutex_);
  rs.success = false;
  if (!strategy_ || !claimed_) {
    rs.message = "memory: the rate controller is not running (configure and enable it first)";
    return true;
  }
  answer_set_memory(*strategy_, rq.memory, rs);
  return true;
}

void RateControllerNode::on_index(const virtual_triaxial::MomentIndex::ConstPtr& msg) {
  const std::lock_guard<std::recursive_mutex> lock(mutex_);
  if (!claimed_ || !strategy_ || msg->tick <= claim_tick_) return;  // states before the claim need no answer
  double rate = 0.0;
  try {
    control::RateInput in;
    in.moment_index = msg->moment_index;
    in.quasi_static_threshold = threshold_;
    rate = strategy_->update(in);
  } catch (const std::exception& e) {
    ROS_ERROR_THROTTLE(1.0, "rate_controller_node: tick %llu: no command: %s",
                       static_cast<unsigned long long>(msg->tick), e.what());
    return;
  }
  virtual_triaxial::CellCommand cmd;
  cmd.header = msg->header;
  cmd.tick = msg->tick;
  cmd.owner = owner_;
  cmd.axes.push_back(static_cast<std::uint8_t>(axis_));
  cmd.strain_rate.push_back(rate);
  command_pub_.publish(boost::make_shared<virtual_triaxial::CellCommand>(std::move(cmd)));
  virtual_triaxial::RateState st;
  st.header = msg->header;
  st.tick = msg->tick;
  st.strategy = strategy_->name();
  st.axis = static_cast<std::uint8_t>(axis_);
  st.moment_index = msg->moment_index;
  st.strain_rate = rate;
  st.strain_rate_dimensionless = rate * t0_;
  state_pub_.publish(st);
}

}  // namespace vt::ros
