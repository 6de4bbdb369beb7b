// The walls of the Tcl worker process (worker_main.cpp), which runs a scene's Tcl: a scene
// is code, and Tcl's own commands can overflow the C stack or panic, so the process that
// runs it is allowed nothing it does not need. `prepare` runs first: the worker dies with
// nomec, keeps only its socket and the standard descriptors, and gets resource limits
// (address space, CPU time, open files, no file writes, no core files). `install_filter`
// runs once the interpreter is made: a system-call filter (libseccomp) after which the
// process can read and write its socket, allocate memory and tell the time, and nothing
// else — no opening files (the scene's files come from nomec over the socket, read
// beneath the scene's folder), no pipes, sockets, processes, signals to others or exec.
#pragma once

#include <sys/types.h>

#include <cstddef>
#include <string>

namespace nomec::tcl::sandbox {

struct Walls {
  size_t address_space = size_t{512} << 20;  // bytes (not applied under AddressSanitizer)
  int cpu_seconds = 600;                      // a backstop: nomec ends a worker past its budget
  int open_files = 16;
};

/// Ends this process when `parent` does, closes every descriptor above `keep_fd` and sets the
/// resource limits. Returns "" or what failed.
std::string prepare(int keep_fd, pid_t parent, const Walls& walls = {});

/// Installs the system-call filter on every thread of the process. Returns "" or what failed
/// (then the worker must not run a scene).
std::string install_filter();

/// The stack size of the thread that runs the interpreter: Tcl's recursion limit is reached
/// before the stack is used up (see worker_main.cpp).
constexpr size_t kEngineStack = size_t{64} << 20;

}  // namespace nomec::tcl::sandbox
