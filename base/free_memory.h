// The memory allocator's controls. jemalloc, as nomec's programs set it up
// (tools/allocator.h), keeps freed pages for reuse; the C library's malloc keeps some in its
// arenas. A program that has just freed a large part of its memory and will not need it
// again soon (the language server once the editor is idle, the command line's check once a
// piece of a large file is lowered) gives its free pages back so its resident memory falls.
#pragma once

#include <cstddef>

namespace nomec {

/// jemalloc's `mallctl` when jemalloc replaced malloc in this process (it exports the
/// symbol; the C library does not), else null. Looked up once.
using Mallctl = int (*)(const char* name, void* old_value, size_t* old_size, void* new_value, size_t new_size);
Mallctl jemalloc_mallctl();

/// Returns the free pages of every allocator arena to the system (jemalloc's
/// `arena.<all>.purge`, else `malloc_trim`). Costs a system call per run of free pages.
void give_back_free_memory();

}  // namespace nomec
