// `nomec --what-if` (see what_if.h).
#include "tools/what_if.h"

#include <filesystem>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "backend/session.h"
#include "lsp/summary_json.h"
#include "tools/cli.h"

namespace nomec::tools {

using lsp::round6;
using lsp::summary_json;

std::string parse_what_if(const std::string& text, WhatIf& out) {
  auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0) {
    return fmt::format("--what-if expects bank.param=value, got `{}`", text);
  }
  std::string value = text.substr(eq + 1);
  const std::optional<double> v = parse_finite_number(value);
  if (!v) return fmt::format("--what-if {}: `{}` is not a finite number", text.substr(0, eq), value);
  out.parameter = text.substr(0, eq);
  out.value = *v;
  return {};
}

namespace {

nlohmann::json counts_json(const backend::UpdateStats& u) {
  return {{"nodes_reevaluated", u.nodes_reevaluated},
          {"generators_rerun", u.generators_rerun},
          {"instances_retransformed", u.instances_retransformed},
          {"kernel_ops_rerun", u.kernel_ops_rerun},
          {"ms", round6(u.ms)}};
}

}  // namespace

int run_what_if(const std::string& path, ir::Module module, const WhatIf& change,
                const backend::PipelineOptions& pipeline, bool allow_out_of_range,
                DiagnosticEngine& diags, std::ostream& out) {
  backend::SessionOptions options;
  options.pipeline = pipeline;
  options.pipeline_name = std::filesystem::path(path).stem().string();
  if (!module.scene.empty()) options.pipeline_where = module.node(module.scene.front()).range;
  options.allow_out_of_range = allow_out_of_range;
  backend::Session session(std::move(module), options);
  backend::UpdateStats full = session.build(diags);
  ir::NodeId p = session.find_parameter(change.parameter);
  const double old_value = p.is_valid() ? session.module().param(p).value : 0;
  backend::UpdateStats u = session.set_parameter(change.parameter, change.value, diags);
  nlohmann::json j = {{"file", path},
                      {"parameter", u.parameter},
                      {"old_value", old_value},
                      {"value", change.value},
                      {"nodes_in_graph", u.nodes_in_graph},
                      {"nodes_reevaluated", u.nodes_reevaluated},
                      {"generators_rerun", u.generators_rerun},
                      {"instances_retransformed", u.instances_retransformed},
                      {"kernel_ops_rerun", u.kernel_ops_rerun},
                      {"changed_outputs", u.changed_outputs},
                      {"full_build_ms", round6(full.ms)},
                      {"update_ms", round6(u.ms)},
                      {"update_over_full", full.ms > 0 ? round6(u.ms / full.ms) : 0.0},
                      {"full_build", counts_json(full)}};
  if (!u.ok()) {
    j["error"] = u.error;
  } else {
    std::vector<backend::MeshSummary> s = session.summary();
    j["summary"] = summary_json(path, s)["meshes"];
  }
  out << j.dump(2) << "\n";
  return u.ok() ? 0 : 1;
}

}  // namespace nomec::tools
