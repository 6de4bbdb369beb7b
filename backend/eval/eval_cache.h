// The evaluator's memory between evaluations (docs/incremental.md). Every value it computes
// (an expression, a generator's mesh, a sweep, an instance's world transform, a placed leaf,
// a pipeline block, a scene entry, a zipper) is kept with the parameters it read, directly
// or through the cached values it used, and whether computing it reported a diagnostic.
// `invalidate(p)` drops exactly the values that read parameter `p` (and the tainted ones,
// so their diagnostics are reported again); the next evaluation recomputes only those.
#pragma once

#include <cstdint>
#include <glm/mat4x4.hpp>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "backend/eval/parts.h"
#include "backend/evaluate.h"
#include "backend/generators/generators.h"
#include "ir/ir.h"

namespace nomec::backend::eval {

/// What a cached value read: sorted parameter node indices, and whether computing it
/// emitted a diagnostic (then it is recomputed next pass, to report it again).
struct Deps {
  std::vector<int32_t> params;
  bool is_tainted = false;
};

template <typename T>
struct Memo {
  T value;
  Deps deps;
};

/// Collects the parameters read while a value is computed. Values are computed inside a
/// frame; a cache hit adds the stored reads to the enclosing frame, so a scene entry knows
/// every parameter its meshes depend on.
class DepsRecorder {
 public:
  void begin_pass(DiagnosticEngine& diags) { diags_ = &diags; }
  DiagnosticEngine& diags() { return *diags_; }
  void open();
  Deps close();
  /// Adds reads to the innermost open frame.
  void note(const Deps& d);

 private:
  struct Frame {
    std::vector<int32_t> params;
    size_t diag_mark = 0;
    bool is_tainted = false;
  };
  std::vector<Frame> frames_;
  DiagnosticEngine* diags_ = nullptr;
};

/// A placed leaf (mesh, generator, curve or sweep) in its entry's frame; reused while its
/// transform, colour and the parameters it read are unchanged.
struct Placement {
  glm::dmat4 t;
  std::optional<glm::vec3> color;
  std::shared_ptr<const Collected> part;
  std::optional<kernel::Mesh> mesh;  // `part` built, when an entry reassembles from parts
};

/// A pipeline block's result: the results of its clusters of input parts, in order (one
/// part when it ran on its whole input).
struct BlockResult {
  std::vector<std::shared_ptr<const Collected>> parts;
};

/// The world-space geometry of one instance (by its chain of instance nodes) with its border
/// loops as vertex sequences, each running the way its faces traverse it (for zippers).
struct InstanceBorders {
  std::string path;
  ir::NodeId target;
  kernel::PolygonSoup soup;
  std::optional<kernel::Mesh> mesh;
  std::vector<std::vector<int32_t>> loops;
};

/// Every memoized value of one evaluator.
struct EvalCache {
  DepsRecorder recorder;
  std::unordered_map<int32_t, std::vector<int32_t>> expr_params;  // never stale: the IR is fixed
  std::unordered_map<int32_t, Memo<ir::EvalResult>> exprs;
  std::map<int32_t, Memo<glm::dmat4>> world;
  std::map<int32_t, Memo<std::optional<Generated>>> generated;
  std::map<std::string, Memo<std::optional<kernel::PolygonSoup>>> sweeps;
  std::unordered_map<std::string, Memo<Placement>> placements;
  std::map<int32_t, Memo<std::shared_ptr<const BlockResult>>> blocks;
  std::map<std::string, Memo<InstanceBorders>> borders;
  std::map<int32_t, Memo<std::shared_ptr<const OutputMesh>>> entries;
  std::map<int32_t, Memo<std::shared_ptr<const OutputMesh>>> zippers;
  /// The vertices placing each node would build (placement.cpp's plan), by node index.
  std::unordered_map<int32_t, Memo<int64_t>> plans;

  /// Drops every value that read parameter `param` (or every tainted value when `param` < 0).
  void invalidate(int32_t param);
  /// The parameters an expression reads, computed once per expression.
  const std::vector<int32_t>& params_of(const ir::Module& m, ir::ExprId id);
};

}  // namespace nomec::backend::eval
