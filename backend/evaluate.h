// Scene evaluation: lowers a checked `ir::Module` to kernel calls and returns the output
// meshes in world space, e.g. the six placed funnels of `instance cf cubeMadeByFunnel
// endinstance`, or the merged and subdivided mesh of a `subdivision … endsubdivision`
// block. Also the whole-scene pipeline of the command line (merge → subdivide → offset →
// subdivide) for NOME 2016 files that have no pipeline blocks. Kernel and generator
// failures become diagnostics at the statement that caused them; nothing here throws.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "frontend/diagnostics/diagnostic.h"
#include "ir/ir.h"
#include "kernel/mesh.h"
#include "kernel/subdivide.h"

namespace nomec::backend {

/// One output mesh, e.g. the faces of the top-level `instance kb kleinbottle endinstance`.
/// `soup` holds world-space positions, faces (orientation already corrected for
/// mirrors), colours, creases and provenance: `face_sources[i].source_face` is the IR node
/// index of the face statement (or of the generator) and `.instance` the IR node index of
/// the innermost instance that placed it. `mesh` is the same geometry built as a
/// winged-edge mesh (it is always a valid 2-manifold).
struct OutputMesh {
  std::string name;  // name of the scene entry, e.g. "kb"
  ir::NodeId scene_node;
  kernel::PolygonSoup soup;
  kernel::Mesh mesh;
  int32_t curve_count = 0;  // polylines and curves under this entry (no faces)
};

/// The command line's whole-scene pipeline, e.g. `--merge --subdivide 2 --offset 0.1`.
/// Subdividing or offsetting implies merging first (as the pipeline blocks do).
struct PipelineOptions {
  bool is_merge = false;
  double merge_tolerance = -1;  // < 0: 1e-4 × the bounding-box diagonal
  int32_t subdivide_levels = 0;
  kernel::VertexRule rule = kernel::VertexRule::CatmullClark;
  double offset_height = 0;  // 0: no offset
  int32_t subdivide_after_levels = 0;
  bool any() const {
    return is_merge || subdivide_levels > 0 || offset_height > 0 || subdivide_after_levels > 0;
  }
};

/// Wall-clock milliseconds per stage (filled by the functions below).
struct StageTimings {
  double evaluate_ms = 0;
  double merge_ms = 0;
  double subdivide_ms = 0;
  double offset_ms = 0;
};

/// Evaluates every entry of `module.scene`. Returns one mesh per scene entry (entries that
/// produce neither faces nor curves are dropped), followed by one mesh per `zipper`
/// statement. On failure, emits diagnostics and
/// returns what it could; callers check `diags.error_count()`.
std::vector<OutputMesh> evaluate_scene(const ir::Module& module, DiagnosticEngine& diags,
                                       StageTimings* timings = nullptr);

/// Applies the whole-scene pipeline: all meshes are concatenated into one (named after
/// `name`), merged, subdivided, offset and subdivided again. Errors are emitted at
/// `where` (the file). `progress` (may be empty) is told the stage being run.
std::vector<OutputMesh> run_pipeline(std::vector<OutputMesh> meshes, const PipelineOptions& options,
                                     std::string_view name, SourceRange where,
                                     DiagnosticEngine& diags, StageTimings* timings = nullptr,
                                     const std::function<void(std::string_view)>& progress = {});

}  // namespace nomec::backend
