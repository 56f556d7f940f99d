#include "virtual_triaxial/dem/thread_runs.h"

#include <algorithm>
#include <cmath>

#include "virtual_triaxial/dem/chunked.h"

namespace vt::dem {

void ThreadRuns::prepare(std::int32_t nchunks, std::size_t n, int threads) {
  if (current(nchunks, n, threads)) return;
  nchunks_ = nchunks;
  n_ = n;
  threads_ = threads;
  bounds_.assign(static_cast<std::size_t>(threads) + 1, 0);
  for (int t = 0; t < threads; ++t) bounds_[static_cast<std::size_t>(t) + 1] = chunk_run(nchunks, t, threads).second;
  busy_.assign(static_cast<std::size_t>(threads), Busy{});
  window_steps_ = 0;
  ++version_;
}

std::size_t ThreadRuns::particles(std::size_t t, const std::vector<std::int32_t>& b) const {
  const std::size_t lo = std::min(n_, static_cast<std::size_t>(b[t]) * kChunkSize);
  const std::size_t hi = std::min(n_, static_cast<std::size_t>(b[t + 1]) * kChunkSize);
  return hi - lo;
}

void ThreadRuns::end_step() {
  if (threads_ < 2) return;
  ++window_steps_;
  double slowest = 0.0;
  for (const Busy& b : busy_) slowest = std::max(slowest, b.seconds);
  if (window_steps_ < kWindowSteps || slowest < kWindowSeconds) return;
  const auto tc = static_cast<std::size_t>(threads_);
  std::vector<double> speed(tc);
  double total = 0.0;
  bool measured = true;
  for (std::size_t t = 0; t < tc; ++t) {
    const std::size_t p = particles(t, bounds_);
    measured = measured && busy_[t].seconds > 0.0 && p > 0;
    speed[t] = busy_[t].seconds > 0.0 ? static_cast<double>(p) / busy_[t].seconds : 0.0;
    total += speed[t];
  }
  busy_.assign(tc, Busy{});
  window_steps_ = 0;
  if (!measured || !(total > 0.0)) return;
  // Cut: cumulative share of the particles by speed, at the nearest chunk
  // boundary; every run keeps at least one chunk when there are enough.
  std::vector<std::int32_t> cut(tc + 1, 0);
  cut[tc] = nchunks_;
  const bool enough = nchunks_ >= threads_;
  double cumulative = 0.0;
  for (std::size_t t = 1; t < tc; ++t) {
    cumulative += speed[t - 1];
    const double target = static_cast<double>(n_) * cumulative / total / kChunkSize;
    auto b = static_cast<std::int32_t>(std::lround(target));
    if (enough) b = std::clamp(b, cut[t - 1] + 1, nchunks_ - static_cast<std::int32_t>(tc - t));
    else b = std::clamp(b, cut[t - 1], nchunks_);
    cut[t] = b;
  }
  double now = 0.0, predicted = 0.0;
  for (std::size_t t = 0; t < tc; ++t) {
    now = std::max(now, static_cast<double>(particles(t, bounds_)) / speed[t]);
    predicted = std::max(predicted, static_cast<double>(particles(t, cut)) / speed[t]);
  }
  if (cut == bounds_ || predicted > (1.0 - kMinGain) * now) return;
  bounds_ = cut;
  ++version_;
  ++recuts_;
}

}  // namespace vt::dem
