// See allocator.h (`use_huge_pages_from_now`).
#include "tools/allocator.h"

#if __has_include(<jemalloc/jemalloc.h>) && __has_include(<sys/mman.h>)
#include <jemalloc/jemalloc.h>
#include <sys/mman.h>
#define NOMEC_EXTENT_HOOKS 1
#endif

namespace nomec {

#if defined(NOMEC_EXTENT_HOOKS)
namespace {

extent_hooks_t* default_hooks = nullptr;  // jemalloc's own, which do the work
extent_hooks_t huge_hooks;                // the same, with `alloc` advising huge pages

void* alloc_huge(extent_hooks_t*, void* new_addr, size_t size, size_t alignment, bool* zero, bool* commit,
                 unsigned arena) {
  void* p = default_hooks->alloc(default_hooks, new_addr, size, alignment, zero, commit, arena);
  // Only a hint: a refused one changes nothing.
  if (p != nullptr) (void)madvise(p, size, MADV_HUGEPAGE);
  return p;
}

}  // namespace
#endif

bool use_huge_pages_from_now() {
#if defined(NOMEC_EXTENT_HOOKS)
  const Mallctl ctl = jemalloc_mallctl();
  if (ctl == nullptr) return false;  // not jemalloc
  if (default_hooks != nullptr) return true;
  // Every thread allocates from arena 0 (`narenas:1`, and no arena for large sizes).
  extent_hooks_t* current = nullptr;
  size_t size = sizeof(current);
  if (ctl("arena.0.extent_hooks", &current, &size, nullptr, 0) != 0 || current == nullptr) return false;
  default_hooks = current;
  huge_hooks = *current;
  huge_hooks.alloc = alloc_huge;
  extent_hooks_t* mine = &huge_hooks;
  if (ctl("arena.0.extent_hooks", nullptr, nullptr, &mine, sizeof(mine)) != 0) {
    default_hooks = nullptr;
    return false;
  }
  return true;
#else
  return false;
#endif
}

}  // namespace nomec
