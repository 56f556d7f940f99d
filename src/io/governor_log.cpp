#include "virtual_triaxial/io/governor_log.h"

#include "virtual_triaxial/io/number_text.h"

namespace vt::io {

void GovernorLog::add(const dem::ThreadGovernor::Block& b) {
  const char* kind = b.start ? "start" : b.probe ? "probe" : "run";
  text_ += std::to_string(b.end_step) + ',' + std::to_string(b.threads) + ',' + kind + ',' +
           std::to_string(b.timed_steps) + ',' + std::to_string(b.untimed_steps) + ',' +
           number_text(1e6 * b.seconds_per_step) + ',' + number_text(1e6 * b.cost_one) + ',' +
           number_text(1e6 * b.cost_max) + ',' + std::to_string(b.next) + '\n';
  ++blocks_;
}

}  // namespace vt::io
