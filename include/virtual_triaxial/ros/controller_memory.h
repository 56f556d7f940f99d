// The answer of a controller node's ~set_memory (SetMemory.srv), shared by
// the servo and the rate controller nodes: the strategy restores the numbers
// its memory() gave (control::ServoStrategy, control::RateStrategy), or
// refuses them naming why.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "virtual_triaxial/SetMemory.h"

namespace vt::ros {

template <class Strategy>
void answer_set_memory(Strategy& strategy, const std::vector<double>& memory,
                       virtual_triaxial::SetMemory::Response& rs) {
  try {
    strategy.restore_memory(memory);
  } catch (const std::invalid_argument& e) {
    rs.success = false;
    rs.message = std::string("memory: ") + e.what();
    return;
  }
  rs.success = true;
  rs.message = "restored " + std::to_string(memory.size()) + " numbers";
}

}  // namespace vt::ros
