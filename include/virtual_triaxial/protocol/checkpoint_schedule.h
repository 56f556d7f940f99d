// When a checkpoint inside a stage is due (run_checkpoint.h), for both
// runners (StageRunner headless, ProtocolSession on the rig): on a sample
// tick after RunOptions::checkpoint_ticks control ticks or
// checkpoint_seconds wall seconds since the last one (0 = that trigger
// off), and never sooner than kCheckpointCostFactor x the wall time the last
// one took, so checkpoints cost at most ~1/kCheckpointCostFactor of the run.
// The caller asks due() on sample ticks only and reports each checkpoint
// with done(). Not thread-safe: one thread at a time (the rig's tick thread
// asks while the rig runs; the session reports while it is paused).
#pragma once

#include <chrono>
#include <cstdint>

namespace vt::protocol {

inline constexpr double kCheckpointCostFactor = 20.0;

class CheckpointSchedule {
 public:
  using Clock = std::chrono::steady_clock;
  CheckpointSchedule(std::int64_t every_ticks, double every_seconds)
      : every_ticks_(every_ticks), every_seconds_(every_seconds), last_(Clock::now()) {}
  bool enabled() const { return every_ticks_ > 0 || every_seconds_ > 0; }
  /// One control tick done.
  void tick() { ++ticks_; }
  /// True when a checkpoint is due now.
  bool due() const {
    if (!enabled()) return false;
    const double since = std::chrono::duration<double>(Clock::now() - last_).count();
    if (since < kCheckpointCostFactor * cost_) return false;  // the cost bound
    return (every_ticks_ > 0 && ticks_ >= every_ticks_) || (every_seconds_ > 0 && since >= every_seconds_);
  }
  /// A checkpoint was written; it took `cost_seconds` of wall time.
  void done(double cost_seconds) {
    last_ = Clock::now();
    cost_ = cost_seconds;
    ticks_ = 0;
  }
  /// Counting starts again (a run starts or resumes).
  void restart() {
    last_ = Clock::now();
    cost_ = 0.0;
    ticks_ = 0;
  }

 private:
  std::int64_t every_ticks_;
  double every_seconds_;
  std::int64_t ticks_ = 0;
  Clock::time_point last_;
  double cost_ = 0.0;  ///< wall seconds the last checkpoint took
};

}  // namespace vt::protocol
