// Resource guards of the embedded interpreter (see interp.h): a `.slf` file is code, and a
// few Tcl commands turn a short script into gigabytes (`string repeat x 1e9`, `append s $s`
// in a loop, `lrepeat`, `format %1000000000s`, `binary format x1e9` …), which makes Tcl
// abort the whole process when memory runs out. The guards refuse, before it is built, any
// value larger than `kMaxValue` characters or list elements, check every command's
// arguments, watch the interpreter's memory growth, and turn a Tcl panic into an error of
// the script instead of an abort. Internal to frontend/tcl.
#pragma once

#include <tcl.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <type_traits>

namespace nomec::tcl {

/// The largest value (characters of a string, elements of a list) a scene's Tcl may build.
constexpr int64_t kMaxValue = 4'000'000;
/// The most decimal digits of a whole number a scene's Tcl may hand to a command or return:
/// Tcl's bignums are cheap to compute but quadratic to print (200,000 digits take ~20 s in one
/// command, which no limit interrupts), and no scene needs more.
constexpr int64_t kMaxDigits = 10'000;
/// The most memory a scene's Tcl may hold beyond what it held when the script started.
constexpr size_t kMaxGrowth = size_t{256} << 20;

struct Guard {
  Tcl_Interp* interp = nullptr;
  std::optional<std::string> refusal;  // why the guard stopped the script (memory), when it did
  size_t baseline = 0;                 // heap in use when the script started
  uint64_t commands = 0;               // commands seen by the trace
};

/// Wraps the commands that amplify their input and traces every command (which also turns
/// off Tcl's inline compilation, so every command passes the trace and the limits).
void install_guards(Guard& g);
/// Called before each script: the memory baseline.
void arm_guard(Guard& g);
/// When `o` is a whole number (Tcl bignum) of more than kMaxDigits digits, a message saying
/// so, naming it `what`; nothing otherwise. Never builds the number's text.
std::optional<std::string> too_many_digits(Tcl_Obj* o, const char* what);
/// Heap bytes in use (0 where the C library cannot tell).
size_t heap_in_use();

/// Calls `fn(arg)`; a Tcl panic (a value past Tcl's 2 GB limit, memory exhausted) inside it
/// returns false with Tcl's message instead of aborting. The interpreter must not be used
/// again after that. `fn` must not own anything with a destructor (the panic jumps out).
bool guarded_call_raw(void (*fn)(void*), void* arg, std::string* panic_message);

/// `guarded_call_raw` for a callable that only touches the interpreter (see there).
template <typename F>
bool guarded_call(std::string* panic_message, F&& f) {
  return guarded_call_raw([](void* p) { (*static_cast<std::remove_reference_t<F>*>(p))(); }, &f, panic_message);
}

}  // namespace nomec::tcl
