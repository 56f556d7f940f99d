#include "virtual_triaxial/dem/thread_governor.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vt::dem {

ThreadGovernor::ThreadGovernor(int max_threads, std::int64_t min_block_steps, double min_block_seconds,
                               int exploit_blocks, double max_spacing_ratio)
    : max_(std::max(1, max_threads)),
      min_steps_(std::max<std::int64_t>(1, min_block_steps)),
      min_seconds_(min_block_seconds),
      exploit_(std::max(1, exploit_blocks)),
      max_ratio_(std::max(1.0, max_spacing_ratio)),
      current_(max_) {}

int ThreadGovernor::useful_threads(std::int32_t chunks, int max_threads) {
  return std::max(1, std::min(max_threads, static_cast<int>(chunks / kMinChunksPerThread)));
}

void ThreadGovernor::limit_to_chunks(std::int32_t chunks) {
  const int capped = useful_threads(chunks, max_);
  if (capped == max_) return;
  // costs measured for the old maximum no longer apply: start afresh
  RoomCheck room = std::move(room_);
  BlockLog log = std::move(log_);
  *this = ThreadGovernor(capped, min_steps_, min_seconds_, exploit_, max_ratio_);
  room_ = std::move(room);
  log_ = std::move(log);
}

bool ThreadGovernor::room_after_wait() {
  if (room_blocks_left_ > 0) {
    --room_blocks_left_;
    return false;
  }
  if (room()) {
    room_wait_ = 1;
    return true;
  }
  room_blocks_left_ = room_wait_ - 1;  // ask again after room_wait_ blocks
  room_wait_ = std::min(2 * room_wait_, exploit_);
  return false;
}

void ThreadGovernor::record_step(double seconds, bool regular) {
  if (max_ == 1) return;
  ++steps_[slot(current_)];
  const bool first_after_switch = switched_;
  switched_ = false;
  if (warming_) {  // the run's first block pays for the start: counted, not timed
    warm_seconds_ += seconds;
    if (++warm_steps_ >= min_steps_ && warm_seconds_ >= min_seconds_) {
      warming_ = false;
      if (!room_after_wait()) {  // the other cores are busy: one thread, max_threads asked for again after its first block
        current_ = 1;
        switched_ = true;
        blocks_since_probe_ = exploit_;  // a probe due at once (r = 1 while max_threads is unmeasured)
      }
      Block b;
      b.threads = max_;
      b.start = true;
      b.untimed_steps = warm_steps_;
      b.seconds_per_step = warm_seconds_ / static_cast<double>(warm_steps_);
      report(b);
    }
    return;
  }
  // counted, not timed; but a block whose steps are all irregular (every
  // step rebuilds the list) is timed after kMaxUntimed of them, so it ends
  if ((!regular || first_after_switch) && untimed_ < kMaxUntimed * min_steps_) {
    ++untimed_;
    return;
  }
  ++block_steps_;
  block_seconds_ += seconds;
  if (block_steps_ >= min_steps_ && block_seconds_ >= min_seconds_) end_block();
}

void ThreadGovernor::end_block() {
  // The count's cost: the lower of this block and the one before when that
  // ran the same count (one block slowed by something else, e.g. a hiccup
  // of the host, does not flip the choice); a probe block (the other count
  // ran before it) gives its own cost, however old that count's last block.
  const double block = block_seconds_ / static_cast<double>(block_steps_);
  const int s = slot(current_);
  Block b;
  b.threads = current_;
  b.probe = probing_;
  b.timed_steps = block_steps_;
  b.untimed_steps = untimed_;
  b.seconds_per_step = block;
  cost_[s] = previous_block_ > 0.0 && previous_slot_ == s ? std::min(block, previous_block_) : block;
  previous_block_ = block;
  previous_slot_ = s;
  block_steps_ = 0;
  block_seconds_ = 0;
  untimed_ = 0;
  const int before = current_;
  choose_next();
  switched_ = current_ != before;
  report(b);
}

void ThreadGovernor::report(Block b) const {
  if (!log_) return;
  b.end_step = steps_[0] + steps_[1];
  b.cost_one = cost_[0];
  b.cost_max = cost_[1];
  b.next = current_;
  log_(b);
}

void ThreadGovernor::choose_next() {
  if (cost_[0] == 0) {  // start: max_threads measured, now 1
    current_ = 1;
    return;
  }
  // max_threads not measured yet (no room after the run's first block): one thread
  const int best = cost_[1] == 0 || cost_[0] <= cost_[1] ? 1 : max_;
  const int other = best == 1 ? max_ : 1;
  if (probing_) {  // the block that ended probed the other count
    probing_ = false;
    if (!recheck_) backoff_ = best == current_ ? 1 : std::min(2 * backoff_, kMaxProbeBackoff);
    recheck_ = false;  // a recheck that confirms one thread leaves b at 1
  } else if (best != current_) {
    // the running count got dearer than the other: the load changed (or
    // max_threads' first measurement lost: b stays 1).
    // blocks_since_probe_ is kept, so the count just left is probed again
    // soon: a second look, in case the change was a hiccup of the host
    backoff_ = 1;
    recheck_ = false;
  }
  if (!compared_ && cost_[1] != 0.0) {  // the first comparison of the two counts
    compared_ = true;
    recheck_ = best == 1;  // lost by max_threads: rechecked soon (the start's transients)
  }
  // Probe spacing grows with the cost ratio r (at most 64), so the probes
  // take at most 1/(exploit + 1) of the run's time, however slow the other
  // count, and doubles with each probe that confirms the count (backoff);
  // a recheck comes kStartRecheck times sooner.
  const double r = std::min(max_ratio_, std::max(1.0, cost_[slot(other)] / cost_[slot(best)]));
  const int probe_after =
      static_cast<int>(std::ceil(exploit_ * r * backoff_ / (recheck_ ? kStartRecheck : 1)));
  if (current_ == best && ++blocks_since_probe_ >= probe_after) {
    if (other == max_ && !room_after_wait()) return;  // the other cores are busy: one thread goes on
    blocks_since_probe_ = 0;
    current_ = other;  // one block to refresh the other count's cost
    // a block that gives a count its first cost (max_threads after no room
    // at the start) is a measurement, not a probe: it confirms nothing
    probing_ = cost_[slot(other)] != 0.0;
  } else {
    current_ = best;
  }
  if (current_ == max_) {  // running max_threads: the next "no room" waits from 1 again
    room_wait_ = 1;
    room_blocks_left_ = 0;
  }
}

}  // namespace vt::dem
