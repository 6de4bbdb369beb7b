// The outputs of `nomec --emit`: meshes and summaries (emit_mesh.cpp) and the saved scene
// (emit_nome.cpp). Each returns the number of errors (diagnostics, a refused or failed
// write). Neither overwrites a file the check read (`inputs`: the scene, its base scene,
// included files, meshes, Tcl files it sources), however the output names it.
#pragma once

#include <string>
#include <vector>

#include "frontend/check/check.h"
#include "frontend/source/source_manager.h"
#include "ir/ir.h"
#include "tools/cli.h"
#include "tools/diagnostics_output.h"

namespace nomec::tools {

/// `--emit stl|obj|ply|summary`: evaluates the checked scene, runs the --merge/--subdivide/
/// --offset pipeline and writes the format (`--time-report` prints each stage's time).
int emit_meshes(const Cli& cli, const std::string& path, const SourceManager& sources, const ir::Module& module,
                const std::vector<std::string>& inputs, double check_ms, DiagnosticOutput& out);

/// `--emit nome`: the scene saved with its current slider values (default target
/// `NAME.saved.EXT` in the working directory). The saved text is checked again (with
/// `options`, less the `-D` overrides) before it is written: it must give every slider the
/// value it has now, or nothing is written and the sliders it cannot carry are named.
int emit_nome(const Cli& cli, const std::string& path, const SourceManager& sources, const CheckResult& result,
              const CheckOptions& options, const std::vector<std::string>& inputs);

}  // namespace nomec::tools
