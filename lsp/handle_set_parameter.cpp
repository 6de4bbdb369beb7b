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
#include "tools/summary_json.h"

namespace nomec::lsp {

namespace {

struct Held {
  std::string uri;
  int64_t version = 0;
  std::shared_ptr<const Analysis> analysis;  // the IR the session was built from
  std::unique_ptr<backend::Session> session;
};

// Rationale: requests are handled one at a time on the request thread, but the mutex keeps
// this correct should that change. Only a few sessions are kept (most recent first), so
// memory stays bounded over a long editing session.
std::mutex g_mutex;
std::vector<Held> g_sessions;
constexpr size_t kMaxSessions = 4;

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
  std::lock_guard<std::mutex> lock(g_mutex);
  auto it = std::find_if(g_sessions.begin(), g_sessions.end(), [&](const Held& h) { return h.uri == uri; });
  if (it != g_sessions.end() && it->version != a->version) {
    g_sessions.erase(it);
    it = g_sessions.end();
  }
  DiagnosticEngine diags;
  if (it == g_sessions.end()) {
    Held h{uri, a->version, a, std::make_unique<backend::Session>(a->module())};
    h.session->build(diags);
    g_sessions.insert(g_sessions.begin(), std::move(h));
    if (g_sessions.size() > kMaxSessions) g_sessions.pop_back();
    it = g_sessions.begin();
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
  for (const backend::MeshSummary& m : it->session->summary()) meshes.push_back(tools::mesh_summary_json(m));
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
