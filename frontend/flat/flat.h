// Readers of flat mesh files: `.sif` (SIF_SFF, read as NOME 2016 read it), Wavefront `.obj`
// and `.stl` (binary and ASCII). Each turns a file's text (already in the SourceManager)
// into an `ir::FlatGeometry`: vertices named `v0, v1, …` in order and faces over them, with
// every problem a diagnostic at its place in the file (file:line:col). Never throws; a
// malformed file gives the faces that could be read. The checker makes the result a
// `FlatMesh` IR node (a scene of its own, or a mesh an `include` defines).
#pragma once

#include <memory>
#include <optional>
#include <string_view>

#include "frontend/diagnostics/diagnostic.h"
#include "frontend/source/source_manager.h"
#include "ir/nodes.h"

namespace nomec::flat {

/// The format a path names by its extension (`.sif`, `.obj`, `.stl`, any case), if any.
std::optional<ir::FlatFormat> format_of_path(std::string_view path);

/// NOME 2016 merged a `.sif` vertex into an earlier one at most this far away.
inline constexpr double kSifWeldDistance = 0.001;

struct ReadOptions {
  /// `.sif` only: consecutive triangles that share an edge (with opposite directions, as
  /// neighbours in one orientation do) become one quad, the seed report's intention (§7.1);
  /// NOME 2016 had it switched off, so it is off by default.
  bool sif_quads = false;
};

/// Reads file `file` of `sources` as `format`. Always returns a geometry (possibly empty).
std::shared_ptr<const ir::FlatGeometry> read(const SourceManager& sources, FileId file, ir::FlatFormat format,
                                             DiagnosticEngine& diags, const ReadOptions& options = {});

// One reader per format (the files sif.cpp, obj.cpp, stl.cpp).
std::shared_ptr<const ir::FlatGeometry> read_sif(const SourceManager& sources, FileId file, DiagnosticEngine& diags,
                                                 const ReadOptions& options = {});
std::shared_ptr<const ir::FlatGeometry> read_obj(const SourceManager& sources, FileId file, DiagnosticEngine& diags);
std::shared_ptr<const ir::FlatGeometry> read_stl(const SourceManager& sources, FileId file, DiagnosticEngine& diags);

}  // namespace nomec::flat
