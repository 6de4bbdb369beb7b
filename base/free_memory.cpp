// See free_memory.h.
#include "base/free_memory.h"

#include <dlfcn.h>
#include <malloc.h>

namespace nomec {

Mallctl jemalloc_mallctl() {
  static const auto mallctl = reinterpret_cast<Mallctl>(dlsym(RTLD_DEFAULT, "mallctl"));
  return mallctl;
}

void give_back_free_memory() {
  if (const Mallctl mallctl = jemalloc_mallctl()) {
    mallctl("arena.4096.purge", nullptr, nullptr, nullptr, 0);  // 4096: MALLCTL_ARENAS_ALL
  } else {
    malloc_trim(0);
  }
}

}  // namespace nomec
