// Scene evaluation: lowers a checked `ir::Module` to kernel calls and returns the output
// meshes in world space, e.g. the six placed funnels of `instance cf cubeMadeByFunnel
// endinstance`, or the merged and subdivided mesh of a `subdivision … endsubdivision`
// block. Also the whole-scene pipeline of the command line (merge → subdivide → offset →
// subdivide) for NOME 2016 files that have no pipeline blocks. Kernel and generator
// failures become diagnostics at the statement that caused them; nothing here throws.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "frontend/diagnostics/diagnostic.h"
#include "ir/ir.h"
#include "kernel/mesh.h"
#include "kernel/subdivide.h"

namespace nomec::backend {

/// A polyline or curve of an output, e.g. `polyline l (a b c) endpolyline` placed by an
/// instance: its points in world space, in order; a closed one returns to its first point.
struct Curve {
  std::vector<glm::dvec3> points;
  bool is_closed = false;
};

/// One output mesh, e.g. the faces of the top-level `instance kb kleinbottle endinstance`.
/// `soup` holds world-space positions, faces (orientation already corrected for
/// mirrors), colours, creases and provenance: `face_sources[i].source_face` is the IR node
/// index of the face statement (or of the generator) and `.instance` the IR node index of
/// the innermost instance that placed it. `mesh` is the same geometry built as a
/// winged-edge mesh (it is always a valid 2-manifold).
struct OutputMesh {
  std::string name;  // name of the scene entry, e.g. "kb"
  ir::NodeId scene_node;
  /// The polygons, which the writers read. Empty for the output of a whole-scene pipeline
  /// run with `PipelineOptions::polygon_lists` off, whose faces are only in `mesh`
  /// (`write_stl_binary` reads them there).
  kernel::PolygonSoup soup;
  kernel::Mesh mesh;
  int32_t curve_count = 0;  // polylines and curves under this entry (no faces)
  /// Their points, for drawing (previews); curves inside pipeline blocks pass through the
  /// block unchanged (a block steps faces only).
  std::vector<Curve> curves;
};

/// The most vertices one evaluation may build (`--max-vertices`): placed leaves and the
/// results of subdivisions, so a scene that multiplies instances or subdivides too far is
/// an error (`SceneTooLarge`) instead of exhausting memory. A million keeps `nomec --emit
/// stl` under about 750 MiB whatever the pipeline (measured with /usr/bin/time: placed
/// geometry costs some 250 bytes a vertex, merging it some 700, the offset of a subdivided
/// million some 190 per output vertex); the 20 million allowed before reached 5.5 GB
/// unmerged. The seed's `--merge --subdivide 2 --offset` of 100,000 placed vertices fits.
inline constexpr int64_t kDefaultMaxVertices = 1'000'000;

/// The command line's whole-scene pipeline, e.g. `--merge --subdivide 2 --offset 0.1`.
/// Subdividing or offsetting implies merging first (as the pipeline blocks do).
struct PipelineOptions {
  bool is_merge = false;
  double merge_tolerance = -1;  // < 0: 1e-4 × the bounding-box diagonal
  int32_t subdivide_levels = 0;
  kernel::VertexRule rule = kernel::VertexRule::CatmullClark;
  double offset_height = 0;  // 0: no offset
  int32_t subdivide_after_levels = 0;
  /// Not a pipeline step: the limit on what the evaluation (and the pipeline) may build.
  int64_t max_vertices = kDefaultMaxVertices;
  /// Not a pipeline step: make the output's polygon list (`OutputMesh::soup`). `nomec
  /// --emit stl` (binary) turns it off and writes from the mesh: the list of a large output
  /// is a copy of all of it (about 50 bytes a face) that only the other writers need.
  bool polygon_lists = true;
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

/// The work one evaluation did, for `Session` and `nomec --what-if`.
struct EvalCounters {
  int32_t generators_run = 0;    // generator and sweep runs
  int32_t instances_placed = 0;  // leaf instances (re)transformed into their entry's frame
  int32_t kernel_ops = 0;        // merge, subdivide, offset, lattice, zipper and delete runs
  std::set<int32_t> nodes;       // IR node indices whose value was (re)computed
  int32_t outputs_patched = 0;   // outputs made by patching the previous one's positions
  int32_t parts_patched = 0;     // parts (placed leaves, block results) whose positions were
  int32_t clusters_reused = 0;   // clusters of a block's input whose merged, stepped result was reused
  /// The outputs of `evaluate` that are new objects (recomputed), not the previous ones.
  std::vector<const OutputMesh*> new_outputs;
};

namespace eval {
class Context;
}

/// Memoized evaluation of one module, shared by `evaluate_scene` (one pass on a fresh
/// evaluator) and `Session` (kept alive across parameter changes). Every expression value,
/// generator mesh, sweep, instance world transform, placed instance, pipeline block and
/// scene entry is cached with the set of parameters it read; `invalidate(p)` drops exactly
/// the values that read `p`, so the next `evaluate` recomputes only those. With
/// `is_incremental`, placed instances and scene entries are kept too, and pipeline blocks
/// (and `pipeline`, the command line's whole-scene steps) subdivide and offset each
/// connected component separately, reusing components whose input did not change (see
/// docs/incremental.md); the geometry is the same, but the element order of such blocks'
/// meshes differs from a one-shot `evaluate_scene`.
class SceneEvaluator {
 public:
  SceneEvaluator(const ir::Module& module, bool is_incremental, PipelineOptions pipeline = {},
                 std::string pipeline_name = {}, SourceRange pipeline_where = {});
  ~SceneEvaluator();
  SceneEvaluator(const SceneEvaluator&) = delete;
  SceneEvaluator& operator=(const SceneEvaluator&) = delete;
  /// The output meshes as `evaluate_scene` (then `run_pipeline`, if `pipeline.any()`)
  /// returns them; unchanged entries are the same objects as in the previous call. A
  /// changed entry may take over the storage of its previous output when the evaluator
  /// holds the only reference to it (callers that keep a previous output keep it intact).
  std::vector<std::shared_ptr<const OutputMesh>> evaluate(DiagnosticEngine& diags,
                                                          StageTimings* timings = nullptr);
  /// Drops every cached value that read parameter `param` (call after changing its value
  /// in the module), and every value whose evaluation reported a diagnostic.
  void invalidate(ir::NodeId param);
  /// The counters since the last call, then resets them.
  EvalCounters take_counters();

 private:
  struct PipelineMemosHolder;
  std::unique_ptr<eval::Context> impl_;
  const ir::Module& module_;
  std::vector<ir::NodeId> entries_;
  std::vector<ir::NodeId> zippers_;
  bool is_incremental_;
  PipelineOptions pipeline_;
  std::string pipeline_name_;
  SourceRange pipeline_where_;
  std::vector<std::shared_ptr<const OutputMesh>> pipeline_inputs_;
  std::vector<std::shared_ptr<const OutputMesh>> pipeline_outputs_;
  std::shared_ptr<PipelineMemosHolder> pipeline_memos_;
};

/// Evaluates every entry of `module.scene`. Returns one mesh per scene entry (entries that
/// produce neither faces nor curves are dropped), followed by one mesh per `zipper`
/// statement. On failure, emits diagnostics and
/// returns what it could; callers check `diags.error_count()`.
std::vector<OutputMesh> evaluate_scene(const ir::Module& module, DiagnosticEngine& diags,
                                       StageTimings* timings = nullptr,
                                       int64_t max_vertices = kDefaultMaxVertices);

/// Applies the whole-scene pipeline: all meshes are concatenated into one (named after
/// `name`), merged, subdivided, offset and subdivided again. Errors are emitted at
/// `where` (the file). `progress` (may be empty) is told the stage being run.
std::vector<OutputMesh> run_pipeline(std::vector<OutputMesh> meshes, const PipelineOptions& options,
                                     std::string_view name, SourceRange where,
                                     DiagnosticEngine& diags, StageTimings* timings = nullptr,
                                     const std::function<void(std::string_view)>& progress = {});

}  // namespace nomec::backend
