// Giving the allocator's free pages back to the system. jemalloc, as nomec's programs set it
// up (tools/allocator.h), keeps freed pages for reuse; the C library's malloc keeps some in
// its arenas. A program that has just freed a large part of its memory and will not need it
// again soon (the language server once the editor is idle, the command line's check once a
// piece of a large file is lowered) calls this so its resident memory falls.
#pragma once

namespace nomec {

/// Returns the free pages of every allocator arena to the system (jemalloc's
/// `arena.<all>.purge`, else `malloc_trim`). Costs a system call per run of free pages.
void give_back_free_memory();

}  // namespace nomec
