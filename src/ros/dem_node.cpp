// DemNode: the DEM specimen as a ROS node. See dem_node.h.
#include "virtual_triaxial/ros/dem_node.h"

#include "virtual_triaxial/io/run_limits.h"
#include "virtual_triaxial/protocol/stage_judge.h"

#include <omp.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <boost/make_shared.hpp>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <rosgraph_msgs/Clock.h>

#include "virtual_triaxial/Fabric.h"
#include "virtual_triaxial/KineticEnergy.h"
#include "virtual_triaxial/MomentIndex.h"
#include "virtual_triaxial/Strain.h"
#include "virtual_triaxial/Stress.h"
#include "virtual_triaxial/dem/axis_stiffness.h"
#include "virtual_triaxial/dem/machine_load.h"
#include "virtual_triaxial/dem/mass_damping.h"
#include "virtual_triaxial/ros/measure_messages.h"
#include "virtual_triaxial/ros/parameters.h"

namespace vt::ros {

namespace {

/// Publisher queue per subscriber: deep enough that a recorder or test node
/// never loses a tick of a fast lockstep run (the messages are small, about
/// 100-200 B: 20 000 of them are a few MB at most). 1000 was not: in a
/// clean-build test run at nice 10 a test node that was not scheduled for a
/// moment lost one /stress message of a 1000-tick run (tests/rostest
/// protocol_rig, "tick ... of the run not received").
constexpr std::uint32_t kQueue = 20000;

constexpr const char* kUnits =
    "SI (m, kg, s, Pa, N, J, rad); stress, strain and strain rates compression positive; "
    "strain rates are logarithmic [1/s], eps' = rate * T0; header stamps are simulation time";

std::vector<int> to_axes(const std::vector<std::uint8_t>& a) { return {a.begin(), a.end()}; }

}  // namespace

DemNode::DemNode(const ::ros::NodeHandle& nh, const ::ros::NodeHandle& pnh) : nh_(nh), pnh_(pnh) {
  nh_.setCallbackQueue(&queue_);
  pnh_.setCallbackQueue(&queue_);
  views_ = std::make_unique<SpecimenViews>(nh_, pnh_);
  read_parameters();
  advertise();
  // pnh_ uses queue_: reconfigure requests are served between control ticks.
  reconfigure_ = std::make_unique<DemReconfigure>(pnh_, [this] { return sim_.get(); });
  last_diagnostics_ = ::ros::WallTime::now();
}

void DemNode::read_parameters() {
  const auto sample = optional_string(pnh_, "sample");
  const auto scene = optional_string(pnh_, "scene");
  if (sample.has_value() == scene.has_value())
    throw std::invalid_argument("~sample / ~scene: give exactly one (HDF5 sample file or YAML scene)");

  const int every = optional_int(pnh_, "publish_every").value_or(10);
  if (every < 1)
    throw std::invalid_argument("~publish_every: must be a whole number >= 1 (DEM steps per control tick)");
  publish_every_ = every;
  lockstep_ = optional_bool(pnh_, "lockstep").value_or(true);
  lockstep_timeout_ = optional_double(pnh_, "lockstep_timeout").value_or(2.0);
  if (!(std::isfinite(lockstep_timeout_) && lockstep_timeout_ > 0.0))
    throw std::invalid_argument("~lockstep_timeout: must be > 0 wall seconds");
  max_dimensionless_rate_ = optional_double(pnh_, "max_dimensionless_rate").value_or(io::RunLimits{}.max_dimensionless_rate);
  if (const double limit = io::RunLimits{}.max_dimensionless_rate;
      !(std::isfinite(max_dimensionless_rate_) && max_dimensionless_rate_ > 0.0 && max_dimensionless_rate_ <= limit)) {
    char b[160];
    std::snprintf(b, sizeof b, "~max_dimensionless_rate: must be > 0 and at most the run limit %g (io/run_limits.h)",
                  limit);
    throw std::invalid_argument(b);
  }
  const double clock_rate = optional_double(pnh_, "clock_rate").value_or(200.0);
  if (!(std::isfinite(clock_rate) && clock_rate >= 0.0))
    throw std::invalid_argument("~clock_rate: must be >= 0 Hz (0: every control tick)");
  clock_period_ = clock_rate > 0.0 ? 1.0 / clock_rate : 0.0;
  diagnostics_period_ = optional_double(pnh_, "diagnostics_period").value_or(1.0);
  if (!(std::isfinite(diagnostics_period_) && diagnostics_period_ > 0.0))
    throw std::invalid_argument("~diagnostics_period: must be > 0 wall seconds");
  paused_ = optional_bool(pnh_, "start_paused").value_or(false);
  // ~threads: OpenMP threads of the DEM steps; 0 (default) = chosen at run
  // time up to OMP_NUM_THREADS / every core (dem/thread_governor.h), so a
  // busy machine does not make the rig wait at barriers.
  threads_ = optional_int(pnh_, "threads").value_or(0);
  if (threads_ < 0) throw std::invalid_argument("~threads: must be >= 0 (0: chosen at run time)");

  SpecimenOverrides o;
  o.damping_model = optional_string(pnh_, "damping_model");
  o.damping_ratio = optional_double(pnh_, "damping_ratio");
  o.time_step_ratio = optional_double(pnh_, "time_step_ratio");
  const std::string bad = o.validate();
  if (!bad.empty()) throw std::invalid_argument("~" + bad);
  loader_ = std::make_unique<SpecimenLoader>(o);

  try {
    const bool yaml = sample && (sample->size() > 5 && (sample->compare(sample->size() - 5, 5, ".yaml") == 0 ||
                                                       sample->compare(sample->size() - 4, 4, ".yml") == 0));
    install(sample && !yaml ? loader_->load_sample(*sample) : loader_->load_scene(sample ? *sample : *scene));
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string(sample ? "~sample: " : "~scene: ") + e.what());
  }
}

void DemNode::install(Specimen s) {
  if (!s.warning.empty()) ROS_WARN("dem_node: %s: %s", s.source.c_str(), s.warning.c_str());
  arbiter_.set_limit(s.sim->time_scale().t0, max_dimensionless_rate_);
  sim_ = std::move(s.sim);
  if (threads_ == 0) sim_->set_thread_governor(dem::governor_on_this_machine(omp_get_max_threads()));
  meta_ = s.meta;
  source_ = s.source;
  arbiter_.reset_commands();
  if (reconfigure_) reconfigure_->sync();
  views_->on_load(*sim_, s.snapshot_interval, source_);
  ROS_INFO("dem_node: %zu particles from %s; T0 %.4g s, %s, %d steps per control tick, %s",
           sim_->particles().size(), source_.c_str(), sim_->time_scale().t0, dem::describe_time_step(*sim_).c_str(),
           publish_every_, lockstep_ ? "lockstep" : "free-running");
}

void DemNode::advertise() {
  stress_pub_ = nh_.advertise<virtual_triaxial::Stress>("stress", kQueue);
  strain_pub_ = nh_.advertise<virtual_triaxial::Strain>("strain", kQueue);
  moment_pub_ = nh_.advertise<virtual_triaxial::MomentIndex>("moment_index", kQueue);
  energy_pub_ = nh_.advertise<virtual_triaxial::KineticEnergy>("kinetic_energy", kQueue);
  fabric_pub_ = nh_.advertise<virtual_triaxial::Fabric>("fabric", kQueue);
  clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>("/clock", 10);
  diag_pub_ = nh_.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10);
  command_sub_ = nh_.subscribe("cell_command", kQueue, &DemNode::on_command, this,
                               ::ros::TransportHints().tcpNoDelay());
  services_.push_back(nh_.advertiseService("set_strain_rate", &DemNode::on_set_strain_rate, this));
  services_.push_back(nh_.advertiseService("claim_axes", &DemNode::on_claim, this));
  services_.push_back(nh_.advertiseService("release_axes", &DemNode::on_release, this));
  services_.push_back(nh_.advertiseService("get_info", &DemNode::on_get_info, this));
  services_.push_back(nh_.advertiseService("pause", &DemNode::on_pause, this));
  services_.push_back(nh_.advertiseService("resume", &DemNode::on_resume, this));
  services_.push_back(nh_.advertiseService("reset_strain", &DemNode::on_reset_strain, this));
  services_.push_back(nh_.advertiseService("step", &DemNode::on_step, this));
  services_.push_back(nh_.advertiseService("load_sample", &DemNode::on_load, this));
  services_.push_back(nh_.advertiseService("save_sample", &DemNode::on_save, this));
  services_.push_back(nh_.advertiseService("set_damping", &DemNode::on_set_damping, this));
  services_.push_back(nh_.advertiseService("set_friction", &DemNode::on_set_friction, this));
}

// ---- loop ---------------------------------------------------------------------------

bool DemNode::stepping() const { return !sim_->unstable() && (!paused_ || pending_ticks_ > 0); }

void DemNode::spin() {
  publish_clock();
  publish_diagnostics();
  while (::ros::ok() && !stop_) {
    queue_.callAvailable(stepping() ? ::ros::WallDuration(0) : ::ros::WallDuration(0.05));
    if ((::ros::WallTime::now() - last_diagnostics_).toSec() >= diagnostics_period_) {
      publish_diagnostics();
      if (!stepping()) publish_clock();  // late joiners on use_sim_time get a clock
    }
    if (!stepping()) continue;
    if (pending_ticks_ > 0) --pending_ticks_;
    run_tick();
  }
}

void DemNode::run_tick() {
  const dem::Vec3 rates = arbiter_.rates();  // compression positive, log strain
  const double dt = sim_->dt();
  dem::Vec3 l;
  for (int i = 0; i < 3; ++i) l[i] = std::expm1(-rates[i] * dt) / dt;
  sim_->set_strain_rates(l);
  const ::ros::WallTime t0 = ::ros::WallTime::now();
  if (threads_ > 0) omp_set_num_threads(threads_);  // in this (callback) thread
  for (int k = 0; k < publish_every_; ++k)
    if (!sim_->step(k == publish_every_ - 1)) break;
  if (sim_->unstable()) {
    pending_ticks_ = 0;
    ROS_ERROR("dem_node: numerical failure at step %lld, stepping stopped: %s",
              static_cast<long long>(sim_->steps()), sim_->failure().c_str());
    publish_diagnostics();
    return;
  }
  ++tick_;
  const ::ros::WallTime t1 = ::ros::WallTime::now();
  publish_state(rates);
  views_->on_tick(*sim_);
  if (clock_period_ <= 0.0 || (t1 - last_clock_).toSec() >= clock_period_) publish_clock();
  const ::ros::WallTime t2 = ::ros::WallTime::now();
  if (lockstep_) wait_for_commands();
  answered_tick_ = tick_;
  diag_.add_tick((t1 - t0).toSec(), (t2 - t1).toSec(), (::ros::WallTime::now() - t2).toSec());
}

void DemNode::wait_for_commands() {
  const ::ros::WallTime deadline = ::ros::WallTime::now() + ::ros::WallDuration(lockstep_timeout_);
  while (::ros::ok() && !stop_) {
    const std::vector<std::string> missing = arbiter_.missing_owners(tick_);
    if (missing.empty()) return;
    const ::ros::WallTime now = ::ros::WallTime::now();
    if (now >= deadline) {
      std::string names;
      for (const std::string& o : missing) {
        diag_.count_timeout(o);
        names += (names.empty() ? "" : ", ") + o;
      }
      ROS_WARN("dem_node: tick %llu: no cell_command from %s within %.3g s; holding the last command",
               static_cast<unsigned long long>(tick_), names.c_str(), lockstep_timeout_);
      publish_diagnostics();
      return;
    }
    const double left = (deadline - now).toSec();
    queue_.callAvailable(::ros::WallDuration(std::min(left, 0.01)));
  }
}

void DemNode::publish_state(const dem::Vec3& rates) {
  const dem::Measures m = sim_->measures();
  const TickStamp s{tick_, sim_->time()};
  const dem::Vec3 stiffness = dem::axis_stiffness(*sim_);
  const double period = sim_->dt() * publish_every_;
  // Shared pointers: subscribers in the same process (the nodelet rig) get
  // the message itself, neither serialised nor copied.
  stress_pub_.publish(
      boost::make_shared<virtual_triaxial::Stress>(to_stress_msg(m, s, period, sim_->settings().material.young, stiffness)));
  strain_pub_.publish(boost::make_shared<virtual_triaxial::Strain>(to_strain_msg(m, s, rates, sim_->time_scale().t0)));
  moment_pub_.publish(boost::make_shared<virtual_triaxial::MomentIndex>(to_moment_index_msg(m, s)));
  energy_pub_.publish(boost::make_shared<virtual_triaxial::KineticEnergy>(to_kinetic_energy_msg(m, s)));
  fabric_pub_.publish(boost::make_shared<virtual_triaxial::Fabric>(to_fabric_msg(m, s)));
}

void DemNode::publish_clock() {
  rosgraph_msgs::Clock c;
  c.clock.fromSec(sim_->time());
  clock_pub_.publish(c);
  last_clock_ = ::ros::WallTime::now();
}

void DemNode::publish_diagnostics() {
  DemStatus s;
  s.name = pnh_.getNamespace() + ": simulation";
  s.t0 = sim_->time_scale().t0;
  s.dt = sim_->dt();
  s.tick = tick_;
  s.step = sim_->steps();
  s.time = sim_->time();
  s.particles = sim_->particles().size();
  s.paused = paused_ && pending_ticks_ == 0;
  s.lockstep = lockstep_;
  s.unstable = sim_->unstable();
  s.failure = sim_->failure();
  last_diagnostics_ = ::ros::WallTime::now();
  diag_pub_.publish(diag_.report(s, last_diagnostics_));
}

// ---- callbacks ----------------------------------------------------------------------

void DemNode::on_command(const virtual_triaxial::CellCommand::ConstPtr& msg) {
  const std::string bad =
      arbiter_.command(msg->owner, msg->tick, to_axes(msg->axes), msg->strain_rate, tick_, lockstep_);
  if (!bad.empty()) {
    diag_.count_rejected("'" + msg->owner + "' tick " + std::to_string(msg->tick) + ": " + bad);
    ROS_WARN_THROTTLE(1.0, "dem_node: cell_command from '%s' refused: %s", msg->owner.c_str(), bad.c_str());
  }
}

bool DemNode::on_set_strain_rate(virtual_triaxial::SetStrainRate::Request& rq,
                                 virtual_triaxial::SetStrainRate::Response& rs) {
  const double rate = rq.dimensionless ? rq.strain_rate / sim_->time_scale().t0 : rq.strain_rate;
  rs.message = arbiter_.set_open_loop_rate(rq.axis, rate);
  rs.success = rs.message.empty();
  if (rs.success)
    rs.message = "axis " + std::to_string(rq.axis) + ": " + std::to_string(rate) + " 1/s (eps' " +
                 std::to_string(rate * sim_->time_scale().t0) + ") from the next control tick";
  return true;
}

bool DemNode::on_claim(virtual_triaxial::ClaimAxes::Request& rq, virtual_triaxial::ClaimAxes::Response& rs) {
  rs.message = arbiter_.claim(rq.owner, to_axes(rq.axes), tick_);
  rs.success = rs.message.empty();
  // A repeated claim answers its first claim's tick (axis_arbiter.h).
  rs.tick = rs.success ? arbiter_.answer_tick(rq.owner, tick_) : tick_;
  if (rs.success) rs.message = "claimed by '" + rq.owner + "'";
  return true;
}

bool DemNode::on_release(virtual_triaxial::ReleaseAxes::Request& rq, virtual_triaxial::ReleaseAxes::Response& rs) {
  rs.message = arbiter_.release(rq.owner, to_axes(rq.axes));
  rs.success = rs.message.empty();
  if (rs.success) rs.message = "released by '" + rq.owner + "' (open loop, rate 0)";
  return true;
}

bool DemNode::on_get_info(virtual_triaxial::GetInfo::Request&, virtual_triaxial::GetInfo::Response& rs) {
  const dem::TimeScale& ts = sim_->time_scale();
  const dem::SimulationSettings& st = sim_->settings();
  rs.t0 = ts.t0;
  rs.dt = sim_->dt();
  rs.l0 = ts.l0;
  rs.time_step_ratio = st.time_step_ratio;
  rs.particles = static_cast<std::uint32_t>(sim_->particles().size());
  rs.time = sim_->time();
  rs.tick = tick_;
  rs.answered_tick = answered_tick_;
  rs.step = sim_->steps();
  rs.publish_every = static_cast<std::uint32_t>(publish_every_);
  rs.lockstep = lockstep_;
  rs.paused = paused_;
  rs.unstable = sim_->unstable();
  rs.failure = sim_->failure();
  rs.units = kUnits;
  const dem::Vec3 r = arbiter_.rates();
  for (int i = 0; i < 3; ++i) {
    rs.axis_owners[static_cast<std::size_t>(i)] = arbiter_.owner(i);
    rs.strain_rate[static_cast<std::size_t>(i)] = r[i];
  }
  rs.max_dimensionless_rate = max_dimensionless_rate_;
  rs.damping_model = dem::to_string(st.damping.model());
  rs.damping_ratio = st.damping.ratio();
  rs.friction = st.material.friction;
  rs.density = st.material.density;
  rs.young_modulus = st.material.young;
  rs.poisson_ratio = st.material.poisson;
  rs.lockstep_timeouts = diag_.timeouts();
  rs.rejected_commands = diag_.rejected();
  rs.source = source_;
  const protocol::SpecimenAtStart specimen = protocol::specimen_at_start(*sim_);
  rs.void_ratio = specimen.void_ratio;
  rs.dispersity_index = specimen.dispersity_index;
  return true;
}

bool DemNode::on_pause(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& rs) {
  paused_ = true;
  pending_ticks_ = 0;
  rs.success = true;
  rs.message = "paused after tick " + std::to_string(tick_);
  publish_clock();  // the clock stands at the last tick's time
  views_->on_pause(*sim_);
  ROS_INFO("dem_node: paused after tick %llu; %s", static_cast<unsigned long long>(tick_),
           diag_.tick_summary().c_str());
  return true;
}

bool DemNode::on_resume(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& rs) {
  if (sim_->unstable()) {
    rs.success = false;
    rs.message = "unstable: " + sim_->failure() + " (load_sample to continue)";
    return true;
  }
  paused_ = false;
  rs.success = true;
  rs.message = "running from tick " + std::to_string(tick_);
  return true;
}

bool DemNode::on_reset_strain(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& rs) {
  sim_->reset_strain_reference();
  rs.success = true;
  rs.message = "strain reference reset at tick " + std::to_string(tick_);
  return true;
}

bool DemNode::on_step(virtual_triaxial::Step::Request& rq, virtual_triaxial::Step::Response& rs) {
  rs.success = false;
  if (rq.count == 0)
    rs.message = "count: must be >= 1";
  else if (!paused_)
    rs.message = "count: the node is running; call pause first";
  else if (sim_->unstable())
    rs.message = "count: unstable: " + sim_->failure() + " (load_sample to continue)";
  else {
    pending_ticks_ += rq.count;
    rs.success = true;
    rs.message = "queued " + std::to_string(rq.count) + " control tick(s) after tick " + std::to_string(tick_);
  }
  return true;
}

bool DemNode::on_load(virtual_triaxial::LoadSample::Request& rq, virtual_triaxial::LoadSample::Response& rs) {
  const auto ends_with = [&](const char* ext) {
    const std::string e(ext);
    return rq.path.size() >= e.size() && rq.path.compare(rq.path.size() - e.size(), e.size(), e) == 0;
  };
  try {
    if (rq.resume)
      install(loader_->load_checkpoint(rq.path));
    else
      install(ends_with(".yaml") || ends_with(".yml") ? loader_->load_scene(rq.path) : loader_->load_sample(rq.path));
  } catch (const std::exception& e) {
    rs.success = false;
    rs.message = std::string("path: ") + e.what();
    return true;
  }
  pending_ticks_ = 0;
  if (rq.resume) {
    tick_ = answered_tick_ = rq.tick;
    arbiter_.rewind(tick_);  // claims held across the load answer from the resumed tick on
    ROS_INFO("dem_node: resuming a test from %s: next tick %llu (step %lld)", rq.path.c_str(),
             static_cast<unsigned long long>(tick_ + 1), static_cast<long long>(sim_->steps()));
  }
  publish_clock();
  rs.success = true;
  rs.message = "loaded " + rq.path + " (" + std::to_string(sim_->particles().size()) + " particles)";
  return true;
}

bool DemNode::on_save(virtual_triaxial::SaveSample::Request& rq, virtual_triaxial::SaveSample::Response& rs) {
  if (rq.path.empty()) {
    rs.success = false;
    rs.message = "path: must not be empty";
    return true;
  }
  try {
    io::write_sample(rq.path, sim_->state(), meta_);
  } catch (const std::exception& e) {
    rs.success = false;
    rs.message = std::string("path: ") + e.what();
    return true;
  }
  rs.success = true;
  rs.message = "saved tick " + std::to_string(tick_) + " (step " + std::to_string(sim_->steps()) + ") to " + rq.path;
  if (sim_->unstable()) rs.message += " (WARNING: state after a numerical failure)";
  return true;
}

bool DemNode::on_set_damping(virtual_triaxial::SetDamping::Request& rq, virtual_triaxial::SetDamping::Response& rs) {
  dem::DampingModel model;
  rs.success = false;
  if (!dem::parse_damping_model(rq.model, model)) {
    rs.message = "model: '" + rq.model + "' is not " + dem::damping_model_names();
  } else if (const std::string bad = dem::damping_parameter_error(model, rq.ratio); !bad.empty()) {
    rs.message = "ratio: " + bad + " for damping model " + dem::to_string(model);
  } else {
    sim_->set_damping(dem::MassDamping(model, rq.ratio));
    if (reconfigure_) reconfigure_->sync();
    rs.success = true;
    rs.message = std::string("damping ") + dem::to_string(model) + " " + dem::damping_parameter_name(model) + " " +
                 std::to_string(rq.ratio);
  }
  return true;
}

bool DemNode::on_set_friction(virtual_triaxial::SetFriction::Request& rq, virtual_triaxial::SetFriction::Response& rs) {
  if (!(std::isfinite(rq.mu) && rq.mu >= 0.0)) {
    rs.success = false;
    rs.message = "mu: must be a finite number >= 0";
    return true;
  }
  sim_->set_friction(rq.mu);
  rs.success = true;
  rs.message = "friction " + std::to_string(rq.mu);
  return true;
}

}  // namespace vt::ros
