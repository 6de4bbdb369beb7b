// Two-way parallelism: work split into two parts (the kernel's passes over large flat
// arrays by index range, the parser's pieces of a large text by bytes) runs its second part
// on another thread. Rationale: the machines nomec targets have few cores and the work is
// memory-bound, so two parts are what pays off, and one kept second thread rather than a
// pool. The second thread is kept between calls (each level of a subdivision runs four
// passes in a row, and starting a thread for each cost about 50 µs on the 2-core virtual
// machine), and waits for the next part by spinning briefly, then sleeping (see
// two_threads.cpp).
#pragma once

#include <exception>
#include <system_error>
#include <thread>
#include <type_traits>
#include <utility>

namespace nomec {

/// True if the machine runs at least two threads at once (so splitting a pass can pay off).
inline bool has_two_hardware_threads() {
  static const bool value = std::thread::hardware_concurrency() >= 2;
  return value;
}

namespace two_threads_detail {

/// The kept second thread (two_threads.cpp), lent to one caller at a time.
struct Helper;
/// The helper, reserved for the caller until `release_helper`; null if another caller
/// holds it (or its thread cannot be started): the caller then starts a thread of its own.
Helper* acquire_helper();
/// Runs `fn(ctx)` on the helper; `wait_for_helper` returns once it has returned.
void start_on_helper(Helper& helper, void (*fn)(void*), void* ctx);
void wait_for_helper(Helper& helper);
void release_helper(Helper& helper);

}  // namespace two_threads_detail

/// Calls `part(0)` on the calling thread and `part(1)` on a second thread, and returns when
/// both have returned. The parts must not write what the other reads or writes, so the
/// result does not depend on their timing: if no thread can be started, `part(1)` simply
/// runs after `part(0)`. An exception thrown by a part is rethrown here once both are done
/// (the calling thread's first). The second part runs on the kept helper thread when no
/// other caller holds it (state it leaves in thread-local variables stays for its next
/// part), else on a thread started for it.
template <typename Part>
void run_two_parts(Part&& part) {
  std::exception_ptr second_error;
  struct Second {
    std::remove_reference_t<Part>* part;
    std::exception_ptr* error;
    static void run(void* self) {
      const Second& s = *static_cast<const Second*>(self);
      try {
        (*s.part)(1);
      } catch (...) {
        *s.error = std::current_exception();
      }
    }
  } second_part{&part, &second_error};

  namespace detail = two_threads_detail;
  detail::Helper* helper = detail::acquire_helper();
  std::thread second;
  if (helper != nullptr) {
    detail::start_on_helper(*helper, &Second::run, &second_part);
  } else {
    try {
      second = std::thread(&Second::run, &second_part);
    } catch (const std::system_error&) {
      part(0);
      part(1);
      return;
    }
  }
  // Waits for the second part, wherever it runs.
  auto join = [&] {
    if (helper != nullptr) {
      detail::wait_for_helper(*helper);
      detail::release_helper(*helper);
    } else {
      second.join();
    }
  };
  try {
    part(0);
  } catch (...) {
    join();
    throw;
  }
  join();
  if (second_error) std::rethrow_exception(second_error);
}

}  // namespace nomec
