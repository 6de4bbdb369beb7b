// See free_memory.h.
#include "base/free_memory.h"

#include <dlfcn.h>
#include <malloc.h>

namespace nomec {

void give_back_free_memory() {
  using Mallctl = int (*)(const char*, void*, size_t*, void*, size_t);
  // jemalloc exports `mallctl` when it replaced malloc; looked up once.
  static const auto mallctl = reinterpret_cast<Mallctl>(dlsym(RTLD_DEFAULT, "mallctl"));
  if (mallctl != nullptr) {
    mallctl("arena.4096.purge", nullptr, nullptr, nullptr, 0);  // 4096: MALLCTL_ARENAS_ALL
  } else {
    malloc_trim(0);
  }
}

}  // namespace nomec
