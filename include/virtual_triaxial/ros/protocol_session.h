// One test run by test_protocol_node on the rig: the ROS calls that set up
// each stage on a paused dem_node and the per-tick loop that feeds the
// ROS-free stage judge (protocol/stage_judge.h, the same as triax_run's). See
// test_protocol_node.h for the protocol of pausing and lockstep.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <ros/ros.h>

#include "virtual_triaxial/GetInfo.h"
#include "virtual_triaxial/ProtocolStatus.h"
#include "virtual_triaxial/RunTestAction.h"
#include "virtual_triaxial/io/checkpoint_file.h"
#include "virtual_triaxial/io/results_recorder.h"
#include "virtual_triaxial/io/run_summary_json.h"
#include "virtual_triaxial/io/scene_config.h"
#include "virtual_triaxial/protocol/checkpoint_schedule.h"
#include "virtual_triaxial/protocol/stage_judge.h"
#include "virtual_triaxial/protocol/stage_runner.h"
#include "virtual_triaxial/ros/idempotent_call.h"
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

/// The judge's answer on one tick: its decision, and `hold` when the session
/// takes a checkpoint after this tick (a sample tick on which the stage goes
/// on): then the node does not answer it, the session does once dem_node is
/// paused, as on a stage's last tick.
struct TickVerdict {
  TickDecision decision;
  bool hold = false;
};

/// Decides tick k from its complete state. The node calls it exactly once
/// per tick, in tick order, as soon as the tick's five messages are in,
/// possibly in another thread (never concurrently with itself); when the
/// stage goes on (and no checkpoint is due) the node answers the tick at
/// once, so dem_node does not wait for the session's bookkeeping
/// (recording, feedback).
using TickJudge = std::function<TickVerdict(std::uint64_t tick, const TickMessages& msgs)>;

/// A tick as the session receives it: its state, the judge's decision and
/// whether the node has already answered it (never when the stage ends).
struct JudgedTick {
  TickMessages msgs;
  TickDecision decision;
  bool answered = false;
  bool hold = false;  ///< a checkpoint follows this tick (TickVerdict::hold)
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
  /// Calls of a service whose answer is lost, in all, and the pause between them.
  static constexpr CallRetry kSessionRetry{5, 0.2};

  ProtocolSession(const ::ros::NodeHandle& nh, std::string servo, std::string owner, double rig_timeout);

  /// Runs every stage of `scene` (loaded from `protocol_path`) on the rig.
  /// Throws RigError when the rig refuses or does not answer during set-up;
  /// failures during the run end up in the report's verdict. `resume`: go
  /// on from that checkpoint (read from `resume_path`; the recorder already
  /// holds its samples): dem_node loads its state and tick, the finished
  /// stages are skipped, the judge and the controllers get their memories back.
  protocol::RunReport run(const io::SceneConfig& scene, const std::string& protocol_path,
                          io::ResultsRecorder& recorder, SessionLinks& links,
                          const io::CheckpointFile* resume = nullptr, const std::string& resume_path = "");
  /// Checkpoints inside a stage (run_checkpoint.h) into `path` (the results
  /// file's io::checkpoint_path), at the scene's output.checkpoint_ticks /
  /// checkpoint_seconds (checkpoint_schedule.h); `scene_text` is the
  /// protocol file as the test read it. "" = none.
  void set_run_checkpoint(std::string path, std::string scene_text) {
    run_checkpoint_ = std::move(path);
    scene_text_ = std::move(scene_text);
  }
  /// Checkpoints written inside stages (valid after run()).
  int checkpoints_written() const { return checkpoints_written_; }
  /// Name of the rate controller node (rate_controller_node.h) that commands
  /// the axial rate of stages with a `predicted` or `adaptive` rate strategy.
  void set_rate_controller(std::string name) { rate_controller_ = std::move(name); }
  /// Name of the rig's bag recorder: its ~split at every checkpoint (none running: nothing).
  void set_bag_recorder(std::string name) { bag_recorder_ = std::move(name); }
  /// Folder for the per-stage checkpoints after_<i>_<stage>.h5 ("" = none).
  void set_checkpoint_dir(std::string dir) { checkpoint_dir_ = std::move(dir); }
  /// Specimen facts for the summary (valid after run()).
  const io::RunContext& context() const { return ctx_; }
  /// Verdict word for the action result ("preempted" is not a RunReport verdict).
  const std::string& verdict_word() const { return verdict_word_; }

 private:
  /// Calls a rig service (waits for it up to rig_timeout_, retries a failed
  /// call); throws RigError when it is not there or refuses (success false).
  template <class Srv>
  void call(const std::string& name, Srv& srv);
  /// `srv` on `c` (service `name`), made again when its answer is lost;
  /// RigError when no call is answered.
  template <class Srv>
  void call_answered(const std::string& name, ::ros::ServiceClient& c, Srv& srv);
  void trigger(const std::string& name);
  std::uint64_t current_tick();
  /// control.servo -> the servo's dynamic_reconfigure (if it has one).
  void tune_servo();
  /// `resume`: the stage goes on from that checkpoint (no strain reset, the
  /// checkpoint's rates, the controllers' memories restored).
  void configure_stage(const protocol::StageSpec& st, const protocol::StageJudge& judge,
                       const protocol::RunCheckpoint* resume);
  /// The stages of run() after the rig is set up (run() leaves the rig on a RigError).
  protocol::RunReport run_stages(const io::SceneConfig& scene, io::ResultsRecorder& recorder, SessionLinks& links,
                                 const io::CheckpointFile* resume, const std::string& resume_path);
  /// Enables the servo (when `servo`) and returns once it no longer answers
  /// "not claimed yet" and dem_node lists a closed-loop owner for every axis
  /// of `axes`; RigError naming the open axes after rig_timeout_.
  void await_controllers(const std::string& stage, const std::vector<int>& axes, bool servo);
  /// The rate controller's ~configure + ~enable for a stage whose strategy is not `fixed`.
  void start_rate_controller(const protocol::StageSpec& st, const protocol::StageJudge& judge);
  /// The judge of stage `st`, with the specimen as dem_node has it now (or
  /// as `at_start` says: a resumed stage); the specimen goes to specimen_.
  protocol::StageJudge make_judge(const protocol::StageSpec& st, const protocol::SpecimenAtStart* at_start = nullptr);
  /// false when the run must end (report updated)
  bool run_stage(const protocol::StageSpec& st, std::size_t index, std::size_t count, io::ResultsRecorder& recorder,
                 SessionLinks& links, protocol::RunReport& report, const protocol::RunCheckpoint* resume);
  // ---- checkpoints (protocol_session_checkpoint.cpp) ----
  /// Checkpoint after tick_ (dem_node paused, the tick answered, its sample
  /// recorded): the next rates once every owner answered, the controllers'
  /// memories, dem_node's state; results flushed first. A failure is logged
  /// and turns checkpoints off (the test goes on).
  void take_checkpoint(std::size_t index, std::int64_t stage_steps, const protocol::StageJudge& judge,
                       const protocol::RunReport& report, io::ResultsRecorder& recorder);
  /// A controller's ~get_memory; false (checkpoints off, logged) when it has none.
  bool controller_memory(const std::string& node, std::vector<double>& memory);
  /// ~set_memory of a controller on a resumed stage (throws RigError).
  void restore_controller_memory(const std::string& node, const std::vector<double>& memory);
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
  // checkpoints inside a stage
  std::string run_checkpoint_, scene_text_, protocol_path_;
  std::string bag_recorder_ = "bag_recorder";
  std::optional<protocol::CheckpointSchedule> schedule_;  ///< none: checkpoints off
  protocol::SpecimenAtStart specimen_;                   ///< the running stage's, at its start
  std::chrono::steady_clock::time_point t_start_;
  double wall_before_ = 0.0;                 ///< a resumed test's wall time before the resume [s]
  std::int64_t timeouts_before_ = 0;          ///< a resumed test's lockstep timeouts before the resume
  int checkpoints_written_ = 0;
};

template <class Srv>
void ProtocolSession::call_answered(const std::string& name, ::ros::ServiceClient& c, Srv& srv) {
  // The session's requests change nothing when made again (idempotent_call.h;
  // reset_strain, load_sample and set_memory because dem_node is paused
  // then), so a call whose answer is lost is made again before the test is
  // given up.
  const bool called = call_idempotent(c, srv, kSessionRetry, [&](int k) {
    ROS_WARN("test_protocol_node: %s: call failed, retrying (%d)", name.c_str(), k);
  }) > 0;
  if (!called) throw RigError(name + ": call failed (" + std::to_string(kSessionRetry.attempts) + " attempts)");
}

template <class Srv>
void ProtocolSession::call(const std::string& name, Srv& srv) {
  ::ros::ServiceClient c = nh_.serviceClient<Srv>(name);
  if (!c.waitForExistence(::ros::Duration(rig_timeout_)))
    throw RigError(name + ": service not available within " + std::to_string(rig_timeout_) + " s");
  call_answered(name, c, srv);
  if constexpr (!std::is_same_v<Srv, virtual_triaxial::GetInfo>) {
    if (!srv.response.success) throw RigError(name + " refused: " + srv.response.message);
  }
}

}  // namespace vt::ros
