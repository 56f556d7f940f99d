#include "virtual_triaxial/dem/huge_pages.h"

#include <cstdint>

#ifdef __linux__
#include <sys/mman.h>
#endif

namespace vt::dem {

#ifdef __linux__
namespace {
#ifdef MADV_COLLAPSE
constexpr int kMadvCollapse = MADV_COLLAPSE;
#else
constexpr int kMadvCollapse = 25;  // Linux >= 6.1 (asm-generic/mman-common.h)
#endif
}  // namespace
#endif

bool advise_huge_pages(const void* data, std::size_t bytes, bool collapse) {
#ifdef __linux__
  const auto begin = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t first = (begin + kHugePageBytes - 1) & ~(kHugePageBytes - 1);
  const std::uintptr_t last = (begin + bytes) & ~(kHugePageBytes - 1);
  if (data == nullptr || last <= first) return false;
  void* p = reinterpret_cast<void*>(first);
  const std::size_t len = last - first;
  bool ok = madvise(p, len, MADV_HUGEPAGE) == 0;
  if (collapse) ok = madvise(p, len, kMadvCollapse) == 0 && ok;
  return ok;
#else
  (void)data;
  (void)bytes;
  (void)collapse;
  return false;
#endif
}

}  // namespace vt::dem
