// Fixed-size particle chunks for deterministic parallel reductions.
//
// Work is split into chunks of kChunkSize particles in storage order; each
// chunk reduces into its own slot and the slots are combined serially in
// chunk order. The result is therefore bit-identical for any thread count.
#pragma once

#include <cstdint>

namespace vt::dem {

constexpr std::int32_t kChunkSize = 512;

inline std::int32_t chunk_count(std::size_t n) {
  return static_cast<std::int32_t>((n + kChunkSize - 1) / kChunkSize);
}

}  // namespace vt::dem
