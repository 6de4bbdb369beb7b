// nome/setParameter {uri, parameter, value}: moves one slider of an open document in an
// editing session (backend::Session) and answers the new summary of every output mesh
// with what the move re-evaluated, e.g. for `fp.z` on the funnel cube: six instances
// re-transformed, no generator re-run. One session is kept per document and version; a
// new version of the text (or another document) starts a fresh one, so successive moves
// at one version are incremental. Refused (InvalidParams) for unknown sliders, values out
// of range, and documents with errors. With `geometry: true` (the preview) the reply also
// holds `outputs`, the geometry of the changed outputs only (see nome/preview), and
// `outputNames`, every output's name in order. The session is the one nome/preview built
// (with its pipeline) when there is one.
#include <algorithm>
#include <mutex>

#include "backend/session.h"
#include "lsp/handler.h"
#include "lsp/preview.h"
#include "lsp/summary_json.h"

namespace nomec::lsp {

namespace {

json set_parameter(Context& ctx) {
  const json& p = ctx.params;
  if (!p.contains("uri") || !p["uri"].is_string() || !p.contains("parameter") || !p["parameter"].is_string() ||
      !p.contains("value") || !p["value"].is_number()) {
    throw LspError(error_code::InvalidParams,
                   "nome/setParameter expects {uri: string, parameter: \"bank.param\", value: number}");
  }
  const std::string uri = p["uri"].get<std::string>();
  std::shared_ptr<const Analysis> a = ctx.analysis(uri);
  if (a->too_large) throw LspError(error_code::InvalidParams, "the document is too large to evaluate");
  if (const Diagnostic* d = first_error(*a)) {
    throw LspError(error_code::InvalidParams, "the document has errors; fix them before moving sliders (" + d->message + ")");
  }
  SliderSessions& sessions = ctx.slider_sessions();
  std::lock_guard<std::mutex> lock(sessions.mu);
  DiagnosticEngine diags;
  bool rebuilt = false;
  SliderSessions::Held& held = session_for(sessions, a, std::nullopt, json(nullptr), diags, rebuilt);
  ctx.check_cancelled();
  diags = DiagnosticEngine();
  backend::UpdateStats u =
      held.session->set_parameter(p["parameter"].get<std::string>(), p["value"].get<double>(), diags);
  if (!u.ok()) throw LspError(error_code::InvalidParams, u.error);
  diags.sort_and_dedupe();
  json geometry = json::array();
  for (const Diagnostic& d : diags.diagnostics()) geometry.push_back(diagnostic_json(*a, d));
  const std::vector<backend::MeshSummary> summaries = held.session->summary();  // once: the outputs reuse them
  json meshes = json::array();
  for (const backend::MeshSummary& m : summaries) meshes.push_back(lsp::mesh_summary_json(m));
  json reply = {{"uri", uri},
          {"version", a->version},
          {"parameter", u.parameter},
          {"value", u.value},
          {"nodesInGraph", u.nodes_in_graph},
          {"nodesReevaluated", u.nodes_reevaluated},
          {"generatorsRerun", u.generators_rerun},
          {"instancesRetransformed", u.instances_retransformed},
          {"kernelOpsRerun", u.kernel_ops_rerun},
          {"changedOutputs", u.changed_outputs},
          {"ms", u.ms},
          {"meshes", meshes},
          {"diagnostics", geometry}};
  // A preview asks for the geometry of the outputs that changed (positions only when their
  // topology did not), so an update's size follows what the move changed.
  if (p.value("geometry", false)) {
    reply["outputs"] = outputs_json(held, false, u.changed_outputs, &summaries);
    json names = json::array();
    for (const auto& m : held.session->outputs()) names.push_back(m->name);
    reply["outputNames"] = std::move(names);
  }
  return reply;
}

}  // namespace

void register_set_parameter(Registry& r) { r.request("nome/setParameter", set_parameter); }

}  // namespace nomec::lsp
