// What a SLIDE scene's Tcl gives the checker, shared by the interpreter that runs it
// (`Engine`, engine.h, inside the Tcl worker process) and the checker's handle on that
// process (`Interp`, interp.h): sliders, `slide create` calls, problems, the outcome of a
// script, and the callbacks through which the scene's Tcl reads files and `-D` values.
// Plain data; nothing here includes <tcl.h>.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace nomec::tcl {

/// Reads a file the scene sources (a path next to the scene); nullopt when it cannot.
using ReadFile = std::function<std::optional<std::string>(const std::string& path)>;

/// A Tk `scale` bound to a variable: `scale .w.x -from 0 -to 2 -resolution 0.1 -var par_x`.
struct Slider {
  std::string variable;  // `par_x`, or `param(rradius)` for an array element
  double value = 0, from = 0, to = 100, resolution = 1;
  bool rounded = false;  // Tk rounded or clamped the variable's value when the scale was made
  double written = 0;    // the value the file set before Tk rounded it (when `rounded`)
  bool operator==(const Slider&) const = default;
};

enum class ProblemKind : uint8_t {
  Error,          // a Tcl error (message and line)
  Limit,          // the command-count limit or the time budget stopped the script
  Refused,        // a command a scene may not use (exec, open for writing, socket, cd, exit, load …)
  MissingSource,  // `source FILE` of a file that cannot be read
  Fallback,       // a missing SLIDEUI.tcl/MATH.tcl/SLFCONSTS.tcl/MOVIE.tcl replaced by nomec's own
  Memory,         // a value or memory use past nomec's bounds refused, or Tcl gave up (see guard.h)
  Crashed,        // the Tcl worker process died (a signal, e.g. Tcl's C stack overflowed)
  Unavailable,    // the Tcl worker could not be started (not installed, no processes left)
  Stopped,        // the scene's Tcl was stopped by an earlier problem, already reported
};

struct Problem {
  ProblemKind kind = ProblemKind::Error;
  std::string message;
  int line = 0;       // 1-based line in the evaluated script, 0 when unknown
  std::string trace;  // Tcl's errorInfo (Error), or the file named (MissingSource, Fallback)
};

/// Result of running a script or evaluating a value.
struct Outcome {
  bool ok = false;
  std::string result;                // Tcl's result when ok
  double number = 0;                 // for values: the result as a number
  std::vector<Problem> problems;     // the error that stopped it, and notes (missing files)
  std::vector<std::string> reads;    // watched variables the script read (see `watch`)
  std::vector<std::string> writes;   // global variables it set or made (`run_tracking_writes`)
};

/// `slide create TYPE NAME ARGS…` or `slide delete TYPE NAME`, as Tcl passed them; or
/// `import import NAME FILE` for a mesh file next to the scene that parselib's
/// `CreateSTLObject`/`CreateSIFObject` read (`slide import NAME FILE` checked it is there).
struct SlideCall {
  std::vector<std::string> words;  // after `slide`
};

/// A `-D` value for a variable a `scale` is about to bind (given its range), set in place of
/// the file's default so the rest of `tclinit` reads it.
using Preset = std::function<std::optional<double>(const std::string& variable, double from, double to)>;

struct Limits {
  int64_t commands = 1'000'000;  // Tcl commands per script
  /// Wall time for everything one interpreter runs (its budget), unless a shared `Budget` is
  /// given (interp.h): a scene's eight looping blocks take this long in all, not eight times.
  int milliseconds = 10000;
};

/// `\r*\n` → `\n` (several real SLIDE files end lines with `\r\r\n`, which breaks Tcl's
/// `\`-continuations; slide.md §1); line numbers stay the same.
std::string normalize_newlines(std::string_view text);

}  // namespace nomec::tcl
