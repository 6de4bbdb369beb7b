// An editing session over one checked scene: a full build, then parameter changes that
// re-evaluate only what read the parameter (see session.h and docs/incremental.md).
#include "backend/session.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fmt/format.h>

namespace nomec::backend {

Session::Session(ir::Module module, SessionOptions options)
    : module_(std::make_unique<ir::Module>(std::move(module))), options_(std::move(options)) {}

Session::~Session() = default;

UpdateStats Session::build(DiagnosticEngine& diags) {
  evaluator_ = std::make_unique<SceneEvaluator>(*module_, true, options_.pipeline, options_.pipeline_name,
                                                options_.pipeline_where);
  outputs_.clear();
  return evaluate(diags);
}

UpdateStats Session::evaluate(DiagnosticEngine& diags) {
  auto t0 = std::chrono::steady_clock::now();
  // The evaluator says which outputs are new; dropping ours first lets a changed entry
  // reuse its previous output's storage when no client holds it (see SceneEvaluator).
  outputs_.clear();
  std::vector<std::shared_ptr<const OutputMesh>> next = evaluator_->evaluate(diags);
  UpdateStats u;
  u.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  EvalCounters c = evaluator_->take_counters();
  u.nodes_in_graph = module_->deps.node_count();
  u.nodes_reevaluated = c.nodes.size();
  u.reevaluated.assign(c.nodes.begin(), c.nodes.end());
  u.generators_rerun = c.generators_run;
  u.instances_retransformed = c.instances_placed;
  u.kernel_ops_rerun = c.kernel_ops;
  u.outputs_patched = c.outputs_patched;
  u.parts_patched = c.parts_patched;
  u.clusters_reused = c.clusters_reused;
  for (const auto& m : next) {
    if (std::find(c.new_outputs.begin(), c.new_outputs.end(), m.get()) != c.new_outputs.end()) {
      u.changed_outputs.push_back(m->name);
    }
  }
  outputs_ = std::move(next);
  return u;
}

ir::NodeId Session::find_parameter(std::string_view name) const {
  if (size_t dot = name.find('.'); dot != std::string_view::npos) {
    return module_->find_param(name.substr(0, dot), name.substr(dot + 1));
  }
  // 2016 `bank_param`: bank names may themselves contain `_`, so try every split.
  for (size_t us = name.find('_'); us != std::string_view::npos; us = name.find('_', us + 1)) {
    ir::NodeId p = module_->find_param(name.substr(0, us), name.substr(us + 1));
    if (p.is_valid()) return p;
  }
  return ir::NodeId::None();
}

UpdateStats Session::set_parameter(std::string_view name, double value, DiagnosticEngine& diags) {
  if (!evaluator_) build(diags);
  UpdateStats u;
  u.value = value;
  u.nodes_in_graph = module_->deps.node_count();
  ir::NodeId p = find_parameter(name);
  if (!p.is_valid()) {
    u.parameter = std::string(name);
    u.error = fmt::format("no slider `{}` in this scene", name);
    return u;
  }
  ir::ParamData& param = module_->param(p);
  u.parameter = module_->node(p).name;  // qualified, e.g. `fp.z`
  if (!std::isfinite(value)) {  // even with allow_out_of_range: no geometry is made of it
    u.error = fmt::format("{} is not a finite number; slider `{}` keeps {}", value, u.parameter, param.value);
    return u;
  }
  if (!options_.allow_out_of_range && param.min <= param.max && (value < param.min || value > param.max)) {
    u.error = fmt::format("{} is outside the range [{}, {}] of slider `{}`", value, param.min, param.max,
                          u.parameter);
    return u;
  }
  if (value == param.value) return u;  // nothing changes
  param.value = value;
  evaluator_->invalidate(p);
  UpdateStats done = evaluate(diags);
  done.parameter = u.parameter;
  done.value = value;
  return done;
}

std::vector<MeshSummary> Session::summary() const {
  std::vector<MeshSummary> out;
  for (const auto& m : outputs_) out.push_back(summarize(*m));
  return out;
}

}  // namespace nomec::backend
