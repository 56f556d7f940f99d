// A copy of Vec3 arrays whose whole destination cache lines are written
// with non-temporal (streaming) stores, for the integrator's stores of the
// particles another thread reads (handoff_stores.h).
//
// An ordinary store to a line that another core holds first takes the
// line back from it (a read for ownership); with the host's two vCPUs far
// apart that costs 15-19 ns a line (session 36, E1) and the integrator's
// stores wait on it one after the other. A streaming store of a whole
// 64-byte line goes to memory without that read and does not wait; the
// other core's copy is dropped, and the next read of the line, by either
// core, comes from memory. Partial lines at either end are copied
// plainly. Values are copied bit for bit. On a target without SSE2 the
// copy is a plain one. The caller orders the streaming stores before the
// next synchronisation with streaming_fence().
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "virtual_triaxial/dem/vec3.h"

namespace vt::dem {

constexpr std::size_t kCacheLineBytes = 64;

/// dst[k] = src[k] for k < count (the ranges must not overlap).
inline void streaming_copy(Vec3* dst, const Vec3* src, std::size_t count) {
  auto* d = reinterpret_cast<unsigned char*>(dst);
  const auto* s = reinterpret_cast<const unsigned char*>(src);
  std::size_t bytes = count * sizeof(Vec3);
#if defined(__SSE2__)
  const std::size_t misalign = reinterpret_cast<std::uintptr_t>(d) % kCacheLineBytes;
  const std::size_t head = std::min(bytes, (kCacheLineBytes - misalign) % kCacheLineBytes);
  std::memcpy(d, s, head);
  d += head;
  s += head;
  bytes -= head;
  for (; bytes >= kCacheLineBytes; bytes -= kCacheLineBytes, d += kCacheLineBytes, s += kCacheLineBytes) {
    for (std::size_t k = 0; k < kCacheLineBytes; k += 16)
      _mm_stream_pd(reinterpret_cast<double*>(d + k), _mm_loadu_pd(reinterpret_cast<const double*>(s + k)));
  }
#endif
  std::memcpy(d, s, bytes);
}

/// Orders the streaming stores made so far before later stores (SFENCE),
/// so a barrier after it publishes them.
inline void streaming_fence() {
#if defined(__SSE2__)
  _mm_sfence();
#endif
}

}  // namespace vt::dem
