// The Tcl 8.6 interpreter of one SLIDE scene, in the process that runs it (slide.md §6, §7):
// runs its `tclinit`/`tclupdate` blocks and `{expr …}` values with Tcl's own `expr`, in a
// safe interpreter (no exec, files, sockets, pipes, cd, exit, load; `source` reads only files
// next to the scene, through the given file reader) within a command limit and a time limit
// per script. Tk is not available headless: its widget commands are stubs, except that a
// `scale` bound to a variable records a slider. `slide create …` calls are recorded for the
// checker. Only the Tcl worker process (worker_main.cpp) and the engine's own tests make
// one: no limit inside Tcl can catch a C-stack overflow or a panic in Tcl's own commands,
// so nomec itself talks to an engine through `Interp` (interp.h), across a process boundary.
// With guard.cpp and fallback.cpp, the only code that includes <tcl.h>; one object per
// scene, no global state.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "frontend/tcl/types.h"

namespace nomec::tcl {

/// Says whether a file next to the scene exists (parselib's mesh import asks, and reads it
/// no further); when empty, `ReadFile` is asked instead.
using HasFile = std::function<bool(const std::string& path)>;

class Engine {
 public:
  /// `dir` is the scene's folder (for `source`, with trailing `/` or empty); `read_file`
  /// may be empty (then every `source` fails).
  Engine(std::string dir, ReadFile read_file, Limits limits = {}, Preset preset = {}, HasFile has_file = {});
  ~Engine();
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

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
  /// The wall time each later script may take (the Tcl worker gives each request what is
  /// left of its budget).
  void set_time_limit(int milliseconds);

  const std::vector<Slider>& sliders() const;
  const std::vector<SlideCall>& slide_calls() const;
  /// The missing files and fallbacks noticed so far, once each (cleared by the call).
  std::vector<Problem> take_notes();

  struct State;

 private:
  std::unique_ptr<State> s_;
};

/// Frees what Tcl keeps for the calling thread; a thread that made interpreters calls it
/// before it ends, after they are gone (the main thread need not). Nothing happens on a
/// thread that made none.
void finish_thread();

/// The commands a scene may not use, in the order the safety test exercises them.
const std::vector<std::string_view>& refused_commands();

}  // namespace nomec::tcl
