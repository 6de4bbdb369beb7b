// The evaluator's context: the state one evaluation of a module shares between its
// concerns (the module, its cache, the work counters, where in the scene the walk is, the
// entry or block being collected part by part) and the concerns themselves as free
// functions, one file each (listed below), in the manner of the checker.
#pragma once

#include <functional>
#include <glm/mat4x4.hpp>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "backend/eval/eval_cache.h"
#include "backend/eval/parts.h"
#include "backend/eval/steps.h"
#include "backend/evaluate.h"
#include "ir/ir.h"
#include "kernel/topology.h"

namespace nomec::backend::eval {

/// One part of a scene entry or block's input collected part by part (incremental only).
struct EntryPart {
  Placement* placement;                   // a placed leaf (built on demand), or
  std::shared_ptr<const Collected> part;  // its faces, or a part of a block's result
  const kernel::Mesh* mesh;               // a block part's built mesh
};

/// The scene entry or block being collected part by part: its faces, its parts in order,
/// whether it holds anything else (then it is built whole), whether the parts are not yet
/// appended to its faces (see `make_eager`), and the polylines counted on it directly.
struct Sink {
  Collected* out = nullptr;
  std::vector<EntryPart> parts;
  bool is_pure = true;
  bool is_deferred = false;
  int32_t direct_curves = 0;
};

/// Per scene entry assembled from parts: its last output and parts, for `patch_entry`.
/// Not a cached value (never invalidated): a base that is checked part by part.
struct EntryLayout {
  std::shared_ptr<const OutputMesh> out;
  std::vector<std::shared_ptr<const Collected>> parts;
  int32_t direct_curves = 0;
};

// The bounding boxes of a block's input part (all its used vertices, and its border
// vertices), kept with the part object they describe.
struct PartBounds {
  std::shared_ptr<const Collected> part;
  kernel::BoundingBox all;
  kernel::BoundingBox border;  // empty (min > max) if the part has no border
};

// One cluster of a block's input parts (see `run_block_by_clusters`) and its result.
struct ClusterMemo {
  std::vector<std::shared_ptr<const Collected>> parts;
  double tolerance = 0;
  std::vector<Step> steps;
  bool any_color = false;
  std::shared_ptr<const Collected> result;
  ComponentMemo components;
};

// What a block keeps between evaluations: per-part bounds and per-cluster results when it
// ran by clusters, or the per-component results when it ran on its whole input.
struct BlockMemo {
  std::unordered_map<const Collected*, PartBounds> bounds;
  std::vector<ClusterMemo> clusters;
  ComponentMemo components;
};

/// Where the walk is when a leaf is placed: the transform and colour from above, the
/// instance path for messages (`cf.fun3`), and the innermost instance.
struct Placing {
  glm::dmat4 t{1.0};
  std::optional<glm::vec3> color;
  std::string path;
  ir::NodeId inst;
};

class Context {
 public:
  Context(const ir::Module& m, bool is_incremental);

  const ir::Module& m;
  const bool is_incremental;
  EvalCache cache;
  EvalCounters counters;
  /// The instance that first places each group or block (index by node), for world
  /// transforms of instances inside them.
  std::vector<ir::NodeId> placer;
  /// Every face a `delete` block names (resolved by the checker).
  std::vector<const ir::DeletedFace*> deletes;
  bool has_deletes() const { return !deletes.empty(); }
  int ref_depth = 0;
  int32_t context = -1;        // the scene entry or block being evaluated (placement keys)
  std::vector<int32_t> chain;  // instances, groups and blocks on the way to the current leaf
  Sink* sink = nullptr;        // the entry or block collected part by part, if any
  // The parts of the entry just collected, its direct polylines, and whether its mesh was
  // assembled (or patched) from them.
  std::vector<EntryPart> entry_parts;
  int32_t entry_direct_curves = 0;
  bool is_entry_assembled = false;
  std::map<int32_t, EntryLayout> layouts;
  std::map<int32_t, BlockMemo> block_memos;
  std::map<int32_t, std::string> instance_paths;  // for messages about faces
  /// Vertices this evaluation may still build (PipelineOptions::max_vertices), and whether
  /// it ran out (reported once; nothing more is placed).
  int64_t vertex_limit = kDefaultMaxVertices;
  int64_t vertex_budget = kDefaultMaxVertices;
  bool is_budget_exhausted = false;
  /// The plan (placement.cpp, `plan_fits`; each node's count is memoized in `cache.plans`):
  /// the nodes being counted (a cycle counts nothing), each scene entry's count as last
  /// planned, kept for entries an update reuses, and each mesh's vertex count (fixed by the IR).
  std::vector<int32_t> planning;
  std::unordered_map<int32_t, int64_t> entry_plans;
  std::unordered_map<int32_t, int64_t> mesh_vertex_counts;

  DiagnosticEngine& diags() { return cache.recorder.diags(); }
  /// True if `out` is the faces of the entry or block being collected part by part.
  bool collects(const Collected& out) const { return sink != nullptr && sink->out == &out; }
};

// ---- values.cpp: operands, transforms, colours ----
/// Expression `i` of operand `o` (memoized with the parameters it reads); `fallback` when
/// absent or not evaluable (reported).
double scalar(Context& c, ir::OperandId o, size_t i, double fallback);
glm::dvec3 vec3(Context& c, ir::OperandId o, double fallback = 0);
/// A transform chain in written order (the first written acts first).
glm::dmat4 local(Context& c, std::span<const ir::TransformOp> ops);
/// World transform of an instance as first placed in the scene (also for hidden ones).
glm::dmat4 world_of(Context& c, ir::NodeId inst, int depth = 0);
/// The colour of a surface (`surface S color (…)`), if it has one.
std::optional<glm::vec3> surface_color(Context& c, ir::NodeId surface);
std::string short_name(std::string_view qualified);

// ---- report.cpp: kernel errors as diagnostics at the faces that caused them ----
void report(Context& c, const kernel::KernelError& e, const kernel::PolygonSoup& soup, SourceRange fallback,
            std::string_view what);

// ---- generated.cpp: generators and paths ----
/// The generator of node `gen` run once (memoized); null after a reported error.
const Generated* generated(Context& c, ir::NodeId gen, std::string_view inst_path);
/// Is flag `f` set (present, and its value, if any, not 0)?
bool flag_set(Context& c, const ir::FlagArg& f);
/// The points of a path (a polyline's vertices, or a generated curve), in order, and
/// whether it is closed.
struct PathPoints {
  std::vector<glm::dvec3> points;
  std::vector<std::string> names;
  bool is_closed = false;
};
PathPoints path_points(Context& c, ir::NodeId path, std::string_view inst_path);

// ---- sweeps.cpp: sweeps, sweepmorphs and morph visualizers ----
/// The sweep or sweepmorph of node `sweep` for one instance path (memoized); nullopt after
/// an error.
std::optional<kernel::PolygonSoup> sweep(Context& c, ir::NodeId sweep, std::string_view inst_path);
/// The vertex of `soup` (the sweep's) that NOME3 name `name` denotes, or -1: `v{k}_{i}`, and
/// NOME3's repeated names that nomec welds — `v{k}_{n}` of a closed n-point cross-section is
/// `v{k}_0`, and ring K+1 of a closed K-ring path is ring 1.
int32_t sweep_vertex(Context& c, ir::NodeId sweep, std::string_view inst_path, const kernel::PolygonSoup& soup,
                     std::string_view name);
/// The cross-section a morphvisualizer shows, as a line strip `v{index}_{i}` placed on its
/// ring of the sweepmorph; nullopt after an error.
std::optional<Generated> morph_visualizer(Context& c, ir::NodeId visualizer, std::string_view inst_path);

// ---- meshes.cpp: meshes and vertex positions ----
/// Adds the faces of a mesh (or object / saved mesh) in its local frame, with its creases.
void mesh(Context& c, ir::NodeId mesh_id, const Placing& at, Collected& out);
/// The vertices `mesh` places for a mesh: one per distinct vertex its faces name (memoized).
int64_t mesh_vertex_count(Context& c, ir::NodeId mesh_id);
/// The soup of a flat mesh file: its vertices `v0…` and faces, in the file's frame.
kernel::PolygonSoup flat_soup(const ir::FlatMeshData& flat);
/// World position of a vertex reference (a point, or a vertex through instances).
std::optional<glm::dvec3> ref_position(Context& c, const ir::VertexRef& ref, std::string_view inst_path);
/// The position of a point node, or of a NOME3 controlpoint (its point's, compat.md E2).
std::optional<glm::dvec3> point_position(Context& c, ir::NodeId point);

// ---- placement.cpp: walking instances and groups down to leaves ----
/// Adds instance `inst` placed by `parent_t`.
void instance(Context& c, ir::NodeId inst, const glm::dmat4& parent_t, std::optional<glm::vec3> color,
              const std::string& parent_path, Collected& out, int depth);
/// Adds the target `tid` of an instance, placed by `at`.
void target(Context& c, ir::NodeId tid, const Placing& at, Collected& out, int depth);
/// Is SLIDE's level of detail `lod` (an instance's or group's) `SLF_OFF`: not drawn? SLIDE
/// draws `SLF_BOUND` and `SLF_EDGES` as a box or wires; nomec draws them in full.
bool is_off(Context& c, ir::OperandId lod);
/// Appends the parts collected so far to the sink's faces and stops deferring.
void make_eager(Context& c);
/// Takes `vertices` from the evaluation's vertex budget for placing `path`; false (and one
/// SceneTooLarge error at `at`) when the budget is exhausted. The walk stops once it is.
bool spend_vertices(Context& c, int64_t vertices, SourceRange at, std::string_view path);
/// Before anything is built: counts the vertices the scene entries `entries` would place
/// (instances × the vertices of their leaves, at least one per leaf, from the module and
/// the generators' meshes, memoized per node, so nested instancing costs the nodes, not the
/// instances) against the vertex budget; false, with one SceneTooLarge error naming the
/// chain of instances that multiplies, when they do not fit. Entries reused from the last
/// evaluation (`reused`) keep their last count.
bool plan_fits(Context& c, std::span<const ir::NodeId> entries, const std::function<bool(ir::NodeId)>& reused);

// ---- highgenus.cpp: `handle`, `rind`, `sierpinski` and `menger` blocks ----
/// True for the four high-genus block kinds.
bool is_high_genus(ir::NodeKind k);
/// Runs high-genus block `pid` on its merged input `mesh`; `soup` is the input before the
/// merge (the same faces) and `vertex_map` maps its vertices to `mesh`'s. Nullopt when it
/// failed (reported).
std::optional<kernel::Mesh> high_genus(Context& c, ir::NodeId pid, const kernel::Mesh& mesh,
                                       const kernel::PolygonSoup& soup, const std::vector<kernel::VertexId>& vertex_map);

// ---- deletes.cpp: faces named by `delete` blocks ----
/// Marks the faces of `out` from `first_face` on that a `delete` names: they were placed by
/// the innermost instance `inst` through the current chain; `source` is a mesh's face node
/// per face (or None), and generator faces are numbered from 0.
void mark_deleted(Context& c, Collected& out, int32_t first_face, ir::NodeId inst);
/// Removes the marked faces of `c` (with the kernel: unused edges and vertices go too).
void apply_deletes(Context& c, Collected& out);

// ---- blocks.cpp: pipeline blocks ----
/// Evaluates block `pid`'s instances in its own frame, runs the operation, and adds the
/// result placed by `at`.
void block(Context& c, ir::NodeId pid, const Placing& at, Collected& out, int depth);

// ---- entries.cpp: scene entries ----
/// Scene entry `id` as an output mesh (null if it produced nothing), memoized when
/// incremental.
std::shared_ptr<const OutputMesh> entry(Context& c, ir::NodeId id);

// ---- zippers.cpp ----
/// `zipper` statement `id` as an output mesh (null on failure), memoized when incremental.
std::shared_ptr<const OutputMesh> zipper_entry(Context& c, ir::NodeId id);

}  // namespace nomec::backend::eval
