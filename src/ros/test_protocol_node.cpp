// TestProtocolNode: action plumbing around ProtocolSession. See test_protocol_node.h.
#include "virtual_triaxial/ros/test_protocol_node.h"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include <boost/make_shared.hpp>

#include "virtual_triaxial/CellCommand.h"
#include "virtual_triaxial/ProtocolStatus.h"
#include "virtual_triaxial/io/checkpoint_file.h"
#include "virtual_triaxial/io/checkpoint_recorder.h"
#include "virtual_triaxial/io/scene_error.h"
#include "virtual_triaxial/io/run_limits.h"
#include "virtual_triaxial/io/scene_parser.h"
#include "virtual_triaxial/io/text_file.h"
#include "virtual_triaxial/ros/parameters.h"
#include "virtual_triaxial/ros/protocol_session.h"
#include "virtual_triaxial/ros/qs_advice_service.h"

namespace vt::ros {

namespace fs = std::filesystem;

TestProtocolNode::TestProtocolNode(const ::ros::NodeHandle& nh, const ::ros::NodeHandle& pnh)
    : nh_(nh),
      pnh_(pnh),
      tick_nh_(nh),
      server_(nh_, "run_test", false) {
  pnh_.param<std::string>("output_dir", output_dir_, "protocol_output");
  pnh_.param<std::string>("servo", servo_, "servo");
  pnh_.param<std::string>("rate_controller", rate_controller_, "rate_controller");
  pnh_.param<std::string>("bag_recorder", bag_recorder_, "bag_recorder");
  tick_timeout_ = optional_double(pnh_, "tick_timeout").value_or(30.0);
  rig_timeout_ = optional_double(pnh_, "rig_timeout").value_or(20.0);
  if (!(tick_timeout_ > 0)) throw std::invalid_argument("~tick_timeout: must be > 0 s");
  if (!(rig_timeout_ > 0)) throw std::invalid_argument("~rig_timeout: must be > 0 s");
  if (servo_.empty()) throw std::invalid_argument("~servo: must name the servo controller node");

  // State messages are taken (and the tick judged) in the delivering thread.
  tick_nh_.setCallbackQueue(&inline_queue_);
  const auto hints = ::ros::TransportHints().tcpNoDelay();
  stress_sub_ = tick_nh_.subscribe<virtual_triaxial::Stress>(
      "stress", 200, [this](const virtual_triaxial::Stress::ConstPtr& m) { on_state(*m); }, {}, hints);
  strain_sub_ = tick_nh_.subscribe<virtual_triaxial::Strain>(
      "strain", 200, [this](const virtual_triaxial::Strain::ConstPtr& m) { on_state(*m); }, {}, hints);
  moment_sub_ = tick_nh_.subscribe<virtual_triaxial::MomentIndex>(
      "moment_index", 200, [this](const virtual_triaxial::MomentIndex::ConstPtr& m) { on_state(*m); }, {}, hints);
  energy_sub_ = tick_nh_.subscribe<virtual_triaxial::KineticEnergy>(
      "kinetic_energy", 200, [this](const virtual_triaxial::KineticEnergy::ConstPtr& m) { on_state(*m); }, {},
      hints);
  fabric_sub_ = tick_nh_.subscribe<virtual_triaxial::Fabric>(
      "fabric", 200, [this](const virtual_triaxial::Fabric::ConstPtr& m) { on_state(*m); }, {}, hints);
  // Latched, as the servo's: a late dem_node connection still gets the last answer.
  command_pub_ = nh_.advertise<virtual_triaxial::CellCommand>("cell_command", 1000, true);
  status_pub_ = nh_.advertise<virtual_triaxial::ProtocolStatus>("protocol_status", 1000, true);
  abort_srv_ = pnh_.advertiseService("abort", &TestProtocolNode::on_abort, this);
  predict_srv_ = pnh_.advertiseService("predict_quasi_static", &TestProtocolNode::on_predict, this);
  virtual_triaxial::ProtocolStatus idle;
  idle.state = "idle";
  status_pub_.publish(idle);
  server_.registerGoalCallback([this](GoalHandle g) { on_goal(g); });
  server_.registerCancelCallback([this](GoalHandle g) { on_cancel(g); });
  server_.start();
  ROS_INFO("test_protocol_node: ready (action %s, output %s)", nh_.resolveName("run_test").c_str(),
           output_dir_.c_str());
}

TestProtocolNode::~TestProtocolNode() {
  abort_ = true;
  shutdown_ = true;
  std::lock_guard<std::mutex> lock(goal_mutex_);
  if (worker_.joinable()) worker_.join();
}

void TestProtocolNode::on_goal(GoalHandle goal) {
  std::lock_guard<std::mutex> lock(goal_mutex_);
  if (running_) {
    virtual_triaxial::RunTestResult r;
    r.verdict = "failed";
    r.message = "goal: a test is running; cancel it (or call ~abort) first";
    ROS_ERROR("test_protocol_node: rejected a goal: %s", r.message.c_str());
    goal.setRejected(r, r.message);
    return;
  }
  if (worker_.joinable()) worker_.join();  // the previous test has ended (running_ is false)
  running_ = true;
  abort_ = false;
  preempt_ = false;
  current_ = goal;
  goal.setAccepted();
  worker_ = std::thread([this, goal] { execute(goal); });
}

void TestProtocolNode::on_cancel(GoalHandle goal) {
  std::lock_guard<std::mutex> lock(goal_mutex_);
  if (running_ && goal == current_) preempt_ = true;
}

bool TestProtocolNode::on_abort(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& rs) {
  if (!running_) {
    rs.success = false;
    rs.message = "no test is running";
    return true;
  }
  abort_ = true;
  rs.success = true;
  rs.message = "the test stops at the next control tick";
  return true;
}

bool TestProtocolNode::on_predict(virtual_triaxial::PredictQuasiStatic::Request& rq,
                                  virtual_triaxial::PredictQuasiStatic::Response& rs) {
  std::string path;
  if (!rq.protocol_file.empty() && !rq.protocol_yaml.empty()) {
    rs.message = "protocol_file: give at most one of protocol_file and protocol_yaml";
  } else if (!rq.protocol_file.empty()) {
    path = fs::absolute(rq.protocol_file).string();
  } else if (!rq.protocol_yaml.empty()) {
    const fs::path p = fs::absolute(output_dir_) / "predict_protocol.yaml";
    try {
      std::error_code ec;
      fs::create_directories(p.parent_path(), ec);
      io::write_text_atomic(p.string(), rq.protocol_yaml);
      path = p.string();
    } catch (const io::WriteError& e) {
      rs.message = std::string("protocol_yaml: ") + e.what();
    }
  } else {
    const std::lock_guard<std::mutex> lock(protocol_mutex_);
    path = last_protocol_;
    if (path.empty()) rs.message = "protocol_file: empty, and no test has run yet (give a protocol)";
  }
  if (path.empty()) {
    rs.success = false;
    return true;
  }
  answer_qs_advice(path, rq.cost_per_particle_step, rs);
  return true;
}

template <class M>
void TestProtocolNode::on_state(const M& m) {
  const std::lock_guard<std::mutex> lock(tick_mutex_);
  ticks_.add(m);
  judge_ready();
}

void TestProtocolNode::judge_ready() {
  while (judge_) {
    std::optional<TickMessages> msgs = ticks_.take(judge_next_);
    if (!msgs) return;
    JudgedTick j;
    j.msgs = std::move(*msgs);
    const TickVerdict v = judge_(judge_next_, j.msgs);
    j.decision = v.decision;
    j.hold = v.hold;
    // Answer at once unless the stage ends here or a checkpoint follows (the
    // session pauses dem_node first) or the session lags too far behind (it
    // answers when it catches up).
    if (j.decision.kind == TickDecision::Kind::Continue && !j.hold && judge_next_ <= taken_ + kMaxLag) {
      answer(judge_next_);
      j.answered = true;
    }
    // Wake the session only when dem_node waits for it; otherwise it picks
    // the tick up at its next poll (a wake-up call per tick would cost the
    // publishing thread, i.e. the lockstep loop, a system call).
    const bool waits = !j.answered;
    judged_.emplace(judge_next_, std::move(j));
    ++judge_next_;
    if (waits) tick_cv_.notify_all();
  }
}

void TestProtocolNode::arm(TickJudge judge, std::uint64_t start) {
  const std::lock_guard<std::mutex> lock(tick_mutex_);
  judge_ = std::move(judge);
  judge_next_ = start + 1;
  taken_ = start;
  judged_.clear();
  judge_ready();
}

void TestProtocolNode::answer(std::uint64_t tick) {
  // A shared pointer: a dem_node in the same process gets it in this call
  // (a copy would go through roscpp's network thread).
  auto c = boost::make_shared<virtual_triaxial::CellCommand>();
  c->tick = tick;
  c->owner = pnh_.getNamespace();
  command_pub_.publish(c);
}

std::optional<JudgedTick> TestProtocolNode::wait_tick(std::uint64_t tick, double seconds) {
  const ::ros::WallTime deadline = ::ros::WallTime::now() + ::ros::WallDuration(seconds);
  std::unique_lock<std::mutex> lock(tick_mutex_);
  while (::ros::ok() && !shutdown_) {
    const auto it = judged_.find(tick);
    if (it != judged_.end()) {
      JudgedTick out = std::move(it->second);
      judged_.erase(judged_.begin(), std::next(it));
      taken_ = tick;
      return out;
    }
    const ::ros::WallTime now = ::ros::WallTime::now();
    if (now >= deadline) return std::nullopt;
    // Callbacks the inline queue could not run at once (none in normal
    // operation) are served here.
    lock.unlock();
    tick_queue_.callAvailable(::ros::WallDuration(0));
    lock.lock();
    tick_cv_.wait_for(lock, std::chrono::milliseconds(2));  // poll: answered ticks do not notify
  }
  return std::nullopt;
}

namespace {

/// A file's contents ("" when it cannot be read).
std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The protocol file of a goal; writes inline YAML to <dir>/protocol.yaml.
std::string protocol_path(const virtual_triaxial::RunTestGoal& g, const fs::path& dir) {
  const bool file = !g.protocol_file.empty(), text = !g.protocol_yaml.empty();
  if (file == text)
    throw io::SceneError("goal", "give exactly one of protocol_file, protocol_yaml and resume");
  if (file) return fs::absolute(g.protocol_file).string();
  const fs::path p = dir / "protocol.yaml";
  try {
    io::write_text_atomic(p.string(), g.protocol_yaml);
  } catch (const io::WriteError& e) {
    throw io::SceneError("output_dir", e.what());
  }
  return p.string();
}

}  // namespace

void TestProtocolNode::execute(GoalHandle gh) {
  const boost::shared_ptr<const virtual_triaxial::RunTestGoal> goal = gh.getGoal();
  virtual_triaxial::RunTestResult result;
  const fs::path dir = fs::absolute(goal->output_dir.empty() ? output_dir_ : goal->output_dir);
  result.results_file = (dir / "results.h5").string();
  result.summary_file = (dir / "summary.json").string();
  auto refuse = [&](const std::string& verdict, const std::string& why) {
    result.verdict = verdict;
    result.message = why;
    ROS_ERROR("test_protocol_node: %s: %s", verdict.c_str(), why.c_str());
    virtual_triaxial::ProtocolStatus st;
    st.state = verdict;
    st.message = why;
    status_pub_.publish(st);
    running_ = false;
    gh.setAborted(result, why);
  };
  io::SceneConfig scene;
  std::string path, scene_text, resume_path;
  std::optional<io::CheckpointFile> resume;
  try {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw io::SceneError("output_dir", "cannot create " + dir.string() + ": " + ec.message());
    if (!goal->resume.empty()) {  // the checkpoint names the protocol; it must be unchanged
      if (!goal->protocol_file.empty() || !goal->protocol_yaml.empty())
        throw io::SceneError("goal", "give exactly one of protocol_file, protocol_yaml and resume");
      resume_path = fs::absolute(goal->resume).string();
      try {
        resume = io::read_checkpoint(resume_path);
      } catch (const std::exception& e) {
        throw io::SceneError("resume", e.what());
      }
      path = resume->scene_path;
      if (read_text(path) != resume->scene_text)
        throw io::SceneError("resume", path + ": changed since the checkpoint (the resumed test would not be the "
                                              "test that was run; start it again instead)");
    } else {
      path = protocol_path(*goal, dir);
    }
    scene_text = read_text(path);
    {
      const std::lock_guard<std::mutex> lock(protocol_mutex_);
      last_protocol_ = path;
    }
    scene = io::load_scene(path);
  } catch (const io::SceneError& e) {
    return refuse("failed", std::string("protocol: ") + e.what());
  }
  // The limits both runners share (io/run_limits.h); the rate limits once T0 is known.
  if (const std::string bad = io::check_scene_limits(scene); !bad.empty()) return refuse("failed", "protocol: " + bad);
  {
    const std::lock_guard<std::mutex> lock(tick_mutex_);
    ticks_.clear();
    judged_.clear();
    judge_ = nullptr;
  }
  tick_queue_.clear();
  ProtocolSession session(nh_, servo_, pnh_.getNamespace(), rig_timeout_);
  session.set_rate_controller(rate_controller_);
  session.set_bag_recorder(bag_recorder_);
  {
    std::error_code ec;
    fs::create_directories(dir / "checkpoints", ec);
    if (!ec) session.set_checkpoint_dir((dir / "checkpoints").string());
  }
  SessionLinks links;
  links.wait_tick = [this](std::uint64_t t, double s) { return wait_tick(t, s); };
  links.tick_timeout = tick_timeout_;
  links.stop_request = [this]() -> const char* {
    if (preempt_) return "preempted";
    if (abort_) return "aborted";
    return nullptr;
  };
  links.arm = [this](TickJudge j, std::uint64_t start) { arm(std::move(j), start); };
  links.answer = [this](std::uint64_t t) { answer(t); };
  links.feedback = [&gh](const virtual_triaxial::RunTestFeedback& f) { gh.publishFeedback(f); };
  virtual_triaxial::ProtocolStatus last_status;  // the verdict below continues it (tick, stage, strain)
  links.status = [this, &last_status](const virtual_triaxial::ProtocolStatus& s) {
    last_status = s;
    status_pub_.publish(s);
  };
  protocol::RunReport report;
  try {
    io::ResultsRecorder recorder(result.results_file, true);
    if (resume) recorder.resume(static_cast<std::size_t>(resume->results_rows));  // throws naming the file
    session.set_run_checkpoint(io::checkpoint_path(result.results_file), scene_text);
    // summary.json as the test goes (verdict `interrupted`), replaced at the end
    recorder.set_after_flush([&result](std::size_t samples, const std::string& stage) {
      io::write_text_atomic(result.summary_file,
                            io::partial_summary_json(samples, stage, result.results_file) + "\n");
    });
    report = session.run(scene, path, recorder, links, resume ? &*resume : nullptr, resume_path);
    recorder.finish(report, session.context());
  } catch (const std::exception& e) {
    return refuse("failed", e.what());
  }
  const std::string json = io::run_summary_json(report, session.context(), result.results_file);
  try {
    io::write_text_atomic(result.summary_file, json + "\n");
  } catch (const io::WriteError& e) {
    return refuse("failed", std::string("output: ") + e.what());
  }
  result.verdict = session.verdict_word();
  result.message = report.failure;
  for (const protocol::StageOutcome& s : report.stages) {
    result.stages.push_back(s.name);
    result.stop_reasons.push_back(s.stop_reason);
  }
  const protocol::ShearSummary& sh = report.shear;
  result.e0 = sh.e0;
  result.phi_peak = sh.phi_peak;
  result.eps_peak = sh.eps_peak;
  result.phi_end = sh.phi_end;
  result.mean_moment_index = sh.mean_moment_index_to_peak;
  result.max_moment_index = sh.max_moment_index_to_peak;
  result.rate_strategy = sh.rate_strategy;
  result.strain_rate_dimensionless_min = sh.strain_rate_min;
  result.strain_rate_dimensionless_max = sh.strain_rate_max;
  result.quasi_static_threshold = scene.control.quasi_static_threshold;
  result.quasi_static = sh.quasi_static;
  result.runtime = report.wall_seconds;
  result.steps = report.steps;
  result.ticks = static_cast<std::uint64_t>(report.ticks);
  virtual_triaxial::ProtocolStatus st = last_status;  // the last tick's, so a recording ends on it
  st.state = result.verdict;
  st.message = report.failure;
  status_pub_.publish(st);
  ROS_INFO("test_protocol_node: %s after %lld steps (%.1f s): %s", result.verdict.c_str(),
           static_cast<long long>(report.steps), report.wall_seconds, result.summary_file.c_str());
  running_ = false;
  if (result.verdict == "completed") gh.setSucceeded(result, "completed");
  else if (result.verdict == "preempted") gh.setCanceled(result, report.failure);
  else gh.setAborted(result, result.verdict + ": " + report.failure);
}

}  // namespace vt::ros
