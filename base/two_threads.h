// Two-way parallelism: work split into two parts (the kernel's passes over large flat
// arrays by index range, the parser's pieces of a large text by bytes) runs its second part
// on another thread. Rationale: the machines nomec targets have few cores and the work is
// memory-bound, so two parts are what pays off; a pool would only add state.
#pragma once

#include <exception>
#include <system_error>
#include <thread>
#include <utility>

namespace nomec {

/// True if the machine runs at least two threads at once (so splitting a pass can pay off).
inline bool has_two_hardware_threads() {
  static const bool value = std::thread::hardware_concurrency() >= 2;
  return value;
}

/// Calls `part(0)` on the calling thread and `part(1)` on a second thread, and returns when
/// both have returned. The parts must not write what the other reads or writes, so the
/// result does not depend on their timing: if no thread can be started, `part(1)` simply
/// runs after `part(0)`. An exception thrown by a part is rethrown here once both are done
/// (the calling thread's first).
template <typename Part>
void run_two_parts(Part&& part) {
  std::exception_ptr second_error;
  std::thread second;
  try {
    second = std::thread([&part, &second_error] {
      try {
        part(1);
      } catch (...) {
        second_error = std::current_exception();
      }
    });
  } catch (const std::system_error&) {
    part(0);
    part(1);
    return;
  }
  try {
    part(0);
  } catch (...) {
    second.join();
    throw;
  }
  second.join();
  if (second_error) std::rethrow_exception(second_error);
}

}  // namespace nomec
