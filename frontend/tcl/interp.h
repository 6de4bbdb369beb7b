// nomec's handle on one SLIDE scene's Tcl interpreter, which runs in a process of its own
// (`nomec-tcl-worker`, worker_main.cpp): the same operations as the engine (engine.h) —
// run a `tclinit`/`tclupdate` block, evaluate an `{expr …}` value, read, set and watch
// variables, the sliders and `slide create` calls recorded — carried over a socket
// (protocol.h). Tcl's own commands can overflow the C stack or panic, and a scene can loop
// in one command no limit interrupts; in the worker that ends only the worker. Every
// operation draws on a wall-clock budget (for the whole file's Tcl, or per slider move);
// past it the worker is killed. A worker that crashed, was killed or could not start is
// one problem, returned by the operation it happened in (`Crashed`, `Limit`,
// `Unavailable`); the operations after it run nothing and return a `Stopped` problem. The
// scene's files and `-D` values are asked of nomec (the callbacks given here) while the
// scene's Tcl runs. Starts the worker on first use. Operations may be called from any
// thread, one at a time.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "frontend/tcl/types.h"

namespace nomec::tcl {

/// Wall time a scene's Tcl may still take, shared by the interpreters that run it (the
/// check's, and the one that re-evaluates values as sliders move). Not thread-safe: share it
/// only between interpreters used one at a time.
class Budget {
 public:
  /// `scope` says what the time is for in messages ("for each slider move"; "" for a file).
  explicit Budget(int milliseconds, std::string scope = "")
      : total_ms_(milliseconds), left_us_(int64_t{milliseconds} * 1000), scope_(std::move(scope)) {}
  int total_ms() const { return total_ms_; }
  const std::string& scope() const { return scope_; }
  int64_t left_us() const { return left_us_; }
  void spend(int64_t us) { left_us_ -= us; }

 private:
  int total_ms_;
  int64_t left_us_;
  std::string scope_;
};

class Interp {
 public:
  /// `dir` is the scene's folder (with trailing `/`, or empty); `read_file` reads what
  /// `source` and `slide import` name (a path `dir` + name; may be empty: every `source`
  /// fails); `limits.milliseconds` is this interpreter's budget until `use_budget`.
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
  std::optional<std::string> get(std::string_view name);
  /// Sets a global variable (a `-D` override of a slider before values are evaluated).
  void set(std::string_view name, std::string_view value);
  /// Records reads of this global variable by later `value` calls.
  void watch(const std::string& name);

  const std::vector<Slider>& sliders() const;
  const std::vector<SlideCall>& slide_calls() const;
  /// The missing files and fallbacks noticed so far, once each, and the problem that stopped
  /// the worker when it stopped in `get`, `set` or `watch` (cleared by the call).
  std::vector<Problem> take_notes();

  /// Draws wall time from `budget` from now on (shared with other interpreters).
  void use_budget(std::shared_ptr<Budget> budget);
  /// True once the worker crashed, was stopped or could not start: nothing more runs.
  bool stopped() const;

  struct State;

 private:
  std::unique_ptr<State> s_;
};

/// The Tcl worker program nomec starts: `$NOMEC_TCL_WORKER` when set, else
/// `nomec-tcl-worker` beside the running program, in `../libexec/nomec/` or `../lib/nomec/`
/// from it, or in the build tree; "" when none is found.
const std::string& worker_path();

}  // namespace nomec::tcl
