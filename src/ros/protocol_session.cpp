// ProtocolSession: one test on the rig. See protocol_session.h.
#include "virtual_triaxial/ros/protocol_session.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include <dynamic_reconfigure/Reconfigure.h>
#include <std_srvs/Trigger.h>

#include "virtual_triaxial/ClaimAxes.h"
#include "virtual_triaxial/ConfigureRate.h"
#include "virtual_triaxial/GetInfo.h"
#include "virtual_triaxial/LoadSample.h"
#include "virtual_triaxial/ReleaseAxes.h"
#include "virtual_triaxial/SaveSample.h"
#include "virtual_triaxial/SetConfiningPressure.h"
#include "virtual_triaxial/SetServoAxes.h"
#include "virtual_triaxial/SetStrainRate.h"
#include "virtual_triaxial/io/number_text.h"
#include "virtual_triaxial/io/run_limits.h"
#include "virtual_triaxial/protocol/stage_judge.h"
#include "virtual_triaxial/ros/measure_messages.h"
#include "virtual_triaxial/ros/rig_reply_words.h"

namespace vt::ros {

namespace {
using Clock = std::chrono::steady_clock;

/// The stop criteria's view of a tick (UFR and contacts on sample ticks only).
protocol::TickSample tick_sample(const TickMessages& m, int axial_axis, std::int64_t steps, bool sample) {
  protocol::TickSample ts;
  ts.stage_steps = steps;
  ts.eps_a = m.strain->strain[static_cast<std::size_t>(axial_axis)];
  ts.p = m.stress->p;
  ts.q = m.stress->q;
  for (int i = 0; i < 3; ++i) ts.stress[i] = m.stress->stress[static_cast<std::size_t>(4 * i)];
  ts.moment_index = m.moment->moment_index;  // every tick (the adaptive rate strategy reads it)
  if (sample) {
    ts.ufr = m.moment->ufr;
    ts.contacts = static_cast<std::int64_t>(m.fabric->contacts);
  }
  return ts;
}
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }
}  // namespace

ProtocolSession::ProtocolSession(const ::ros::NodeHandle& nh, std::string servo, std::string owner,
                                 double rig_timeout)
    : nh_(nh), servo_(std::move(servo)), owner_(std::move(owner)), rig_timeout_(rig_timeout) {}

std::string ProtocolSession::dead_node(bool servo_too) const {
  // service::exists connects to the service's port: refused once the process
  // is gone (the master still lists a killed node's services). A stopped
  // process still accepts the connection: it only costs lockstep timeouts.
  if (!::ros::service::exists(nh_.resolveName("get_info"), false))
    return "dem_node died (" + nh_.resolveName("get_info") + " refuses connections)";
  if (servo_too && !::ros::service::exists(nh_.resolveName(servo_ + "/enable"), false))
    return servo_ + " died (" + nh_.resolveName(servo_ + "/enable") + " refuses connections)";
  return "";
}

std::optional<JudgedTick> ProtocolSession::next_tick(std::uint64_t want, bool servo_stage, SessionLinks& links,
                                                     std::string& dead) {
  const auto t_wait = Clock::now();
  while (true) {
    const double left = links.tick_timeout - seconds_since(t_wait);
    if (left <= 0) return std::nullopt;
    const double slice = std::min(left, kProbeSeconds);
    const auto t_slice = Clock::now();
    std::optional<JudgedTick> judged = links.wait_tick(want, slice);
    if (judged) return judged;
    if (seconds_since(t_slice) < 0.5 * slice) return std::nullopt;  // the node is shutting down
    dead = dead_node(servo_stage);
    if (!dead.empty()) {
      ROS_ERROR("test_protocol_node: %s while waiting for tick %llu", dead.c_str(),
                static_cast<unsigned long long>(want));
      dem_dead_ = dead.rfind("dem_node", 0) == 0;
      servo_dead_ = !dem_dead_;
      return std::nullopt;
    }
    // A numerical failure stops dem_node's ticks: report it now, not after tick_timeout.
    virtual_triaxial::GetInfo info;
    call("get_info", info);
    if (info.response.unstable) return std::nullopt;
  }
}

void ProtocolSession::trigger(const std::string& name) {
  std_srvs::Trigger t;
  call(name, t);
}

std::uint64_t ProtocolSession::current_tick() {
  virtual_triaxial::GetInfo info;
  call("get_info", info);
  return info.response.tick;
}

void ProtocolSession::tune_servo() {
  const protocol::ServoSettings& sv = scene_->control.servo;
  const std::string name = servo_ + "/set_parameters";
  ::ros::ServiceClient c = nh_.serviceClient<dynamic_reconfigure::Reconfigure>(name);
  if (!c.waitForExistence(::ros::Duration(1.0))) {
    ROS_WARN_ONCE("test_protocol_node: %s not available: the servo keeps its own tuning (the protocol asks for "
                  "%s, gain %g, ki %g)", name.c_str(), sv.strategy.c_str(), sv.parameters.gain, sv.parameters.ki);
    return;
  }
  dynamic_reconfigure::Reconfigure r;
  auto add = [&](const char* key, double v) {
    dynamic_reconfigure::DoubleParameter d;
    d.name = key;
    d.value = v;
    r.request.config.doubles.push_back(d);
  };
  add("gain", sv.parameters.gain);
  add("ki", sv.parameters.ki);
  add("kd", sv.parameters.kd);
  add("max_dimensionless_rate", sv.max_dimensionless_rate);
  add("max_rate_change", sv.max_dimensionless_rate_change);
  call_answered(name, c, r);  // setting the same values again changes nothing
  for (const auto& d : r.response.config.doubles)
    for (const auto& want : r.request.config.doubles)
      if (d.name == want.name && d.value != want.value)
        throw RigError("control.servo." + d.name + ": the servo refused " + std::to_string(want.value) +
                       " (keeps " + std::to_string(d.value) + "; see its log)");
}

protocol::StageJudge ProtocolSession::make_judge(const protocol::StageSpec& st,
                                                const protocol::SpecimenAtStart* at_start) {
  protocol::RunOptions options = scene_->run_options();
  options.control_interval = publish_every_;  // = control.interval, checked in run()
  virtual_triaxial::GetInfo info;
  call("get_info", info);
  options.young_modulus = info.response.young_modulus;
  specimen_.void_ratio = info.response.void_ratio;
  specimen_.dispersity_index = info.response.dispersity_index;
  if (at_start) specimen_ = *at_start;
  try {
    return protocol::StageJudge(st, options, ctx_.t0, specimen_);
  } catch (const std::invalid_argument& e) {
    throw RigError(e.what());
  }
}

void ProtocolSession::configure_stage(const protocol::StageSpec& st, const protocol::StageJudge& judge,
                                      const protocol::RunCheckpoint* resume) {
  const protocol::StageBoundary& b = judge.boundary();
  if (!resume) trigger("reset_strain");  // a resumed stage keeps its reference (in the checkpoint's state)
  trigger(servo_ + "/disable");
  if (rate_controller_on_) {
    trigger(rate_controller_ + "/disable");
    rate_controller_on_ = false;
  }
  // Open-loop rates first: a controller that claims an axis keeps its
  // open-loop rate until its first command (axis_arbiter.h), so the servo
  // axes start at 0 and the axial axis at the judge's first rate, as in triax_run;
  // a resumed stage's axes at the rates its checkpoint's next tick had.
  for (int a = 0; a < 3; ++a) {
    virtual_triaxial::SetStrainRate r;
    r.request.axis = static_cast<std::uint8_t>(a);
    r.request.strain_rate = b.servo[a] ? 0.0 : (a == st.axial_axis ? judge.first_axial_rate() : b.open_rate[a]);
    if (resume) r.request.strain_rate = resume->rates[a];
    r.request.dimensionless = false;
    call("set_strain_rate", r);
  }
  if (b.any_servo()) {
    tune_servo();
    virtual_triaxial::SetServoAxes axes;
    for (int a : b.servo_axes()) axes.request.axes.push_back(static_cast<std::uint8_t>(a));
    call(servo_ + "/set_axes", axes);
    virtual_triaxial::SetConfiningPressure cp;
    cp.request.target = st.confining_pressure.value_or(0.0);
    cp.request.ramp_seconds = 0.0;
    call(servo_ + "/set_confining_pressure", cp);
  }
  if (st.rate_spec.strategy != control::RateStrategyKind::Fixed) start_rate_controller(st, judge);
  std::vector<int> closed = b.servo_axes();
  if (rate_controller_on_) closed.push_back(st.axial_axis);
  await_controllers(st.name, closed, b.any_servo());
  // Memories last: a controller takes one only once it runs (claimed).
  if (resume && b.any_servo()) restore_controller_memory(servo_, resume->servo_memory);
  if (resume && rate_controller_on_) restore_controller_memory(rate_controller_, resume->rate_controller_memory);
}

void ProtocolSession::await_controllers(const std::string& stage, const std::vector<int>& axes, bool servo) {
  // The stage must not start before its controllers hold their axes: its
  // first tick would run open loop, and a claim made while dem_node runs
  // joins at a tick the wall clock picks. A servo's ~enable answers "... not
  // claimed yet (why), retrying" while its claim is pending
  // (servo_controller_node.h); asked again, it tries again at once (and
  // learns of a claim dem_node ran but whose answer it lost). A servo that
  // words it otherwise is still waited for through dem_node's owners.
  const auto t0 = Clock::now();
  while (true) {
    std::string pending;
    if (servo) {
      std_srvs::Trigger t;
      call(servo_ + "/enable", t);
      if (reply_words::says_not_claimed_yet(t.response.message)) pending = t.response.message;
    }
    virtual_triaxial::GetInfo info;
    call("get_info", info);
    std::string open;
    for (int a : axes)
      if (info.response.axis_owners[static_cast<std::size_t>(a)].empty())
        open += (open.empty() ? "" : ", ") + std::to_string(a);
    if (open.empty() && pending.empty()) return;
    if (seconds_since(t0) > rig_timeout_)
      throw RigError("stage '" + stage + "': " +
                     (open.empty() ? servo_ + "/enable still answers '" + pending + "'"
                                   : "cell axes " + open + " have no closed-loop owner") +
                     " " + io::number_text(rig_timeout_, 3) + " s after the controllers were enabled (is " +
                     servo_ + " claiming them? see its log)");
    ::ros::WallDuration(0.05).sleep();
  }
}

void ProtocolSession::start_rate_controller(const protocol::StageSpec& st, const protocol::StageJudge& judge) {
  const control::AdaptiveRateParameters& a = st.rate_spec.adaptive;
  virtual_triaxial::ConfigureRate c;
  c.request.strategy = control::to_string(st.rate_spec.strategy);
  c.request.axis = static_cast<std::uint8_t>(st.axial_axis);
  c.request.rate0 = judge.first_axial_rate();
  c.request.t0 = ctx_.t0;
  c.request.quasi_static_threshold = scene_->control.quasi_static_threshold;
  c.request.target = a.target;
  c.request.min_dimensionless = a.min_dimensionless;
  c.request.max_dimensionless = a.max_dimensionless;
  c.request.max_change = a.max_change;
  c.request.smoothing_ticks = a.smoothing_ticks;
  c.request.response_ticks = a.response_ticks;
  c.request.sensitivity = a.sensitivity;
  const std::string name = rate_controller_ + "/configure";
  if (!::ros::service::exists(nh_.resolveName(name), false) &&
      !nh_.serviceClient<virtual_triaxial::ConfigureRate>(name).waitForExistence(::ros::Duration(rig_timeout_)))
    throw RigError("stage '" + st.name + "' rate.strategy " + c.request.strategy + ": no rate controller node '" +
                   rate_controller_ + "' on the rig (start protocol_rig.launch with rate_node:=rate_controller_node "
                   "or py_rate_controller.py)");
  call(name, c);
  if (!c.response.success) throw RigError(rate_controller_ + "/configure refused: " + c.response.message);
  rate_controller_on_ = true;  // disabled by the next stage or finish_rig, even if ~enable fails
  std_srvs::Trigger t;
  call(rate_controller_ + "/enable", t);
  if (!t.response.success) throw RigError(rate_controller_ + "/enable failed: " + t.response.message);
}

protocol::RunReport ProtocolSession::run(const io::SceneConfig& scene, const std::string& protocol_path,
                                         io::ResultsRecorder& recorder, SessionLinks& links,
                                         const io::CheckpointFile* resume, const std::string& resume_path) {
  scene_ = &scene;
  protocol_path_ = protocol_path;
  protocol_name_ = std::filesystem::path(protocol_path).stem().string();
  t_start_ = Clock::now();
  virtual_triaxial::GetInfo info;
  call("get_info", info);
  if (static_cast<std::int64_t>(info.response.publish_every) != scene.control.interval)
    throw RigError("control.interval: the protocol asks for " + std::to_string(scene.control.interval) +
                   " DEM steps per control tick but dem_node runs publish_every = " +
                   std::to_string(info.response.publish_every) + " (start dem_node with ~publish_every " +
                   std::to_string(scene.control.interval) + ")");
  if (!info.response.lockstep)
    ROS_WARN("test_protocol_node: dem_node is free-running: stage changes are not tick-exact");
  publish_every_ = info.response.publish_every;
  timeouts_at_start_ = info.response.lockstep_timeouts;
  trigger("pause");
  virtual_triaxial::LoadSample load;
  load.request.path = resume ? resume_path : protocol_path;
  load.request.resume = resume != nullptr;
  if (resume) load.request.tick = resume->run.rig_tick;
  call("load_sample", load);
  call("get_info", info);
  ctx_.particles = info.response.particles;
  ctx_.t0 = info.response.t0;
  ctx_.dt = info.response.dt;
  ctx_.l0 = info.response.l0;
  if (const std::string bad = io::check_rate_limits(scene, ctx_.t0); !bad.empty()) throw RigError("protocol: " + bad);
  virtual_triaxial::ClaimAxes claim;  // lockstep participant, no axes
  claim.request.owner = owner_;
  call("claim_axes", claim);
  tick_ = claim.response.tick;
  try {
    return run_stages(scene, recorder, links, resume, resume_path);
  } catch (const RigError&) {
    finish_rig();  // controllers off, axes and our participant claim released, as after a test
    throw;
  }
}

protocol::RunReport ProtocolSession::run_stages(const io::SceneConfig& scene, io::ResultsRecorder& recorder,
                                                SessionLinks& links, const io::CheckpointFile* resume,
                                                const std::string& resume_path) {

  protocol::RunReport report;
  verdict_word_ = "completed";
  std::size_t first = 0;
  wall_before_ = 0.0;
  timeouts_before_ = 0;
  if (resume) {
    const protocol::RunCheckpoint& c = resume->run;
    if (c.stage_index >= scene.stages.size())
      throw RigError("resume: " + resume_path + ": stage " + std::to_string(c.stage_index) + " of a protocol with " +
                     std::to_string(scene.stages.size()) + " stages");
    first = c.stage_index;
    report.stages = c.finished;
    report.steps = c.steps;
    report.ticks = c.ticks;
    wall_before_ = c.wall_seconds;
    timeouts_before_ = c.lockstep_timeouts;
    ROS_INFO("test_protocol_node: resuming %s at stage '%s', stage step %lld (tick %llu)", protocol_name_.c_str(),
             scene.stages[first].name.c_str(), static_cast<long long>(c.stage_steps),
             static_cast<unsigned long long>(c.rig_tick));
  }
  const protocol::RunOptions options = scene.run_options();
  schedule_.reset();
  if (!run_checkpoint_.empty() && (options.checkpoint_ticks > 0 || options.checkpoint_seconds > 0))
    schedule_.emplace(options.checkpoint_ticks, options.checkpoint_seconds);
  checkpoints_written_ = 0;
  for (std::size_t i = first; i < scene.stages.size(); ++i)
    if (!run_stage(scene.stages[i], i, scene.stages.size(), recorder, links, report,
                   resume && i == first ? &resume->run : nullptr))
      break;
  finish_rig();
  report.wall_seconds = wall_before_ + seconds_since(t_start_);
  // The test has ended: nothing to resume, unless a node of the rig died
  // (then `run_triaxial.sh --resume` goes on from the last checkpoint).
  if (!run_checkpoint_.empty() && !dem_dead_ && !servo_dead_) {
    std::error_code ec;
    std::filesystem::remove(run_checkpoint_, ec);
  }
  return report;
}

void ProtocolSession::finish_rig() {
  if (dem_dead_) return;
  try {
    virtual_triaxial::GetInfo info;
    call("get_info", info);
    ctx_.lockstep_timeouts =
        timeouts_before_ + static_cast<std::int64_t>(info.response.lockstep_timeouts - timeouts_at_start_);
    ctx_.dt = info.response.dt;  // the step in force at the end (the contacts basis changes it), as triax_run's
    if (ctx_.lockstep_timeouts > 0)
      ROS_WARN("test_protocol_node: %lld lockstep timeouts during the test (a participant answered late; see "
               "/diagnostics)", static_cast<long long>(ctx_.lockstep_timeouts));
    if (!servo_dead_) trigger(servo_ + "/disable");
    if (rate_controller_on_) {
      rate_controller_on_ = false;
      trigger(rate_controller_ + "/disable");
    }
    for (int a = 0; a < 3; ++a) {
      virtual_triaxial::SetStrainRate r;
      r.request.axis = static_cast<std::uint8_t>(a);
      r.request.strain_rate = 0.0;
      call("set_strain_rate", r);
    }
    virtual_triaxial::ReleaseAxes rel;
    rel.request.owner = owner_;
    ::ros::ServiceClient c = nh_.serviceClient<virtual_triaxial::ReleaseAxes>("release_axes");
    const ReleaseAnswer a = call_release_axes(c, rel);
    if (!a.released)
      ROS_WARN("test_protocol_node: leaving the rig: release_axes: %s",
               a.answered ? a.refusal.c_str() : "dem_node does not answer");
  } catch (const RigError& e) {
    ROS_WARN("test_protocol_node: leaving the rig: %s", e.what());
  }
}

bool ProtocolSession::run_stage(const protocol::StageSpec& st, std::size_t index, std::size_t count,
                                io::ResultsRecorder& recorder, SessionLinks& links, protocol::RunReport& report,
                                const protocol::RunCheckpoint* resume) {
  const io::SceneConfig& scene = *scene_;
  protocol::StageJudge judge = make_judge(st, resume ? &resume->specimen : nullptr);
  if (resume) judge.restore_state(resume->judge);
  configure_stage(st, judge, resume);
  const bool external_rate = rate_controller_on_;  // the rate controller commands the axial axis
  const std::int64_t n = publish_every_;
  // The tick the stage started after (a resumed stage: as if it had run here).
  const std::uint64_t now = current_tick();
  const std::uint64_t start = resume ? now - static_cast<std::uint64_t>(resume->stage_steps / n) : now;
  tick_ = now;
  if (resume)
    ROS_INFO("test_protocol_node: [%s] resumed at stage step %lld (stage %zu of %zu)", st.name.c_str(),
             static_cast<long long>(resume->stage_steps), index + 1, count);
  else
    ROS_INFO("test_protocol_node: [%s] start: %s (stage %zu of %zu)", st.name.c_str(), protocol::to_string(st.type),
             index + 1, count);

  virtual_triaxial::ProtocolStatus status;
  status.tick = now;  // the stage starts after this tick
  status.protocol = protocol_name_;
  status.stage = st.name;
  status.stage_index = static_cast<std::uint32_t>(index);
  status.stage_count = static_cast<std::uint32_t>(count);
  status.state = "running";
  // A resumed stage is not started again: its recording continues the
  // killed run's (bag_report.py gives the uninterrupted run's table).
  if (!resume) links.status(status);

  // One tick judged by the stage judge (see TickJudge); it runs in the
  // node's tick thread and owns the judge's decide() side while the stage runs.
  const std::uint64_t stage_start = start;
  // A checkpoint is due on a sample tick the stage goes on from (checkpoint_schedule.h).
  auto decide = [&, stage_start, n, external_rate](std::uint64_t t, const TickMessages& m) {
    const std::int64_t steps = static_cast<std::int64_t>(t - stage_start) * n;
    protocol::TickSample ts = tick_sample(m, st.axial_axis, steps, judge.is_sample_tick(steps));
    if (external_rate) ts.applied_axial_rate = m.strain->strain_rate[static_cast<std::size_t>(st.axial_axis)];
    TickVerdict v;
    v.decision = judge.decide(ts, links.stop_request());
    if (schedule_) {
      schedule_->tick();
      v.hold = v.decision.kind == TickDecision::Kind::Continue && v.decision.sample_tick && schedule_->due();
    }
    return v;
  };
  links.arm(decide, now);
  struct Disarm {  // the judge refers to this frame's locals
    SessionLinks& l;
    ~Disarm() { l.arm(nullptr, 0); }
  } disarm{links};

  trigger("resume");
  auto t_feedback = Clock::now() - std::chrono::seconds(1);
  auto t_progress = Clock::now();
  std::uint64_t tick_progress = now;
  while (true) {
    const std::uint64_t want = tick_ + 1;
    std::string dead;
    std::optional<JudgedTick> judged = next_tick(want, judge.boundary().any_servo(), links, dead);
    if (!judged && !dead.empty()) {  // a verdict naming the node, not a hang
      const std::string failure =
          dead + " during stage '" + st.name + "' (no state for tick " + std::to_string(want) + ")";
      judge.fail(protocol::Verdict::Aborted, failure, failure);
      verdict_word_ = "failed";
      if (!dem_dead_) {
        try {
          trigger("pause");
        } catch (const RigError& e) {
          ROS_WARN("test_protocol_node: %s", e.what());
        }
      }
      break;
    }
    if (!judged) {
      virtual_triaxial::GetInfo info;
      call("get_info", info);
      if (info.response.unstable) {
        judge.fail(protocol::Verdict::Unstable, info.response.failure, "unstable: " + info.response.failure);
        verdict_word_ = "unstable";
      } else {
        const std::string failure = "no state for tick " + std::to_string(want) + " from dem_node in time";
        judge.fail(protocol::Verdict::Aborted, failure, failure);
        verdict_word_ = links.stop_request() ? links.stop_request() : "failed";
      }
      break;
    }
    tick_ = want;
    const TickMessages& m = judged->msgs;
    ctx_.energy_relative_balance_error = m.energy->relative_balance_error;
    const protocol::TickSample& ts = judged->decision.sample;  // as judged
    const std::int64_t steps = ts.stage_steps;
    const bool sample = judged->decision.sample_tick;
    const std::string why = judged->decision.why;
    if (judged->decision.kind == TickDecision::Kind::StepLimit) verdict_word_ = "step_limit";
    if (judged->decision.kind == TickDecision::Kind::Stop) verdict_word_ = why;
    const bool last = !why.empty();
    const bool hold = judged->hold && !last;  // a checkpoint after this tick
    if (last || hold) trigger("pause");  // before answering: dem_node halts right after this tick
    if (!judged->answered) links.answer(tick_);
    if (sample || last) {
      const dem::Measures measures =
          measures_from_messages(*m.stress, *m.strain, *m.moment, *m.energy, *m.fabric, steps);
      recorder.on_sample(st, measures);
      judge.record(measures, judged->decision);
    }
    ++report.ticks;

    status.header = m.stress->header;
    status.tick = tick_;
    status.eps_a = ts.eps_a;
    status.eps_v = m.strain->volumetric;
    status.p = ts.p;
    status.q = ts.q;
    status.e = m.fabric->void_ratio;
    status.moment_index = m.moment->moment_index;
    if (sample || last) {
      if (last) status.message = why;
      links.status(status);
    }
    if (last || seconds_since(t_feedback) >= 0.25) {
      virtual_triaxial::RunTestFeedback fb;
      fb.stage = st.name;
      fb.stage_index = static_cast<std::uint32_t>(index);
      fb.tick = tick_;
      fb.time = m.stress->time;
      fb.eps_a = ts.eps_a;
      fb.q = ts.q;
      fb.p = ts.p;
      fb.e = status.e;
      fb.moment_index = status.moment_index;
      links.feedback(fb);
      t_feedback = Clock::now();
    }
    if (seconds_since(t_progress) >= scene.output.progress_seconds) {
      const double rate = static_cast<double>((tick_ - tick_progress) * n) / seconds_since(t_progress);
      ROS_INFO("test_protocol_node: [%s] tick %llu  eps_a %.3f%%  eps_v %.3f%%  p %.1f kPa  q %.1f kPa  e %.4f  "
               "I_mom %.2e  (%.0f steps/s)",
               st.name.c_str(), static_cast<unsigned long long>(tick_), 100 * ts.eps_a, 100 * status.eps_v,
               ts.p / 1e3, ts.q / 1e3, status.e, status.moment_index, rate);
      t_progress = Clock::now();
      tick_progress = tick_;
    }
    if (hold) {  // after this tick's status (in the bag before its split)
      take_checkpoint(index, steps, judge, report, recorder);
      trigger("resume");
    }
    if (last) break;
  }
  const std::int64_t stage_steps = static_cast<std::int64_t>(tick_ - start) * n;
  if (!checkpoint_dir_.empty() && !dem_dead_) {  // the rig is paused: the state after the stage, restartable bit for bit
    virtual_triaxial::SaveSample save;
    save.request.path = checkpoint_dir_ + "/after_" + std::to_string(index) + "_" + st.name + ".h5";
    try {
      call("save_sample", save);
    } catch (const RigError& e) {
      ROS_WARN("test_protocol_node: checkpoint: %s", e.what());
    }
  }
  const bool go_on = judge.finish(stage_steps, report);
  const protocol::StageOutcome& out = report.stages.back();
  ROS_INFO("test_protocol_node: [%s] done after %lld steps: %s", st.name.c_str(), static_cast<long long>(out.steps),
           out.stop_reason.c_str());
  status.state = go_on ? "running" : verdict_word_;
  status.message = out.stop_reason;
  links.status(status);
  return go_on;
}

}  // namespace vt::ros
