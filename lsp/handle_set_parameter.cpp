// nome/setParameter {uri, parameter, value}: moves one slider of an open document in an
// editing session (backend::Session) and answers the new summary of every output mesh
// with what the move re-evaluated, e.g. for `fp.z` on the funnel cube: six instances
// re-transformed, no generator re-run. One session is kept per document and version; a
// new version of the text (or another document) starts a fresh one, so successive moves
// at one version are incremental. Refused (InvalidParams) for unknown sliders, values out
// of range, and documents with errors.
#include <algorithm>
#include <mutex>

#include "backend/session.h"
#include "lsp/handler.h"
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
  for (const Diagnostic& d : a->diagnostics) {
    if (d.severity == Severity::Error) {
      throw LspError(error_code::InvalidParams,
                     "the document has errors; fix them before moving sliders (" + d.message + ")");
    }
  }
  SliderSessions& sessions = ctx.slider_sessions();
  std::lock_guard<std::mutex> lock(sessions.mu);
  auto it = std::find_if(sessions.held.begin(), sessions.held.end(), [&](const SliderSessions::Held& h) { return h.uri == uri; });
  if (it != sessions.held.end() && it->version != a->version) {
    sessions.held.erase(it);
    it = sessions.held.end();
  }
  DiagnosticEngine diags;
  if (it == sessions.held.end()) {
    SliderSessions::Held h{uri, a->version, a, std::make_unique<backend::Session>(a->module())};
    h.session->build(diags);
    sessions.held.insert(sessions.held.begin(), std::move(h));
    if (sessions.held.size() > SliderSessions::kMax) sessions.held.pop_back();
    it = sessions.held.begin();
  }
  ctx.check_cancelled();
  diags = DiagnosticEngine();
  backend::UpdateStats u =
      it->session->set_parameter(p["parameter"].get<std::string>(), p["value"].get<double>(), diags);
  if (!u.ok()) throw LspError(error_code::InvalidParams, u.error);
  diags.sort_and_dedupe();
  json geometry = json::array();
  for (const Diagnostic& d : diags.diagnostics()) geometry.push_back(diagnostic_json(*a, d));
  json meshes = json::array();
  for (const backend::MeshSummary& m : it->session->summary()) meshes.push_back(lsp::mesh_summary_json(m));
  return {{"uri", uri},
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
}

}  // namespace

void register_set_parameter(Registry& r) { r.request("nome/setParameter", set_parameter); }

}  // namespace nomec::lsp
