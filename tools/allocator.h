// The memory allocator of the programs that host the language server (`nomec`, bench_lsp).
// `allocator_name()` says which one runs: "jemalloc" when the program was linked with it
// (NOMEC_JEMALLOC, see the top-level CMakeLists.txt) and it took over malloc, else "malloc"
// (the C library's). Shown by `nomec --version` and reported by bench_lsp, so a build that
// silently lost jemalloc is visible in tests and in benchmark figures.
//
// NOMEC_JEMALLOC_CONFIG() (once per program, at namespace scope) sets jemalloc's options:
// freed pages are kept for reuse instead of being returned to the system on a timer. Each
// keystroke on a large document frees and allocates tens of megabytes; returned pages were
// faulted back in by the next check (about a tenth of its time). The language server
// returns free memory itself once the editor is idle (`release_free_memory` in
// lsp/server.cpp), so memory still goes back to the system, just not mid-typing.
// Memory comes in 4 KiB pages (`thp:never`): a cold `nomec --check` checks a large file in
// pieces and gives each piece's memory back once it is lowered (frontend/check), and pages
// given back from inside a 2 MiB huge page do not leave the process; with huge pages the
// 1 MiB scene's check peaked at 38 MiB instead of 27, and start-up alone took 14 MiB
// instead of 9 (bench/frontend/README.md). It once spent most of its time faulting in
// 4 KiB pages, when it touched 200 MiB; at 27 MiB the two page sizes take about the same
// time, and so do the editor's checks, whose memory is reused from one check to the next.
// The commands that build meshes ask for huge pages once their check is done
// (`use_huge_pages_from_now`), and the kernel asks for them for its own large arrays
// (kernel/large_arrays.h). Large allocations share the one arena
// (`oversize_threshold:0`: jemalloc 5.3 reads 0 as "no threshold" and keeps no separate
// arena for allocations above it, 8 MiB by default; `arenas.lookup` puts an 8 MiB block in
// arena 0), so the pages a large array frees are reused by the next ones: when it was set,
// the peak of the 1 MiB scene's check went from 76 MiB to 65 (61 MiB with neither option).
// Every thread allocates from one arena (`narenas:1`): with freed pages kept, pages a thread
// freed in an arena of its own were never reused by the others, so a large file parsed on
// two threads (frontend/parse) peaked 4–6 MiB higher (57.6 MiB instead of 51.8 for the
// 1 MiB scene).
#pragma once

#include <string_view>

#include "base/free_memory.h"

namespace nomec {

/// From now on, the memory jemalloc maps for the process may be backed by 2 MiB huge pages
/// (it asks with `madvise` for each new mapping; pages mapped before stay 4 KiB). For the
/// commands that build meshes (`--emit stl`/`obj`, `--what-if`, `view`): their
/// evaluation, merge and subdivision fill many arrays of a few megabytes, which took 1.3–1.6
/// times as long on 4 KiB pages (bench/pipeline/README.md).
/// The check itself stays on 4 KiB pages. Returns false where it cannot (not jemalloc).
bool use_huge_pages_from_now();

inline std::string_view allocator_name() { return jemalloc_mallctl() != nullptr ? "jemalloc" : "malloc"; }

}  // namespace nomec

// jemalloc reads its options from this symbol when the program starts; without jemalloc
// the symbol is unused.
#define NOMEC_JEMALLOC_CONFIG()        \
  extern "C" const char* malloc_conf; \
  const char* malloc_conf = "dirty_decay_ms:-1,muzzy_decay_ms:-1,thp:never,oversize_threshold:0,narenas:1"
