// The kept second thread of run_two_parts.
//
// One helper thread per process, started by the first call and never stopped (it sleeps
// in the kernel when idle, and the process ends without joining it). A caller reserves it
// with a flag; a second caller meanwhile (another thread of the language server, or a part
// that itself splits) starts a thread of its own, as every call did before. Between parts
// both sides spin for a short while before they sleep: a subdivision's passes come one
// after the other, separated by a few hundred microseconds of single-threaded work, and
// waking a sleeping thread costs tens of microseconds on a virtual machine whose idle
// processor has halted. A process forked after the helper started has no helper thread;
// it starts its own.
#include "base/two_threads.h"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdint>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace nomec::two_threads_detail {

namespace {

// How long a side spins for the other before sleeping.
constexpr std::chrono::microseconds kSpin{200};

void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
  _mm_pause();
#endif
}

// Waits until `value` differs from `old`: spins for kSpin, then sleeps.
uint32_t wait_for_change(const std::atomic<uint32_t>& value, uint32_t old) {
  uint32_t now = value.load(std::memory_order_acquire);
  if (now != old) return now;
  const auto until = std::chrono::steady_clock::now() + kSpin;
  for (int i = 1;; ++i) {
    cpu_relax();
    now = value.load(std::memory_order_acquire);
    if (now != old) return now;
    if (i % 64 == 0 && std::chrono::steady_clock::now() >= until) break;
  }
  for (;;) {
    value.wait(old, std::memory_order_acquire);
    now = value.load(std::memory_order_acquire);
    if (now != old) return now;
  }
}

}  // namespace

struct Helper {
  std::atomic<bool> in_use{false};
  std::atomic<uint32_t> started{0};   // the number of the last part handed over
  std::atomic<uint32_t> finished{0};  // the number of the last part done
  void (*fn)(void*) = nullptr;
  void* ctx = nullptr;
  pid_t pid = 0;

  void loop() {
    uint32_t seen = 0;
    for (;;) {
      seen = wait_for_change(started, seen);
      fn(ctx);
      finished.store(seen, std::memory_order_release);
      finished.notify_one();
    }
  }
};

namespace {

std::atomic<Helper*> g_state{nullptr};
std::atomic<bool> g_starting{false};

// The process's helper, started on first use; null if it cannot be started.
Helper* state() {
  Helper* s = g_state.load(std::memory_order_acquire);
  if (s != nullptr && s->pid == getpid()) return s;
  if (g_starting.exchange(true, std::memory_order_acq_rel)) return nullptr;  // another caller is starting it
  s = g_state.load(std::memory_order_acquire);
  if (s == nullptr || s->pid != getpid()) {
    // A helper from before a fork has no thread in this process: it stays allocated, unused.
    auto* fresh = new Helper;
    fresh->pid = getpid();
    try {
      std::thread([fresh] { fresh->loop(); }).detach();
      g_state.store(fresh, std::memory_order_release);
      s = fresh;
    } catch (const std::system_error&) {
      delete fresh;
      s = nullptr;
    }
  }
  g_starting.store(false, std::memory_order_release);
  return s;
}

}  // namespace

Helper* acquire_helper() {
  Helper* s = state();
  if (s == nullptr || s->in_use.exchange(true, std::memory_order_acquire)) return nullptr;
  return s;
}

void start_on_helper(Helper& s, void (*fn)(void*), void* ctx) {
  s.fn = fn;
  s.ctx = ctx;
  const uint32_t n = s.started.load(std::memory_order_relaxed) + 1;
  s.started.store(n, std::memory_order_release);
  s.started.notify_one();
}

void wait_for_helper(Helper& s) {
  const uint32_t n = s.started.load(std::memory_order_relaxed);
  uint32_t done = s.finished.load(std::memory_order_acquire);
  while (done != n) done = wait_for_change(s.finished, done);
}

void release_helper(Helper& s) { s.in_use.store(false, std::memory_order_release); }

}  // namespace nomec::two_threads_detail
