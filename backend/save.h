// `--emit nome` and the preview's "Save scene with these values" / "Write slider values
// into the file": the scene written back as NOME source that nomec itself accepts, with
// every slider at its current value (after `-D` overrides or slider moves), changing
// nothing but the text of each moved slider's value, in place:
//   - a bank's `set n 8 3 10 1` after `-D fp.n=5` becomes `set n 5 3 10 1`;
//   - in a file with `savedparameter` blocks (NOME 2016 saved work), a slider they set is
//     changed in the block entry that sets it (the last one), so every save updates the
//     file's one block instead of adding a block;
//   - a SLIDE slider made by Tcl: the default argument of the `CreateScale` call that makes
//     it (`CreateScale $name $root q0x "q0x" 0.9 0 2 0.1 1 horizontal`), or the number a
//     `set` gives the variable a `scale -variable` reads (`set x0 1.0`,
//     `set [subst $this](v0) 1.60`); a slider a procedure of another file makes with its
//     own default (`CreateSLIDESubdivisionUI .ui oSubdivision`) gets one line,
//     `set oSubdivision(subdivisions) 3`, before the `tclinit` command that makes it (and
//     that line is the one rewritten by the next save).
// A slider is moved when its value differs from the one the file as written gives it; the
// others are not touched, whatever their text. Values are written with the fewest decimals
// that read back as the same slider position (within a millionth of its step):
// 0.30000000000000004 on a slider of step 0.1 is `0.3`; a token that already reads as the
// value keeps its spelling (`0.90`).
// Saved work (`.anom` checked with its base scene) becomes one self-contained file: the
// base scene first, then the saved work with its consolidated geometry; a flat mesh file
// given as the scene is written as NOME points and faces. Included files stay included
// (their text is not copied in). Comments and layout are kept as written.
// The text is found without a syntax tree, so callers check the saved text again and ask
// `lost_values` whether it gives every slider its value before they write it.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "frontend/source/source_manager.h"
#include "ir/ir.h"

namespace nomec::backend {

/// A slider whose value has no place in the saved text: no value of its own in the files
/// saved (made by a Tcl helper file or by nomec's stand-in for SLIDE's lost packages,
/// defined in an included file), or a value spelt as an expression.
struct UnsavedSlider {
  ir::NodeId param;
  std::string reason;  // e.g. "its value is not written in `G3adjust.slf` (a Tcl helper sets it)"
};

struct SavedScene {
  std::string text;
  /// The sliders `text` cannot carry; the saved file gives them their value as written.
  std::vector<UnsavedSlider> unsaved;
};

/// The saved source. `module` holds the current values; `as_written` is the module of the
/// same file checked as written (without `-D` or moves; `module` itself when nothing moved):
/// a slider whose value is the same in both is left as written. `main_file` is the file
/// the user compiled (written last); `base_file` (a `.anom`'s base scene, or empty) comes first.
SavedScene save_scene(const ir::Module& module, const ir::Module& as_written, const SourceManager& sources,
                      std::string_view main_file, std::string_view base_file = {});

/// What writing `saved` would lose: one line per slider of `module` that `saved_module` (the
/// saved text checked again) does not give its value (e.g. "slider `oSub.subdivisions` = 3
/// cannot be saved: its value is not written in `s.slf` …"); empty when the save is faithful.
std::vector<std::string> lost_values(const ir::Module& module, const SavedScene& saved, const ir::Module& saved_module);

/// The text of `value` as a slider of step `step` saves it: the fewest decimals (fixed
/// notation) that read back within a millionth of a step, else the shortest text that
/// reads back exactly (`0.30000000000000004` at step 0.1 is `0.3`; at step 0, exact).
std::string slider_value_text(double value, double step);

}  // namespace nomec::backend
