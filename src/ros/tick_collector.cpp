#include "virtual_triaxial/ros/tick_collector.h"

namespace vt::ros {

TickMessages& TickCollector::slot(std::uint64_t tick) {
  if (tick > newest_) newest_ = tick;
  // Bound the memory if nobody takes ticks (e.g. between tests).
  while (ticks_.size() > 64) ticks_.erase(ticks_.begin());
  return ticks_[tick];
}

std::optional<TickMessages> TickCollector::take(std::uint64_t tick) {
  auto it = ticks_.find(tick);
  if (it == ticks_.end() || !it->second.complete()) return std::nullopt;
  TickMessages out = std::move(it->second);
  ticks_.erase(ticks_.begin(), std::next(it));
  return out;
}

}  // namespace vt::ros
