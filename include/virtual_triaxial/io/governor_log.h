// The thread governor's choices as a CSV table (triax_run --governor-log):
// one row per block of steps (dem/thread_governor.h), so a user can see
// why a run took the thread counts it took. Columns:
//   end_step       steps run so far, this block's included
//   threads        the count the block ran
//   kind           start (the run's first block: counted, not timed),
//                  probe (it measured the count not running), or run
//   timed_steps, untimed_steps   steps timed / counted only (list rebuilds,
//                  the first step after a change of count, the start)
//   us_per_step    the block's mean wall time per timed step [us] (start:
//                  per counted step)
//   cost_one_us, cost_max_us     the governor's costs per step after the
//                  block [us] (0: not measured yet)
//   next           the count of the next block
#pragma once

#include <string>

#include "virtual_triaxial/dem/thread_governor.h"

namespace vt::io {

class GovernorLog {
 public:
  void add(const dem::ThreadGovernor::Block& b);
  /// The table so far: the header and one line per block.
  const std::string& text() const { return text_; }
  std::size_t blocks() const { return blocks_; }

 private:
  std::string text_ =
      "end_step,threads,kind,timed_steps,untimed_steps,us_per_step,cost_one_us,cost_max_us,next\n";
  std::size_t blocks_ = 0;
};

}  // namespace vt::io
