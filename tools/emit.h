// The outputs of `nomec --emit`: meshes and summaries (emit_mesh.cpp) and the saved scene
// (emit_nome.cpp). Each returns the number of errors (diagnostics or a failed write).
#pragma once

#include <string>

#include "frontend/source/source_manager.h"
#include "ir/ir.h"
#include "tools/cli.h"
#include "tools/diagnostics_output.h"

namespace nomec::tools {

/// `--emit stl|obj|ply|summary`: evaluates the checked scene, runs the --merge/--subdivide/
/// --offset pipeline and writes the format (`--time-report` prints each stage's time).
int emit_meshes(const Cli& cli, const std::string& path, const SourceManager& sources, const ir::Module& module,
                double check_ms, DiagnosticOutput& out);

/// `--emit nome`: the scene saved with its current slider values (default target
/// `NAME.saved.EXT` in the working directory).
int emit_nome(const Cli& cli, const std::string& path, const SourceManager& sources, const ir::Module& module);

}  // namespace nomec::tools
