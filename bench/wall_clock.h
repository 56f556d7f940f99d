// The wall clock the bench programs time with (steady: not moved by
// clock adjustments).
#pragma once

#include <chrono>

namespace vt::bench {

using WallClock = std::chrono::steady_clock;

/// Seconds from t to now.
inline double seconds_since(WallClock::time_point t) {
  return std::chrono::duration<double>(WallClock::now() - t).count();
}

}  // namespace vt::bench
