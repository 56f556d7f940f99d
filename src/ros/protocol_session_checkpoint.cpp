// ProtocolSession: checkpoints inside a stage on the rig and what a resume
// needs from the controllers. See protocol_session.h. The checkpoint is the
// headless runner's (protocol/run_checkpoint.h, io/checkpoint_file.h) plus
// the rig's fields: dem_node's tick and the controller nodes' memories.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <thread>

#include <std_srvs/Trigger.h>

#include "virtual_triaxial/GetMemory.h"
#include "virtual_triaxial/SaveSample.h"
#include "virtual_triaxial/SetMemory.h"
#include "virtual_triaxial/io/sample_file.h"
#include "virtual_triaxial/ros/protocol_session.h"

namespace vt::ros {

namespace {
double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}
}  // namespace

bool ProtocolSession::controller_memory(const std::string& node, std::vector<double>& memory) {
  const std::string name = node + "/get_memory";
  if (!::ros::service::exists(nh_.resolveName(name), false)) {
    ROS_WARN("test_protocol_node: %s: no such service (a controller without a memory service, e.g. a Python "
             "one): no checkpoints inside stages in this test, so it cannot be resumed",
             nh_.resolveName(name).c_str());
    return false;
  }
  virtual_triaxial::GetMemory m;
  call(name, m);
  memory = m.response.memory;
  return true;
}

void ProtocolSession::restore_controller_memory(const std::string& node, const std::vector<double>& memory) {
  const std::string name = node + "/set_memory";
  if (!::ros::service::exists(nh_.resolveName(name), false) &&
      !nh_.serviceClient<virtual_triaxial::SetMemory>(name).waitForExistence(::ros::Duration(rig_timeout_)))
    throw RigError("resume: " + nh_.resolveName(name) +
                   ": no such service (this controller cannot be resumed; run the test again, or resume with "
                   "the C++ controller nodes)");
  virtual_triaxial::SetMemory s;
  s.request.memory = memory;
  call(name, s);
}

void ProtocolSession::take_checkpoint(std::size_t index, std::int64_t stage_steps, const protocol::StageJudge& judge,
                                      const protocol::RunReport& report, io::ResultsRecorder& recorder) {
  const auto t0 = std::chrono::steady_clock::now();
  try {
    // The next tick's rates: once every owner's command for tick_ is in.
    virtual_triaxial::GetInfo info;
    while (true) {
      call("get_info", info);
      if (info.response.answered_tick >= tick_) break;
      if (seconds_since(t0) > rig_timeout_)
        throw RigError("dem_node did not get every command for tick " + std::to_string(tick_) + " within " +
                       std::to_string(rig_timeout_) + " s");
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    const double rates[3] = {info.response.strain_rate[0], info.response.strain_rate[1],
                             info.response.strain_rate[2]};
    protocol::RunCheckpoint c = protocol::checkpoint_of(index, stage_steps, rates, report,
                                                        wall_before_ + seconds_since(t_start_), judge, specimen_,
                                                        judge.boundary().any_servo());
    if (c.servo && !controller_memory(servo_, c.servo_memory)) {
      schedule_.reset();
      return;
    }
    if (rate_controller_on_ && !controller_memory(rate_controller_, c.rate_controller_memory)) {
      schedule_.reset();
      return;
    }
    c.rig_tick = tick_;
    c.lockstep_timeouts =
        timeouts_before_ + static_cast<std::int64_t>(info.response.lockstep_timeouts - timeouts_at_start_);
    // Everything recorded up to this tick into a closed bag (a killed
    // recorder loses the chunk it holds in memory; the resumed run records
    // only the ticks after the checkpoint).
    if (const std::string split = nh_.resolveName(bag_recorder_ + "/split"); ::ros::service::exists(split, false)) {
      // Called once: a split made again would add an empty bag. A failed
      // call is the recorder's business, not the test's.
      std_srvs::Trigger t;
      ::ros::ServiceClient c = nh_.serviceClient<std_srvs::Trigger>(split);
      if (!c.call(t) || !t.response.success)
        ROS_WARN("test_protocol_node: checkpoint: %s: %s", split.c_str(),
                 t.response.message.empty() ? "call failed" : t.response.message.c_str());
    }
    // dem_node's state, through a sample file beside the checkpoint.
    const std::string state_file = run_checkpoint_ + ".state.h5";
    virtual_triaxial::SaveSample save;
    save.request.path = state_file;
    call("save_sample", save);
    io::CheckpointFile f;
    f.state = io::read_sample(state_file);
    std::error_code ec;
    std::filesystem::remove(state_file, ec);
    f.run = c;
    f.scene_path = protocol_path_;
    f.scene_text = scene_text_;
    const std::string where = "stage " + std::to_string(index) + " at stage step " + std::to_string(stage_steps) +
                              ", tick " + std::to_string(tick_);
    recorder.flush_partial("the test stopped after its checkpoint (" + where + "); run_triaxial.sh --resume " +
                           std::filesystem::path(run_checkpoint_).parent_path().string() + " continues it");
    f.results_rows = static_cast<std::int64_t>(recorder.rows());
    io::write_checkpoint(run_checkpoint_, f);
    ++checkpoints_written_;
    const double cost = seconds_since(t0);
    schedule_->done(cost);
    ROS_INFO("test_protocol_node: checkpoint %s (%s, %lld samples; %.3f s)", run_checkpoint_.c_str(), where.c_str(),
             static_cast<long long>(f.results_rows), cost);
  } catch (const std::exception& e) {
    ROS_ERROR("test_protocol_node: checkpoint after tick %llu failed, no more checkpoints in this test: %s",
              static_cast<unsigned long long>(tick_), e.what());
    schedule_.reset();
  }
}

}  // namespace vt::ros
