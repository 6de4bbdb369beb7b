// textDocument/codeAction: one quick fix per fix-it of the diagnostics that touch the
// requested range, e.g. "replace with `$fp_ro`" for a misspelt slider. The edits come from
// the analysis of the current version and are tied to that version.
#include "lsp/handler.h"

namespace nomec::lsp {

namespace {

json code_action(Context& ctx) {
  std::shared_ptr<const Analysis> a = ctx.analysis();
  const json& range = ctx.params.at("range");
  auto pos = [](const json& p) {
    return Position{p.at("line").get<uint32_t>(), p.at("character").get<uint32_t>()};
  };
  uint32_t begin = a->offset(pos(range.at("start")));
  uint32_t end = a->offset(pos(range.at("end")));
  if (end < begin) std::swap(begin, end);
  if (auto context = ctx.params.find("context"); context != ctx.params.end() && context->contains("only")) {
    bool wants = false;
    for (const json& k : context->at("only")) {
      if (k.is_string() && (k == "quickfix" || k.get<std::string>().rfind("quickfix.", 0) == 0)) wants = true;
    }
    if (!wants) return json::array();
  }
  json actions = json::array();
  for (size_t i = 0; i < a->diagnostics.size(); ++i) {
    const Diagnostic& d = a->diagnostics[i];
    if (d.fixits.empty() || !d.range.is_valid() || d.range.file != a->file) continue;
    // Touching counts: a cursor at either end of the underlined text still offers the fix.
    if (d.range.end < begin || d.range.begin > end) continue;
    for (const FixIt& f : d.fixits) {
      if (!f.range.is_valid() || f.range.file != a->file) continue;
      json edit = {{"range", a->range_json(f.range)}, {"newText", f.replacement}};
      std::string title = !f.description.empty() ? f.description
                          : f.replacement.empty() ? "delete `" + std::string(a->sources().text(f.range)) + "`"
                                                  : "replace with `" + f.replacement + "`";
      title[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(title[0])));
      actions.push_back({{"title", title},
                         {"kind", "quickfix"},
                         {"diagnostics", json::array({a->diagnostics_json[i]})},
                         {"isPreferred", d.fixits.size() == 1},
                         {"edit",
                          {{"documentChanges",
                            json::array({{{"textDocument", {{"uri", a->uri}, {"version", a->version}}},
                                          {"edits", json::array({edit})}}})}}}});
    }
  }
  return actions;
}

}  // namespace

void register_code_action(Registry& r) {
  r.capabilities()["codeActionProvider"] = {{"codeActionKinds", {"quickfix"}}};
  r.request("textDocument/codeAction", code_action);
}

}  // namespace nomec::lsp
