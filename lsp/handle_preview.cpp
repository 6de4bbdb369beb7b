// nome/preview {uri, pipeline?, values?}: everything a live preview draws of an open
// document — every output's geometry (base64 typed arrays, see preview.h) with its
// topology summary, the scene's camera, lights and background when it sets them up, the sliders, the whole-scene pipeline used, the files the scene read
// (for a host that watches them) and the diagnostics. A document with errors answers
// `ok: false` with its diagnostics and no geometry, so the client keeps its last good
// picture. The session it builds is the one nome/setParameter then moves sliders in.
// nome/saveScene {uri}: the document saved with the session's current slider values
// (`nomec --emit nome`: each moved slider's value token rewritten in place, nothing else);
// the saved text is checked again first, and an error (no text) names any moved slider it
// would not give its value.
#include <mutex>

#include "backend/save.h"
#include "backend/session.h"
#include "base/file_io.h"
#include "base/read_beneath.h"
#include "frontend/check/check.h"
#include "frontend/flat/flat.h"
#include "frontend/source/file_kinds.h"
#include "lsp/handler.h"
#include "lsp/preview.h"

namespace nomec::lsp {

namespace {

std::string uri_param(const json& p, const char* method) {
  if (!p.contains("uri") || !p["uri"].is_string()) {
    throw LspError(error_code::InvalidParams, std::string(method) + " expects {uri: string, ...}");
  }
  return p["uri"].get<std::string>();
}

json files_json(const Analysis& a) {
  json files = json::array();
  for (size_t i = 0; i < a.sources().file_count(); ++i) {
    files.push_back(std::string(a.sources().name(FileId(static_cast<int32_t>(i)))));
  }
  return files;
}

json preview(Context& ctx) {
  const json& p = ctx.params;
  const std::string uri = uri_param(p, "nome/preview");
  const backend::PipelineOptions pipeline = pipeline_from_json(p.value("pipeline", json(nullptr)));
  const json values = p.value("values", json(nullptr));
  if (!values.is_null() && !values.is_object()) {
    throw LspError(error_code::InvalidParams, "nome/preview: values must be an object {\"bank.param\": number}");
  }
  std::shared_ptr<const Analysis> a = ctx.analysis(uri);
  json reply = {{"uri", uri}, {"version", a->version}, {"pipeline", pipeline_json(pipeline)}};
  json diagnostics = a->diagnostics_json;
  if (a->too_large || first_error(*a) != nullptr) {
    reply["ok"] = false;
    reply["diagnostics"] = std::move(diagnostics);
    if (a->too_large) reply["message"] = "the document is too large to evaluate";
    return reply;
  }
  SliderSessions& sessions = ctx.slider_sessions();
  std::lock_guard<std::mutex> lock(sessions.mu);
  DiagnosticEngine diags;
  bool rebuilt = false;
  SliderSessions::Held& held = session_for(sessions, a, pipeline, values, diags, rebuilt);
  ctx.check_cancelled();
  diags.sort_and_dedupe();
  for (const Diagnostic& d : diags.diagnostics()) diagnostics.push_back(diagnostic_json(*a, d));
  reply["ok"] = diags.error_count() == 0;
  reply["rebuilt"] = rebuilt;
  reply["sliders"] = sliders_json(held.session->module());
  reply["files"] = files_json(*a);
  reply["outputs"] = outputs_json(held, true, {});
  if (json view = view_json(held.session->module()); !view.is_null()) reply["view"] = std::move(view);
  reply["diagnostics"] = std::move(diagnostics);
  return reply;
}

json save_scene(Context& ctx) {
  const std::string uri = uri_param(ctx.params, "nome/saveScene");
  std::shared_ptr<const Analysis> a = ctx.analysis(uri);
  if (const Diagnostic* d = first_error(*a)) {
    throw LspError(error_code::InvalidParams, "the document has errors; fix them before saving (" + d->message + ")");
  }
  SliderSessions& sessions = ctx.slider_sessions();
  std::lock_guard<std::mutex> lock(sessions.mu);
  const ir::Module* module = &a->module();
  for (const SliderSessions::Held& h : sessions.held) {
    if (h.uri == uri && h.version == a->version) module = &h.session->module();
  }
  const std::string path(a->sources().name(a->file));
  backend::SavedScene saved = backend::save_scene(*module, a->module(), a->sources(), path, a->check->base_file);
  if (module != &a->module()) {
    // Something moved: the saved text is checked again beside the document (where its
    // includes and Tcl sources are) and must give every slider its value.
    CheckOptions options;
    options.dialect = a->check->dialect;
    if (uri_to_path(uri)) {
      options.read_file = read_file_bytes;
      options.read_beneath = [](const std::string& folder, const std::string& name) {
        return read_file_beneath(folder, name);
      };
      options.list_folder = list_folder;
    }
    const std::string_view ext = path_extension(path);
    const std::string beside = path.substr(0, path.size() - ext.size()) + ".saved" +
                               (is_saved_work_path(path) || flat::format_of_path(path) ? std::string(".nome") : std::string(ext));
    SourceManager sources;
    DiagnosticEngine diags;
    const CheckResult back = check_source(sources, beside, saved.text, options, diags);
    std::vector<std::string> lost;
    for (const Diagnostic& d : diags.diagnostics()) {
      if (d.severity == Severity::Error && lost.empty()) lost.push_back("the saved text does not check: " + d.message);
    }
    if (lost.empty()) lost = backend::lost_values(*module, saved, back.module);
    if (!lost.empty()) {
      std::string message = "not saved: ";
      for (size_t i = 0; i < lost.size(); ++i) message += (i == 0 ? "" : "; ") + lost[i];
      throw LspError(error_code::InvalidParams, message);
    }
  }
  return {{"uri", uri}, {"version", a->version}, {"text", std::move(saved.text)}};
}

}  // namespace

void register_preview(Registry& r) {
  r.request("nome/preview", preview);
  r.request("nome/saveScene", save_scene);
}

}  // namespace nomec::lsp
