// Huge-page advice for large buffers (see large_arrays.h).
#include "kernel/large_arrays.h"

#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace nomec::kernel {

void advise_huge_pages(const void* data, size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  if (data == nullptr || bytes < kHugePageAdviceBytes) return;
  constexpr uintptr_t kHuge = uintptr_t{2} << 20;
  // The advice covers the whole 2 MiB blocks that the buffer touches: a large allocation
  // is its own mapping, which the system aligns to 2 MiB, so the first block (holding the
  // allocator's header) is worth a huge page too. Advice on a neighbour's memory or past
  // the end of the mapping is harmless: it only allows huge pages, and unmapped parts are
  // skipped. A refused hint changes nothing, so the result is ignored.
  const uintptr_t begin = reinterpret_cast<uintptr_t>(data) & ~(kHuge - 1);
  const uintptr_t end = (reinterpret_cast<uintptr_t>(data) + bytes + kHuge - 1) & ~(kHuge - 1);
  (void)madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
  (void)data;
  (void)bytes;
#endif
}

}  // namespace nomec::kernel
