// test_protocol_node: the test operator of the virtual rig (DESIGN §6). Runs a
// YAML protocol (config/protocols/, the scene format of config/scenes/README.md)
// on dem_node + a servo controller, the way an operator drives a physical
// triaxial machine; a thin adapter over the ROS-free protocol library
// (protocol/stage_spec.h: stage boundaries, protocol/stage_monitor.h: stop
// criteria, protocol/shear_summary.h), so it takes the same decisions on the
// same ticks as the headless `triax_run` on the same file.
//
// Parameters (private, `~`):
//   output_dir    "protocol_output"  default folder for results.h5 / summary.json
//                 (relative to the working directory, ROS_HOME under roslaunch)
//   servo         "servo"   name of the servo controller node (its private
//                           services servo/set_axes, enable, disable,
//                           set_confining_pressure)
//   rate_controller "rate_controller"  name of the rate controller node
//                           (rate_controller_node.h) that commands the axial
//                           rate of stages with rate.strategy predicted or
//                           adaptive (its ~configure, ~enable, ~disable)
//   bag_recorder "bag_recorder"  name of the rig's recorder (ros/bag_recorder.h):
//                           its ~split is called at every checkpoint (none: skipped)
//   tick_timeout  30.0      wall seconds to wait for the state of the next tick
//                           before asking dem_node whether it failed
//   rig_timeout   20.0      wall seconds to wait for dem_node / servo services
//
// Interface (relative to the rig's namespace):
//   action  run_test (virtual_triaxial/RunTest): goal = protocol file or YAML
//           text; feedback = stage, eps_a, q, p, e, I_mom (throttled to
//           ~4 Hz); result = the test summary. Cancelling the goal preempts
//           the test: it stops at the next tick, the summary says "preempted".
//   service ~abort (std_srvs/Trigger): ends the running test at the next tick
//           with the verdict "aborted".
//   service ~predict_quasi_static (virtual_triaxial/PredictQuasiStatic): the
//           eq. 83-85 prediction of eps'_QS and the shear stage's run plan
//           for a protocol's sample (default: the last test's protocol),
//           as `triax_qs predict` (ros/qs_advice_service.h). The result of a
//           test states the I_QS of its quasi-static verdict
//           (quasi_static_threshold).
//   topic   protocol_status (virtual_triaxial/ProtocolStatus) on sample ticks
//           and at every change of state (a stage start with the tick it
//           starts after, none when a stage is resumed; the verdict as the
//           last tick's status with the final state).
//
// Lockstep: at the start of a test the node registers with dem_node as a
// lockstep participant without axes (claim_axes with no axes), so dem_node
// waits for its (empty) cell_command every tick. When a stage ends on tick k
// it calls `pause` BEFORE answering tick k, so dem_node halts exactly after
// tick k whatever the machine load; it then reconfigures the rig (reset_strain,
// set_strain_rate on the open-loop axes, servo set_axes / enable / disable /
// set_confining_pressure) and resumes. A test therefore is deterministic.
// The stop criteria of a tick are judged as soon as its five messages are in,
// in the thread that delivers them (ros/inline_callback_queue.h; in the
// nodelet rig dem_node's own thread, inside its publish), and a tick on which
// the stage goes on is answered right there; the session's thread records
// and reports the ticks behind it (at most kMaxLag ticks behind, else the
// answers wait for it). So the lockstep loop has no thread hand-off.
//
// Per test: pause, load_sample(protocol file) (dem_node builds the specimen
// exactly as triax_run would), then the stages; the summary (phi_peak,
// eps_peak, phi_end, e0, mean I_mom to the peak, quasi-static verdict against
// control.quasi_static_threshold, runtime, steps, ticks) goes to
// <output_dir>/results.h5 (time series of the sample ticks + attributes), to
// <output_dir>/summary.json and into the action result. After every stage
// (also a preempted or aborted one) the paused rig saves its state to
// <output_dir>/checkpoints/after_<i>_<stage>.h5, from which a test continues
// bit for bit (e.g. a protocol whose particles.sample_file is that file). The rig is left
// paused with every axis open loop at rate 0.
// Inside a stage, on a sample tick when a checkpoint is due
// (protocol/checkpoint_schedule.h, output.checkpoint_ticks / _seconds), the
// tick is held like a stage's last one: pause, answer, then the checkpoint
// <output_dir>/results.h5.checkpoint.h5 (protocol_session_checkpoint.cpp),
// then resume. A goal with `resume` (a checkpoint) continues that test
// (run_triaxial.sh --resume): dem_node loads the checkpoint's state and
// tick, the finished stages are skipped, judge and controllers get their
// memories back, results.h5 is re-opened at the checkpoint's sample count.
// Bad goals (no or two protocols, a protocol that fails validation, a
// control.interval that differs from dem_node's publish_every) are refused
// with the field named; the node keeps serving. One test at a time: a goal
// that arrives while a test runs is rejected (cancel the running one first).
// Goals are not ordered by their stamps (actionlib's SimpleActionServer
// recalls a goal stamped before the previous one, and the rig's simulation
// time, which stamps the goals under use_sim_time, restarts at every
// load_sample).
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include <actionlib/server/action_server.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>

#include "virtual_triaxial/PredictQuasiStatic.h"
#include "virtual_triaxial/RunTestAction.h"
#include "virtual_triaxial/io/scene_config.h"
#include "virtual_triaxial/protocol/stage_runner.h"
#include "virtual_triaxial/ros/inline_callback_queue.h"
#include "virtual_triaxial/ros/protocol_session.h"
#include "virtual_triaxial/ros/tick_collector.h"

namespace vt::ros {

class TestProtocolNode {
 public:
  TestProtocolNode(const ::ros::NodeHandle& nh, const ::ros::NodeHandle& pnh);
  ~TestProtocolNode();

 private:
  using GoalHandle = actionlib::ServerGoalHandle<virtual_triaxial::RunTestAction>;
  void on_goal(GoalHandle goal);
  void on_cancel(GoalHandle goal);
  void execute(GoalHandle goal);  ///< in worker_
  /// The judged state of `tick`, or nullopt after `seconds` (or when stopped).
  std::optional<JudgedTick> wait_tick(std::uint64_t tick, double seconds);
  /// A state message (any thread): collect it; judge the ticks now complete.
  template <class M>
  void on_state(const M& m);
  void judge_ready();  ///< tick_mutex_ held
  void arm(TickJudge judge, std::uint64_t start);
  void answer(std::uint64_t tick);  ///< empty cell_command for `tick`
  bool on_abort(std_srvs::Trigger::Request& rq, std_srvs::Trigger::Response& rs);
  bool on_predict(virtual_triaxial::PredictQuasiStatic::Request& rq,
                  virtual_triaxial::PredictQuasiStatic::Response& rs);

  ::ros::NodeHandle nh_, pnh_;
  ::ros::NodeHandle tick_nh_;         ///< nh_ on inline_queue_ (state subscriptions)
  ::ros::CallbackQueue tick_queue_;   ///< fallback of inline_queue_; spun by the executing test
  InlineCallbackQueue inline_queue_{tick_queue_, nullptr};
  std::string output_dir_, servo_, rate_controller_, bag_recorder_;
  double tick_timeout_ = 30.0, rig_timeout_ = 20.0;
  /// Ticks judged ahead of the session at most (bounds memory and keeps the
  /// collector's window, 64 ticks, ahead of the session).
  static constexpr std::uint64_t kMaxLag = 32;
  std::mutex tick_mutex_;             ///< guards the members down to judged_
  std::condition_variable tick_cv_;   ///< a tick was judged
  TickCollector ticks_;
  TickJudge judge_;                   ///< the running stage's; null between stages
  std::uint64_t judge_next_ = 0;      ///< next tick to judge
  std::uint64_t taken_ = 0;           ///< last tick the session took
  std::map<std::uint64_t, JudgedTick> judged_;  ///< judged, not yet taken
  std::atomic<bool> abort_{false};
  std::atomic<bool> running_{false};
  std::atomic<bool> preempt_{false};
  std::atomic<bool> shutdown_{false};  ///< set by the destructor: wait_tick gives up
  std::mutex goal_mutex_;   ///< guards current_ and worker_
  GoalHandle current_;      ///< the goal being executed
  std::thread worker_;      ///< runs execute()

  actionlib::ActionServer<virtual_triaxial::RunTestAction> server_;
  ::ros::Publisher status_pub_, command_pub_;
  ::ros::Subscriber stress_sub_, strain_sub_, moment_sub_, energy_sub_, fabric_sub_;
  ::ros::ServiceServer abort_srv_, predict_srv_;
  std::mutex protocol_mutex_;   ///< guards last_protocol_
  std::string last_protocol_;   ///< the protocol file of the last goal
};

}  // namespace vt::ros
