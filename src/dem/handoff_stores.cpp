#include "virtual_triaxial/dem/handoff_stores.h"

#include <algorithm>

namespace vt::dem {

void HandoffStores::set_mode(Mode m) {
  mode_ = m;
  streaming_ = m == Mode::Streaming;
  window_steps_ = 0;
  streamed_windows_ = 0;
  for (Sums& s : sums_) s = Sums{};
}

void HandoffStores::ensure_threads(int threads) {
  if (static_cast<int>(sums_.size()) == threads) return;
  sums_.assign(static_cast<std::size_t>(threads), Sums{});
  window_steps_ = 0;
}

std::int64_t HandoffStores::streamed_chunks() const {
  std::int64_t total = 0;
  for (const Sums& s : sums_) total += s.streamed_chunks;
  return total;
}

void HandoffStores::record(int t, bool shared, double seconds, std::size_t particles) {
  Window& s = sums_[static_cast<std::size_t>(t)].window;
  (shared ? s.shared_seconds : s.other_seconds) += seconds;
  (shared ? s.shared_particles : s.other_particles) += particles;
}

void HandoffStores::end_step() {
  ++steps_;
  streamed_steps_ += streaming_ ? 1 : 0;
  if (mode_ == Mode::Streaming || ++window_steps_ < kWindowSteps) return;
  window_steps_ = 0;
  if (streaming_) {
    // streamed windows are not measured; after kProbeWindows, one plain
    if (++streamed_windows_ >= kProbeWindows) {
      streaming_ = false;
      streamed_windows_ = 0;
    }
    return;
  }
  double ratio = 0.0;
  for (const Sums& slot : sums_) {
    const Window& s = slot.window;
    if (s.shared_particles == 0 || s.other_particles == 0 || !(s.other_seconds > 0.0)) continue;
    const double r = (s.shared_seconds / static_cast<double>(s.shared_particles)) /
                     (s.other_seconds / static_cast<double>(s.other_particles));
    ratio = std::max(ratio, r);
  }
  for (Sums& s : sums_) s.window = Window{};
  last_ratio_ = ratio;
  if (mode_ == Mode::Auto) streaming_ = ratio > kSlowRatio;
}

}  // namespace vt::dem
