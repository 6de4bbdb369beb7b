// The Tcl worker's walls (frontend/tcl/sandbox.h), each tried in a child process that
// walls itself in as the worker does: files cannot be opened, no socket, pipe, process,
// exec or signal to another process, no executable memory, and the resource limits hold.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <functional>

#include "frontend/tcl/sandbox.h"

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define NOMEC_TEST_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define NOMEC_TEST_ASAN 1
#endif

namespace nomec::tcl::sandbox {
namespace {

// Runs `body` in a child walled in like the worker; its wait status. `body` returns the
// child's exit code (0 = what was expected happened).
int walled(const std::function<int()>& body, bool filter = true) {
  const pid_t parent = getpid();
  const pid_t child = fork();
  if (child == 0) {
    if (!prepare(2, parent).empty()) _exit(90);
    if (filter && !install_filter().empty()) _exit(91);
    _exit(body());
  }
  int status = 0;
  waitpid(child, &status, 0);
  return status;
}

bool exited_ok(int status) { return WIFEXITED(status) && WEXITSTATUS(status) == 0; }
bool killed_by_filter(int status) { return WIFSIGNALED(status) && WTERMSIG(status) == SIGSYS; }

TEST(TclSandbox, FilesCannotBeOpened) {
  const int status = walled([] {
    if (open("/etc/passwd", O_RDONLY) >= 0 || errno != EACCES) return 1;
    if (openat(AT_FDCWD, "/etc/hostname", O_RDONLY) >= 0 || errno != EACCES) return 2;
    if (open("/tmp/nomec-sandbox-test", O_WRONLY | O_CREAT, 0600) >= 0) return 3;
    struct stat st{};
    if (stat("/etc/passwd", &st) == 0) return 4;  // not even whether a file exists
    return 0;
  });
  EXPECT_TRUE(exited_ok(status)) << status;
}

TEST(TclSandbox, NoPipesNoProcesses) {
  EXPECT_TRUE(exited_ok(walled([] {
    int p[2];
    if (pipe(p) == 0) return 1;
    if (fork() >= 0) return 2;  // clone is refused
    return 0;
  })));
}

TEST(TclSandbox, WhatOnlyAnAttackDoesEndsTheWorker) {
  EXPECT_TRUE(killed_by_filter(walled([] { return socket(AF_INET, SOCK_STREAM, 0) >= 0 ? 0 : 1; })));
  EXPECT_TRUE(killed_by_filter(walled([] {
    char* argv[] = {const_cast<char*>("/bin/true"), nullptr};
    execv("/bin/true", argv);
    return 1;
  })));
  EXPECT_TRUE(killed_by_filter(walled([] { return kill(getppid(), 0); })));
}

TEST(TclSandbox, MemoryCanBeUsedButNeverExecuted) {
  EXPECT_TRUE(exited_ok(walled([] {
    void* rw = mmap(nullptr, 1 << 20, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (rw == MAP_FAILED) return 1;
    static_cast<char*>(rw)[12345] = 1;
    if (mprotect(rw, 4096, PROT_READ | PROT_EXEC) == 0) return 2;
    void* rx = mmap(nullptr, 4096, PROT_READ | PROT_EXEC, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (rx != MAP_FAILED) return 3;
    void* heap = std::malloc(64 << 20);
    if (heap == nullptr) return 4;
    std::free(heap);
    return 0;
  })));
}

TEST(TclSandbox, ResourceLimitsAreSet) {
  // (Read before the filter, which refuses even reading them.)
  const int status = walled(
      [] {
    rlimit r{};
    if (getrlimit(RLIMIT_FSIZE, &r) != 0 || r.rlim_cur != 0) return 1;
    if (getrlimit(RLIMIT_NOFILE, &r) != 0 || r.rlim_cur > 64) return 2;
    if (getrlimit(RLIMIT_CPU, &r) != 0 || r.rlim_cur == RLIM_INFINITY) return 3;
    if (getrlimit(RLIMIT_CORE, &r) != 0 || r.rlim_cur != 0) return 4;
#ifndef NOMEC_TEST_ASAN
    if (getrlimit(RLIMIT_AS, &r) != 0 || r.rlim_cur > (size_t{1} << 30)) return 5;
    if (std::malloc(size_t{900} << 20) != nullptr) return 6;  // past the address space
#endif
    // Only the standard descriptors are left.
    if (fcntl(3, F_GETFD) != -1 || fcntl(4, F_GETFD) != -1) return 7;
    return 0;
      },
      false);
  EXPECT_TRUE(exited_ok(status)) << (WIFEXITED(status) ? WEXITSTATUS(status) : -1);
}

}  // namespace
}  // namespace nomec::tcl::sandbox
