// One test run by test_protocol_node on the rig: the ROS calls that set up
// each stage on a paused dem_node and the per-tick loop that feeds the
// ROS-free stage judge (protocol/stage_judge.h, the same as triax_run's). See
// test_protocol_node.h for the protocol of pausing and lockstep.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>

#include <ros/ros.h>

#include "virtual_triaxial/ProtocolStatus.h"
#include "virtual_triaxial/RunTestAction.h"
#include "virtual_triaxial/io/results_recorder.h"
#include "virtual_triaxial/io/run_summary_json.h"
#include "virtual_triaxial/io/scene_config.h"
#include "virtual_triaxial/protocol/stage_judge.h"
#include "virtual_triaxial/protocol/stage_runner.h"
#include "virtual_triaxial/ros/tick_collector.h"

namespace vt::ros {

/// A refused request or a rig that does not answer; what() names the field
/// or the service.
class RigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The decision on one control tick of a stage (the ROS-free stage judge's).
using TickDecision = protocol::TickDecision;

/// Decides tick k from its complete state. The node calls it exactly once
/// per tick, in tick order, as soon as the tick's five messages are in,
/// possibly in another thread (never concurrently with itself); when the
/// stage goes on the node answers the tick at once, so dem_node does not
/// wait for the session's bookkeeping (recording, feedback).
using TickJudge = std::function<TickDecision(std::uint64_t tick, const TickMessages& msgs)>;

/// A tick as the session receives it: its state, the judge's decision and
/// whether the node has already answered it (never when the stage ends).
struct JudgedTick {
  TickMessages msgs;
  TickDecision decision;
  bool answered = false;
};

/// How the session talks to its node.
struct SessionLinks {
  /// The next judged tick; nullopt when none came within `seconds` (or the node stops).
  std::function<std::optional<JudgedTick>(std::uint64_t tick, double seconds)> wait_tick;
  /// Wall seconds without a tick after which the session asks dem_node why.
  double tick_timeout = 30.0;
  /// Installs the judge for the ticks after `start` (a null judge: none).
  std::function<void(TickJudge, std::uint64_t start)> arm;
  std::function<const char*()> stop_request;   ///< nullptr, "aborted" or "preempted"
  std::function<void(std::uint64_t)> answer;   ///< empty cell_command for a tick
  std::function<void(const virtual_triaxial::RunTestFeedback&)> feedback;
  std::function<void(const virtual_triaxial::ProtocolStatus&)> status;
};

class ProtocolSession {
 public:
  ProtocolSession(const ::ros::NodeHandle& nh, std::string servo, std::string owner, double rig_timeout);

  /// Runs every stage of `scene` (loaded from `protocol_path`) on the rig.
  /// Throws RigError when the rig refuses or does not answer during set-up;
  /// failures during the run end up in the report's verdict.
  protocol::RunReport run(const io::SceneConfig& scene, const std::string& protocol_path,
                          io::ResultsRecorder& recorder, SessionLinks& links);
  /// Name of the rate controller node (rate_controller_node.h) that commands
  /// the axial rate of stages with a `predicted` or `adaptive` rate strategy.
  void set_rate_controller(std::string name) { rate_controller_ = std::move(name); }
  /// Folder for the per-stage checkpoints after_<i>_<stage>.h5 ("" = none).
  void set_checkpoint_dir(std::string dir) { checkpoint_dir_ = std::move(dir); }
  /// Specimen facts for the summary (valid after run()).
  const io::RunContext& context() const { return ctx_; }
  /// Verdict word for the action result ("preempted" is not a RunReport verdict).
  const std::string& verdict_word() const { return verdict_word_; }

 private:
  template <class Srv>
  void call(const std::string& name, Srv& srv);
  void trigger(const std::string& name);
  std::uint64_t current_tick();
  /// control.servo -> the servo's dynamic_reconfigure (if it has one).
  void tune_servo();
  void configure_stage(const protocol::StageSpec& st, const protocol::StageJudge& judge);
  /// The rate controller's ~configure + ~enable for a stage whose strategy is not `fixed`.
  void start_rate_controller(const protocol::StageSpec& st, const protocol::StageJudge& judge);
  /// The judge of stage `st`, with the specimen as dem_node has it now.
  protocol::StageJudge make_judge(const protocol::StageSpec& st);
  /// false when the run must end (report updated)
  bool run_stage(const protocol::StageSpec& st, std::size_t index, std::size_t count, io::ResultsRecorder& recorder,
                 SessionLinks& links, protocol::RunReport& report);
  void finish_rig();
  /// "" while dem_node (and, with `servo_too`, the servo) has a live process
  /// behind its services; else which one died. A TCP connect per call.
  std::string dead_node(bool servo_too) const;
  /// The next tick, probing the nodes every kProbeSeconds without one; on
  /// nullopt `dead` names the node that died ("" = tick_timeout passed).
  std::optional<JudgedTick> next_tick(std::uint64_t want, bool servo_stage, SessionLinks& links, std::string& dead);
  static constexpr double kProbeSeconds = 1.0;

  ::ros::NodeHandle nh_;
  std::string servo_, owner_;
  std::string rate_controller_ = "rate_controller";
  bool rate_controller_on_ = false;  ///< enabled by this session (disable at the next stage / the end)
  double rig_timeout_;
  const io::SceneConfig* scene_ = nullptr;
  io::RunContext ctx_;
  std::uint32_t publish_every_ = 1;
  std::uint64_t tick_ = 0;  ///< last tick answered (or the tick the rig paused at)
  std::string verdict_word_ = "completed";
  std::string protocol_name_;
  std::string checkpoint_dir_;
  bool dem_dead_ = false, servo_dead_ = false;  ///< found dead: no more calls to it
  std::uint64_t timeouts_at_start_ = 0;         ///< dem_node's lockstep timeouts before the test
};

}  // namespace vt::ros
