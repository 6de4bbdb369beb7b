// An editing session over one checked scene: a full build, then slider moves that
// re-evaluate only what depends on the moved parameter (seed report §6.1, §7.1), with
// counts of the work done. Used by `nomec --what-if`, the language server's
// `nome/setParameter` and any future preview. JSON-free: clients format the results.
//
//   Session s(std::move(check.module));
//   s.build(diags);                          // everything, once
//   UpdateStats u = s.set_parameter("fp.z", -0.5, diags);
//   // u.instances_retransformed == 6, u.generators_rerun == 0; s.outputs() is current.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "backend/evaluate.h"
#include "backend/summary.h"
#include "frontend/diagnostics/diagnostic.h"
#include "ir/ir.h"

namespace nomec::backend {

struct SessionOptions {
  /// The command line's whole-scene steps (`--merge --subdivide N --offset H`), if any.
  PipelineOptions pipeline;
  /// Name of the pipeline's output mesh (the file's stem) and where its errors point.
  std::string pipeline_name = "scene";
  SourceRange pipeline_where;
  /// Accept values outside a slider's [min, max] (as `--allow-out-of-range` does for -D).
  bool allow_out_of_range = false;
};

/// What a build or a parameter change did.
struct UpdateStats {
  std::string parameter;  // as found, e.g. "fp.z"; empty for `build`
  double value = 0;
  std::string error;      // non-empty: the change was refused and nothing was evaluated
  size_t nodes_in_graph = 0;
  /// IR nodes whose value was recomputed: expression values, generators, sweeps, placed
  /// instances with the groups, blocks and scene entries above them.
  size_t nodes_reevaluated = 0;
  int32_t generators_rerun = 0;
  int32_t instances_retransformed = 0;
  /// merge, subdivide, offset, lattice, zipper and delete runs (one per connected
  /// component when a block works per component).
  int32_t kernel_ops_rerun = 0;
  /// Outputs updated by copying the previous one and overwriting the positions of the
  /// parts that moved (their topology unchanged), and how many parts that was.
  int32_t outputs_patched = 0;
  int32_t parts_patched = 0;
  /// Clusters of a pipeline block's input (parts that the merge may join) whose merged and
  /// subdivided/offset result was reused as a whole (see docs/incremental.md).
  int32_t clusters_reused = 0;
  std::vector<int32_t> reevaluated;          // the node indices behind nodes_reevaluated
  std::vector<std::string> changed_outputs;  // names of output meshes that are new objects
  double ms = 0;                             // wall-clock time of the evaluation
  bool ok() const { return error.empty(); }
};

class Session {
 public:
  explicit Session(ir::Module module, SessionOptions options = {});
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  /// Evaluates everything from scratch (dropping every cached value).
  UpdateStats build(DiagnosticEngine& diags);
  /// Sets parameter `name` (`bank.param` or 2016 `bank_param`) and re-evaluates what
  /// depends on it; geometry diagnostics of the new state go to `diags`. Builds first if
  /// `build` was never called.
  UpdateStats set_parameter(std::string_view name, double value, DiagnosticEngine& diags);

  /// The parameter node named `bank.param` or `bank_param`, or None.
  ir::NodeId find_parameter(std::string_view name) const;

  /// The current output meshes, as `evaluate_scene` (then `run_pipeline`) returns them.
  const std::vector<std::shared_ptr<const OutputMesh>>& outputs() const { return outputs_; }
  std::vector<MeshSummary> summary() const;
  const ir::Module& module() const { return *module_; }

 private:
  UpdateStats evaluate(DiagnosticEngine& diags);

  std::unique_ptr<ir::Module> module_;
  SessionOptions options_;
  std::unique_ptr<SceneEvaluator> evaluator_;
  std::vector<std::shared_ptr<const OutputMesh>> outputs_;
};

}  // namespace nomec::backend
