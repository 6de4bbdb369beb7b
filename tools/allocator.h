// Which memory allocator this process runs on: "jemalloc" when the program was linked with
// it (NOMEC_JEMALLOC, see the top-level CMakeLists.txt) and it took over malloc, else
// "malloc" (the C library's). Shown by `nomec --version` and reported by bench_lsp, so a
// build that silently lost jemalloc is visible in tests and in benchmark figures.
#pragma once

#include <dlfcn.h>

#include <string_view>

namespace nomec {

inline std::string_view allocator_name() {
  // jemalloc exports `mallctl`; the C library does not.
  return dlsym(RTLD_DEFAULT, "mallctl") != nullptr ? "jemalloc" : "malloc";
}

}  // namespace nomec
