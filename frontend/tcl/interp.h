// The embedded Tcl 8.6 interpreter of one SLIDE scene (slide.md §6, §7): runs its
// `tclinit`/`tclupdate` blocks and `{expr …}` values with Tcl's own `expr`, in a safe
// interpreter (no exec, files, sockets, cd, exit, load; `source` reads only files next to
// the scene, through the checker's file reader) within command and time limits. Tk is not
// available headless: its widget commands are stubs, except that a `scale` bound to a
// variable records a slider. `slide create …` calls are recorded for the checker. The only
// code that includes <tcl.h>; one object per checked file, no global state.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
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
};

enum class ProblemKind : uint8_t {
  Error,          // a Tcl error (message and line)
  Limit,          // the command-count or time limit stopped the script
  Refused,        // a command a scene may not use (exec, open for writing, socket, cd, exit, load …)
  MissingSource,  // `source FILE` of a file that cannot be read
  Fallback,       // a missing SLIDEUI.tcl/MATH.tcl/SLFCONSTS.tcl/MOVIE.tcl replaced by nomec's own
  Memory,         // a value or memory use past nomec's bounds refused, or Tcl gave up (see guard.h)
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
  int milliseconds = 10000;       // wall time per script
};

class Interp {
 public:
  /// `dir` is the scene's folder (for `source`, with trailing `/` or empty); `read_file`
  /// may be empty (then every `source` fails).
  Interp(std::string dir, ReadFile read_file, Limits limits = {}, Preset preset = {});
  ~Interp();
  Interp(const Interp&) = delete;
  Interp& operator=(const Interp&) = delete;

  /// Runs a script at global level (a `tclinit` block's text without its braces); records
  /// which watched variables it read.
  Outcome run(std::string_view script);
  /// `run`, also recording the global variables the script writes or creates (by name; an
  /// array by its name), for a `tclupdate` block: values that read them follow it.
  Outcome run_tracking_writes(std::string_view script);
  /// Evaluates a SLIDE value: `expr` script text (`expr $a*2`, `if {…} {expr 1} …`) whose
  /// result must be a number; records which watched variables it read.
  Outcome value(std::string_view script);
  /// A global variable's value (`name` or `arr(key)`), or nullopt when unset.
  std::optional<std::string> get(std::string_view name) const;
  /// Sets a global variable (a `-D` override of a slider before values are evaluated).
  void set(std::string_view name, std::string_view value);
  /// Records reads of this global variable by later `value` calls.
  void watch(const std::string& name);

  const std::vector<Slider>& sliders() const;
  const std::vector<SlideCall>& slide_calls() const;
  /// The missing files and fallbacks noticed so far, once each (cleared by the call).
  std::vector<Problem> take_notes();

  struct State;

 private:
  std::unique_ptr<State> s_;
};

/// `\r*\n` → `\n` (several real SLIDE files end lines with `\r\r\n`, which breaks Tcl's
/// `\`-continuations; slide.md §1); line numbers stay the same.
std::string normalize_newlines(std::string_view text);

/// Frees what Tcl keeps for the calling thread; a thread that made interpreters calls it
/// before it ends, after they are gone (the main thread need not). Nothing happens on a
/// thread that made none.
void finish_thread();

/// The commands a scene may not use, in the order the safety test exercises them.
const std::vector<std::string_view>& refused_commands();

}  // namespace nomec::tcl
