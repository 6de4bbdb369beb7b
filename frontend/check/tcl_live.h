// SLIDE values that follow their sliders (docs/dialects.md, "SLIDE's Tcl"): a `{…}` value
// whose Tcl nomec's own expression reader cannot repeat (`if {$par_n >= 2} {expr 1} else
// {expr 0}`, Tcl's integer division, a value reading what a `tclupdate` block computes) is
// an `External` expression of the IR, evaluated by `TclEvaluator` whenever a slider it
// depends on moves. The evaluator replays the scene's Tcl in an interpreter of its own: the
// `tclinit` blocks and the files they sourced (as the check read them), sliders preset to
// the values they had when the scene was checked; then, per change of slider values, sets
// the slider variables as Tk would and re-runs the `tclupdate` blocks before a value that
// reads what they set. The interpreter is a Tcl worker process of the evaluator's own
// (frontend/tcl/interp.h); callers on any thread are served one evaluation at a time.
// While the scene is checked, the evaluator's Tcl shares the check's wall-clock budget;
// afterwards each change of slider values has a budget of its own, a value already
// evaluated at the current values is answered without running it again, and a worker that
// crashed or ran out of time in one move is replaced by a new one for the next.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "frontend/tcl/interp.h"
#include "ir/external.h"

namespace nomec::check {

/// The files a scene's Tcl read while it was checked (path → text, or nullopt when it could
/// not be read), so that later interpreters read the same text without the checker's file
/// reader, which need not outlive the check. Shared by the check and the evaluator.
class TclFiles {
 public:
  /// A reader that asks `inner` and remembers its answers.
  tcl::ReadFile recording(tcl::ReadFile inner);
  /// A reader that answers from what was remembered (nullopt for anything else).
  tcl::ReadFile replaying();

 private:
  std::mutex mutex_;
  std::map<std::string, std::optional<std::string>> files_;
};

/// What the evaluator's interpreter replays of a checked scene.
struct TclScene {
  std::string dir;                  // the scene's folder (for `source`)
  std::vector<std::string> init;    // the `tclinit` blocks' texts, in file order
  std::vector<std::string> update;  // the `tclupdate` blocks' texts, in file order
  struct Slider {
    std::string variable;  // `par_numS`, `oOffset(height)`
    ir::NodeId param;
    double value = 0;       // when the scene was checked (with `-D`): `tclinit` sees this
    double resolution = 0;  // Tk writes the variable with the digits this step has
  };
  std::vector<Slider> sliders;  // in the order of `inputs()`
  int move_milliseconds = 2000;  // the Tcl's budget per slider move once the scene is checked
  std::shared_ptr<TclFiles> files;
};

class TclEvaluator final : public ir::ExternalEvaluator {
 public:
  /// `check_budget`: the check's budget for the scene's Tcl, drawn on until `end_check`.
  TclEvaluator(TclScene scene, std::shared_ptr<tcl::Budget> check_budget);
  ~TclEvaluator() override;
  TclEvaluator(const TclEvaluator&) = delete;
  TclEvaluator& operator=(const TclEvaluator&) = delete;

  /// Adds a value's script (while the scene is checked); `follows_update`: it reads what a
  /// `tclupdate` block sets, so those blocks run before it when the sliders changed.
  uint32_t add(std::string script, bool follows_update);
  /// The check is over: from now on each slider move has a budget of its own, and results
  /// are remembered per move.
  void end_check();

  std::span<const ir::NodeId> inputs() const override { return inputs_; }
  ir::ExternalResult evaluate(uint32_t script, std::span<const double> values) const override;
  std::string_view text(uint32_t script) const override;

  /// How many times the `tclupdate` blocks were re-run (tests: once per change of values).
  int update_runs() const;

  struct Worker;

 private:
  std::vector<ir::NodeId> inputs_;
  std::unique_ptr<Worker> w_;
};

/// `value` as Tk's `scale` writes it into its variable: with the digits `resolution` has
/// (`2`, `0.35`), or in full when that would change it.
std::string tk_scale_text(double value, double resolution);

}  // namespace nomec::check
