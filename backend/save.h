// `--emit nome`: the seed's "save" (report §7, "the current values of the sliders and the
// consolidated mesh can be saved to a new .NOME file"): the scene written back as NOME
// source that nomec itself accepts, with every slider at its current value (after `-D`
// overrides and `savedparameter` blocks), e.g. `set n 8 3 10 1` saved after `-D fp.n=5`
// becomes `set n 5 3 10 1`. Saved work (`.anom` checked with `--base`) becomes one
// self-contained file: the base scene first, then the saved work with its consolidated
// geometry (`savedworkingmesh` / `consolidate` faces, which name the base scene's
// vertices). Everything else is kept as written, comments included.
#pragma once

#include <string>
#include <string_view>

#include "frontend/source/source_manager.h"
#include "ir/ir.h"

namespace nomec::backend {

/// The saved source. `main_file` is the file the user compiled (written last); other
/// files of `sources` (a `--base` scene) come first. Parameter values are printed so that
/// reading them back gives the same doubles.
std::string to_nome(const ir::Module& module, const SourceManager& sources, std::string_view main_file);

}  // namespace nomec::backend
