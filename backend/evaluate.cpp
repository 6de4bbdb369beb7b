// Scene evaluation (see evaluate.h): which IR nodes are scene entries, the evaluator over
// them (backend/eval/: one file per concern), the command line's whole-scene pipeline, and
// the one-shot functions the CLI and the language server call.
#include "backend/evaluate.h"

#include <chrono>
#include <fmt/format.h>
#include <set>

#include "backend/eval/context.h"
#include "kernel/merge.h"

namespace nomec::backend {

using eval::run_steps;
using eval::run_steps_by_component;
using eval::Step;
using eval::StepFailure;

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

}  // namespace

namespace {

// The scene entries of a module: its top-level instances and blocks, then NOME 2016 saved
// work, or for SLIDE the world groups.
std::vector<ir::NodeId> scene_entries(const ir::Module& module) {
  std::vector<ir::NodeId> entries = module.scene;
  // NOME 2016 saved work: `consolidate` / `savedworkingmesh` meshes are part of the scene
  // unless something instances them.
  std::set<int32_t> instanced;
  for (const ir::Node& n : module.nodes) {
    if (n.kind == ir::NodeKind::Instance && n.as<ir::InstanceData>().target.is_valid()) {
      instanced.insert(n.as<ir::InstanceData>().target.index);
    }
  }
  for (size_t i = 0; i < module.nodes.size(); ++i) {
    const ir::Node& n = module.nodes[i];
    if (n.kind != ir::NodeKind::Mesh || instanced.contains(static_cast<int32_t>(i))) continue;
    const ir::MeshForm form = n.as<ir::MeshData>().form;
    if (form == ir::MeshForm::Consolidate || form == ir::MeshForm::SavedWorkingMesh) {
      entries.push_back(ir::NodeId(static_cast<int32_t>(i)));
    }
  }
  // SLIDE has no top-level instances: `render VIEWPORT CAMERA WORLD` draws the group WORLD
  // and what it holds (slide.md §3.20; the first render, as the preview's view). Without a
  // render whose root resolved, the top-level groups that nothing instances stand for the
  // world (groups holding only cameras and lights produce nothing and are dropped).
  if (entries.empty() && module.dialect == Dialect::Slide) {
    for (const ir::Node& n : module.nodes) {
      if (n.kind != ir::NodeKind::SceneSetup) continue;
      const ir::SceneData& d = n.as<ir::SceneData>();
      if (d.kind != ir::SceneKind::Render) continue;
      if (d.root.is_valid() && module.node(d.root).kind == ir::NodeKind::Group) return {d.root};
      break;
    }
  }
  if (entries.empty() && module.dialect == Dialect::Slide) {
    for (size_t i = 0; i < module.nodes.size(); ++i) {
      const ir::Node& n = module.nodes[i];
      if (n.kind == ir::NodeKind::Group && !n.parent.is_valid() &&
          !instanced.contains(static_cast<int32_t>(i))) {
        entries.push_back(ir::NodeId(static_cast<int32_t>(i)));
      }
    }
  }
  return entries;
}

// Per-step component memos of the whole-scene pipeline (incremental evaluation only).
struct PipelineMemos {
  eval::ComponentMemo components;
};

std::vector<OutputMesh> pipeline_impl(const std::vector<const OutputMesh*>& meshes, const PipelineOptions& o,
                                      std::string_view name, SourceRange where,
                                      DiagnosticEngine& diags, StageTimings* timings,
                                      const std::function<void(std::string_view)>& progress,
                                      PipelineMemos* memos, int32_t& kernel_ops) {
  auto say = [&](std::string_view s) {
    if (progress) progress(s);
  };
  auto fail = [&](std::string_view stage, const kernel::KernelError& e) {
    DiagKind kind = e.kind == kernel::KernelError::Kind::NonManifoldMerge ||
                            e.kind == kernel::KernelError::Kind::NonManifoldEdge ||
                            e.kind == kernel::KernelError::Kind::NonManifoldVertex
                        ? DiagKind::NonManifoldGeometry
                        : DiagKind::GeometryFailed;
    std::string message = fmt::format("--{} of the whole scene failed: {}", stage, e.message);
    if (kind == DiagKind::NonManifoldGeometry) {
      diags.emit(DiagKind::NonManifoldGeometry, where, std::move(message));
    } else {
      diags.emit(DiagKind::GeometryFailed, where, std::move(message));
    }
  };
  std::vector<const kernel::Mesh*> parts;
  int32_t curves = 0;
  std::vector<Curve> curve_points;
  for (const OutputMesh* m : meshes) {
    parts.push_back(&m->mesh);
    curves += m->curve_count;
    curve_points.insert(curve_points.end(), m->curves.begin(), m->curves.end());
  }
  auto t0 = Clock::now();
  say("merge");
  kernel::Mesh all = kernel::concatenate(parts);
  auto merged = eval::merge_mesh(all, o.merge_tolerance);
  ++kernel_ops;
  if (timings) timings->merge_ms += ms_since(t0);
  if (!merged) {
    fail("merge", merged.error());
    return {};
  }
  kernel::Mesh mesh = std::move(merged->mesh);
  // Runs one step on `mesh`.
  auto run = [&](const Step& st, std::string_view flag, double* ms) -> bool {
    auto t1 = Clock::now();
    auto r = run_steps(std::move(mesh), {st}, kernel_ops, o.max_vertices);
    if (timings) *ms += ms_since(t1);
    if (auto* failed = std::get_if<StepFailure>(&r)) {
      fail(flag, failed->error);
      return false;
    }
    mesh = std::move(std::get<kernel::Mesh>(r));
    return true;
  };
  auto subdivide = [&](int32_t levels, std::string_view flag) -> bool {
    if (levels <= 0) return true;
    say("subdivide");
    Step st;
    st.subdivision.levels = levels;
    st.subdivision.vertex_rule = o.rule;
    st.subdivision.has_parent_maps = false;
    return run(st, flag, timings ? &timings->subdivide_ms : nullptr);
  };
  bool is_done = false;
  if (memos != nullptr) {
    // Incremental: every step at once per connected component, so an unchanged component
    // is reused whole; on a failure the steps are redone one by one below, for the same
    // diagnostics as a one-shot run.
    std::vector<Step> steps;
    Step st;
    st.subdivision.vertex_rule = o.rule;
    st.subdivision.has_parent_maps = false;
    st.subdivision.levels = o.subdivide_levels;
    steps.push_back(st);
    if (o.offset_height > 0) {
      Step off;
      off.kind = Step::Kind::Offset;
      off.height = o.offset_height;
      steps.push_back(off);
    }
    st.subdivision.levels = o.subdivide_after_levels;
    steps.push_back(st);
    say("subdivide");
    auto t1 = Clock::now();
    eval::ComponentMemo next;
    auto r = run_steps_by_component(mesh, steps, memos->components, next, kernel_ops, o.max_vertices);
    memos->components = std::move(next);
    if (timings) timings->subdivide_ms += ms_since(t1);
    if (auto* m = std::get_if<kernel::Mesh>(&r)) {
      mesh = std::move(*m);
      is_done = true;
    } else {
      memos->components.entries.clear();
    }
  }
  if (!is_done) {
    if (!subdivide(o.subdivide_levels, "subdivide")) return {};
    if (o.offset_height > 0) {
      say("offset");
      Step st;
      st.kind = Step::Kind::Offset;
      st.height = o.offset_height;
      if (!run(st, "offset", timings ? &timings->offset_ms : nullptr)) return {};
    }
    if (!subdivide(o.subdivide_after_levels, "subdivide-after")) return {};
  }
  OutputMesh out;
  out.name = std::string(name);
  if (o.polygon_lists) out.soup = kernel::to_soup(mesh);
  out.mesh = std::move(mesh);
  out.curve_count = curves;
  out.curves = std::move(curve_points);
  std::vector<OutputMesh> result;
  result.push_back(std::move(out));
  return result;
}

}  // namespace

struct SceneEvaluator::PipelineMemosHolder {
  PipelineMemos memos;
};

SceneEvaluator::SceneEvaluator(const ir::Module& module, bool is_incremental, PipelineOptions pipeline,
                               std::string pipeline_name, SourceRange pipeline_where)
    : impl_(std::make_unique<eval::Context>(module, is_incremental)),
      module_(module),
      entries_(scene_entries(module)),
      is_incremental_(is_incremental),
      pipeline_(pipeline),
      pipeline_name_(std::move(pipeline_name)),
      pipeline_where_(pipeline_where) {
  for (size_t i = 0; i < module.nodes.size(); ++i) {
    const ir::Node& n = module.nodes[i];
    if (n.kind == ir::NodeKind::Zipper) zippers_.push_back(ir::NodeId(static_cast<int32_t>(i)));
  }
}

SceneEvaluator::~SceneEvaluator() = default;

void SceneEvaluator::invalidate(ir::NodeId param) { impl_->cache.invalidate(param.index); }

EvalCounters SceneEvaluator::take_counters() { return std::exchange(impl_->counters, EvalCounters{}); }

std::vector<std::shared_ptr<const OutputMesh>> SceneEvaluator::evaluate(DiagnosticEngine& diags,
                                                                        StageTimings* timings) {
  auto t0 = Clock::now();
  const int errors_before = diags.error_count();
  impl_->cache.recorder.begin_pass(diags);
  impl_->cache.invalidate(-1);  // values that reported a diagnostic report it again
  impl_->vertex_limit = impl_->vertex_budget = pipeline_.max_vertices;
  impl_->is_budget_exhausted = false;
  std::vector<std::shared_ptr<const OutputMesh>> out;
  // Nothing is built for a scene whose instances would place more than the budget.
  if (!eval::plan_fits(*impl_, entries_, [&](ir::NodeId id) { return impl_->cache.entries.contains(id.index); })) {
    if (timings) timings->evaluate_ms += ms_since(t0);
    return out;
  }
  for (ir::NodeId id : entries_) {
    if (auto m = eval::entry(*impl_, id)) out.push_back(std::move(m));
  }
  // Zipper faces: one output mesh per `zipper` statement, after the scene entries.
  for (ir::NodeId id : zippers_) {
    if (auto m = eval::zipper_entry(*impl_, id)) out.push_back(std::move(m));
  }
  if (impl_->is_budget_exhausted) {
    // What was placed after the budget ran out is incomplete: none of it is kept for the
    // next evaluation.
    impl_->cache.entries.clear();
    impl_->cache.blocks.clear();
    impl_->cache.placements.clear();
    impl_->cache.zippers.clear();
    impl_->layouts.clear();
    impl_->block_memos.clear();
  }
  if (timings) timings->evaluate_ms += ms_since(t0);
  if (!pipeline_.any() || out.empty() || diags.error_count() > errors_before) return out;
  if (is_incremental_ && out == pipeline_inputs_) {
    impl_->counters.new_outputs.clear();
    return pipeline_outputs_;
  }
  std::vector<const OutputMesh*> parts;
  for (const auto& m : out) parts.push_back(m.get());
  if (!pipeline_memos_) pipeline_memos_ = std::make_shared<PipelineMemosHolder>();

  std::vector<OutputMesh> done = pipeline_impl(parts, pipeline_, pipeline_name_, pipeline_where_, diags, timings, {},
                                               is_incremental_ ? &pipeline_memos_->memos : nullptr,
                                               impl_->counters.kernel_ops);
  std::vector<std::shared_ptr<const OutputMesh>> result;
  impl_->counters.new_outputs.clear();
  for (OutputMesh& m : done) {
    result.push_back(std::make_shared<OutputMesh>(std::move(m)));
    impl_->counters.new_outputs.push_back(result.back().get());
  }
  if (is_incremental_) {
    pipeline_inputs_ = std::move(out);
    pipeline_outputs_ = result;
  }
  return result;
}

std::vector<OutputMesh> evaluate_scene(const ir::Module& module, DiagnosticEngine& diags,
                                       StageTimings* timings, int64_t max_vertices) {
  std::vector<OutputMesh> out;
  {
    PipelineOptions limits;
    limits.max_vertices = max_vertices;
    SceneEvaluator ev(module, false, limits);
    for (const auto& m : ev.evaluate(diags, timings)) {
      // A one-shot evaluator keeps no reference: these objects are ours to move from.
      out.push_back(std::move(const_cast<OutputMesh&>(*m)));
    }
  }
  return out;
}

std::vector<OutputMesh> run_pipeline(std::vector<OutputMesh> meshes, const PipelineOptions& o,
                                     std::string_view name, SourceRange where,
                                     DiagnosticEngine& diags, StageTimings* timings,
                                     const std::function<void(std::string_view)>& progress) {
  if (!o.any() || meshes.empty()) return meshes;
  std::vector<const OutputMesh*> parts;
  for (const OutputMesh& m : meshes) parts.push_back(&m);
  int32_t kernel_ops = 0;
  return pipeline_impl(parts, o, name, where, diags, timings, progress, nullptr, kernel_ops);
}

}  // namespace nomec::backend
