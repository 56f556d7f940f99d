// Fixed-size particle chunks for deterministic parallel reductions.
//
// Work is split into chunks of kChunkSize particles in storage order; each
// chunk reduces into its own slot and the slots are combined serially in
// chunk order. The result is therefore bit-identical for any thread count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>

namespace vt::dem {

constexpr std::int32_t kChunkSize = 512;

inline std::int32_t chunk_count(std::size_t n) {
  return static_cast<std::int32_t>((n + kChunkSize - 1) / kChunkSize);
}

/// Chunks [first, second) of thread t of `threads`: one run of consecutive
/// chunks per thread, runs in thread order, sizes differing by at most one.
/// Every loop that splits chunks this way gives a thread the same particles
/// (the sphere pair loop, its sums and the integrator), so a thread mostly
/// reads data it wrote itself.
inline std::pair<std::int32_t, std::int32_t> chunk_run(std::int32_t nchunks, int t, int threads) {
  const std::int64_t c = nchunks;
  return {static_cast<std::int32_t>(c * t / threads), static_cast<std::int32_t>(c * (t + 1) / threads)};
}

}  // namespace vt::dem
