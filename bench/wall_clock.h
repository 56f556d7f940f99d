// The wall clock the bench programs time with (steady: not moved by
// clock adjustments).
#pragma once

#include <chrono>

namespace vt::bench {

using WallClock = std::chrono::steady_clock;

/// Seconds from a to b.
inline double seconds_between(WallClock::time_point a, WallClock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

/// Seconds from t to now.
inline double seconds_since(WallClock::time_point t) { return seconds_between(t, WallClock::now()); }

}  // namespace vt::bench
