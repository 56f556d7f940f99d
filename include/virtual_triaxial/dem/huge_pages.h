// Transparent huge pages (THP) for the large per-particle and per-pair
// arrays of the DEM core.
//
// At 10^4-10^5 particles the step's working set (10-100 MB) exceeds what the
// data TLB covers with 4 KiB pages (about 2000 entries = 8 MiB), so the
// scattered partner reads of the contact loop miss the TLB
// as well as the caches. Backing those arrays with 2 MiB pages removes most
// of the TLB misses. These are hints to the kernel (madvise): where THP is
// disabled, unsupported or the memory is fragmented they do nothing, and the
// results never depend on them (bit-identical either way).
//
// Two ways in:
//  - reserve_huge(v, n) before the array is first written: the pages are
//    faulted in as huge pages (Linux THP mode "madvise" or "always");
//  - collapse_huge(v) on an array already written (Linux >= 6.1,
//    MADV_COLLAPSE: copied into huge pages once, synchronously).
// Arrays smaller than kHugePageMinBytes are left alone: they cannot hold a
// whole aligned 2 MiB page.
#pragma once

#include <cstddef>
#include <vector>

namespace vt::dem {

constexpr std::size_t kHugePageBytes = std::size_t{2} << 20;     ///< x86-64 PMD page, 2 MiB
constexpr std::size_t kHugePageMinBytes = kHugePageBytes;       ///< smallest array advised

/// madvise(MADV_HUGEPAGE) on the 2 MiB-aligned part of [data, data + bytes);
/// with `collapse`, also MADV_COLLAPSE (populated memory). Returns true if
/// the kernel accepted the hint(s); failures are not errors.
bool advise_huge_pages(const void* data, std::size_t bytes, bool collapse);

/// Reserve capacity for n elements and advise it before anything is written.
template <class T>
void reserve_huge(std::vector<T>& v, std::size_t n) {
  if (n * sizeof(T) < kHugePageMinBytes || v.capacity() >= n) return;
  v.reserve(n);
  advise_huge_pages(v.data(), v.capacity() * sizeof(T), false);
}

/// Ask for an array already written to be moved into huge pages.
template <class T>
void collapse_huge(const std::vector<T>& v) {
  if (v.capacity() * sizeof(T) < kHugePageMinBytes) return;
  advise_huge_pages(v.data(), v.capacity() * sizeof(T), true);
}

}  // namespace vt::dem
