// The Tcl worker's walls (see sandbox.h): resource limits and the libseccomp filter.
//
// The filter's default answers a system call with EPERM, so a call Tcl makes that nobody
// foresaw fails like a refused permission instead of ending the worker. The calls that
// only an attack makes (exec, sockets, ptrace, signals to other processes) end it
// (SIGSYS, which nomec reports as a forbidden system call). Opening files fails with
// EACCES: the scene's files reach the worker over its socket.
#include "frontend/tcl/sandbox.h"

#include <fcntl.h>
#include <seccomp.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define NOMEC_WORKER_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define NOMEC_WORKER_ASAN 1
#endif

namespace nomec::tcl::sandbox {

namespace {

std::string failed(const char* what, int error) { return std::string(what) + ": " + std::strerror(error); }

std::string limit(int resource, rlim_t soft, rlim_t hard, const char* what) {
  const rlimit r{soft, hard};
  if (setrlimit(resource, &r) != 0) return failed(what, errno);
  return "";
}

}  // namespace

std::string prepare(int keep_fd, pid_t parent, const Walls& walls) {
  if (prctl(PR_SET_PDEATHSIG, SIGKILL) != 0) return failed("prctl(PR_SET_PDEATHSIG)", errno);
  if (getppid() != parent) _exit(0);  // nomec ended before the line above took effect
  if (close_range(static_cast<unsigned>(keep_fd) + 1, ~0U, 0) != 0) {
    for (int fd = keep_fd + 1; fd < 65536; ++fd) close(fd);  // a kernel without close_range
  }
  std::string error;
#ifndef NOMEC_WORKER_ASAN
  // AddressSanitizer reserves terabytes of address space for its shadow memory: under it
  // the guard's count of the heap (guard.cpp) is the only bound.
  if (error = limit(RLIMIT_AS, walls.address_space, walls.address_space, "setrlimit(RLIMIT_AS)"); !error.empty()) {
    return error;
  }
#endif
  struct Wall {
    int resource;
    rlim_t soft, hard;
    const char* what;
  };
  const auto cpu = static_cast<rlim_t>(walls.cpu_seconds);
  const auto files = static_cast<rlim_t>(walls.open_files);
  const Wall rest[] = {{RLIMIT_CPU, cpu, cpu + 5, "setrlimit(RLIMIT_CPU)"},
                       {RLIMIT_NOFILE, files, files, "setrlimit(RLIMIT_NOFILE)"},
                       {RLIMIT_FSIZE, 0, 0, "setrlimit(RLIMIT_FSIZE)"},
                       {RLIMIT_CORE, 0, 0, "setrlimit(RLIMIT_CORE)"}};
  for (const Wall& w : rest) {
    if (error = limit(w.resource, w.soft, w.hard, w.what); !error.empty()) return error;
  }
  return "";
}

std::string install_filter() {
  scmp_filter_ctx ctx = seccomp_init(SCMP_ACT_ERRNO(EPERM));
  if (ctx == nullptr) return "seccomp_init failed";
  int rc = seccomp_attr_set(ctx, SCMP_FLTATR_CTL_TSYNC, 1);
  auto allow = [&](int call) {
    if (rc == 0) rc = seccomp_rule_add(ctx, SCMP_ACT_ALLOW, call, 0);
  };
  // Reading and writing the socket (and stderr), memory, time, and ending.
  for (int call : {SCMP_SYS(read), SCMP_SYS(readv), SCMP_SYS(write), SCMP_SYS(writev), SCMP_SYS(sendto),
                   SCMP_SYS(recvfrom), SCMP_SYS(close), SCMP_SYS(lseek), SCMP_SYS(fstat), SCMP_SYS(fcntl),
                   SCMP_SYS(brk), SCMP_SYS(munmap), SCMP_SYS(mremap), SCMP_SYS(madvise), SCMP_SYS(futex),
                   SCMP_SYS(rt_sigreturn), SCMP_SYS(rt_sigprocmask), SCMP_SYS(rt_sigaction), SCMP_SYS(sigaltstack),
                   SCMP_SYS(restart_syscall), SCMP_SYS(clock_gettime), SCMP_SYS(clock_getres),
                   SCMP_SYS(gettimeofday), SCMP_SYS(time), SCMP_SYS(nanosleep), SCMP_SYS(clock_nanosleep),
                   SCMP_SYS(getpid), SCMP_SYS(gettid), SCMP_SYS(getppid), SCMP_SYS(getuid), SCMP_SYS(geteuid),
                   SCMP_SYS(getgid), SCMP_SYS(getegid), SCMP_SYS(getrusage), SCMP_SYS(getrandom),
                   SCMP_SYS(sched_yield), SCMP_SYS(sched_getaffinity), SCMP_SYS(exit), SCMP_SYS(exit_group)}) {
    allow(call);
  }
  // Memory that is never executable: a scene that corrupted memory cannot run code it wrote.
  if (rc == 0) rc = seccomp_rule_add(ctx, SCMP_ACT_ALLOW, SCMP_SYS(mmap), 1, SCMP_A2(SCMP_CMP_MASKED_EQ, PROT_EXEC, 0));
  if (rc == 0) {
    rc = seccomp_rule_add(ctx, SCMP_ACT_ALLOW, SCMP_SYS(mprotect), 1, SCMP_A2(SCMP_CMP_MASKED_EQ, PROT_EXEC, 0));
  }
  // `fstat` as glibc spells it (on a descriptor: no path).
  if (rc == 0) {
    rc = seccomp_rule_add(ctx, SCMP_ACT_ALLOW, SCMP_SYS(newfstatat), 1,
                          SCMP_A3(SCMP_CMP_MASKED_EQ, AT_EMPTY_PATH, AT_EMPTY_PATH));
  }
  // abort() signals its own process only.
  for (int call : {SCMP_SYS(tgkill), SCMP_SYS(tkill)}) {
    if (rc == 0) {
      rc = seccomp_rule_add(ctx, SCMP_ACT_ALLOW, call, 1, SCMP_A0(SCMP_CMP_EQ, static_cast<scmp_datum_t>(getpid())));
    }
  }
  for (int call : {SCMP_SYS(open), SCMP_SYS(openat), SCMP_SYS(openat2), SCMP_SYS(creat)}) {
    if (rc == 0) rc = seccomp_rule_add(ctx, SCMP_ACT_ERRNO(EACCES), call, 0);
  }
  for (int call : {SCMP_SYS(execve), SCMP_SYS(execveat), SCMP_SYS(ptrace), SCMP_SYS(socket), SCMP_SYS(socketpair),
                   SCMP_SYS(connect), SCMP_SYS(bind), SCMP_SYS(listen), SCMP_SYS(accept), SCMP_SYS(accept4),
                   SCMP_SYS(sendmsg), SCMP_SYS(recvmsg), SCMP_SYS(kill), SCMP_SYS(process_vm_readv),
                   SCMP_SYS(process_vm_writev), SCMP_SYS(fork), SCMP_SYS(vfork)}) {
    if (rc == 0) rc = seccomp_rule_add(ctx, SCMP_ACT_KILL_PROCESS, call, 0);
  }
  if (rc == 0) rc = seccomp_load(ctx);
  seccomp_release(ctx);
  if (rc != 0) return failed("the system-call filter (libseccomp)", -rc);
  return "";
}

}  // namespace nomec::tcl::sandbox
