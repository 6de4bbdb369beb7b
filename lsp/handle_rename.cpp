// textDocument/prepareRename and textDocument/rename: the index checks the new name and
// returns every edit (definition and uses, including inside `$bank.param` and 2016
// `_`-joined names); refusals come back as a RequestFailed error with the reason.
#include <map>

#include "lsp/handler.h"

namespace nomec::lsp {

namespace {

constexpr int kRequestFailed = -32803;

json prepare_rename(Context& ctx) {
  std::shared_ptr<const Analysis> a = ctx.analysis();
  if (!a->index) return nullptr;
  std::optional<SourceRange> r = a->index->prepare_rename(a->file, ctx.position_offset(*a));
  if (!r || r->file != a->file) return nullptr;
  return {{"range", a->range_json(*r)}, {"placeholder", std::string(a->sources().text(*r))}};
}

json rename(Context& ctx) {
  std::shared_ptr<const Analysis> a = ctx.analysis();
  if (!a->index) throw LspError(kRequestFailed, "this file is too large to rename in");
  std::string new_name = ctx.params.at("newName").get<std::string>();
  auto result = a->index->rename(a->file, ctx.position_offset(*a), new_name);
  if (auto* why = std::get_if<std::string>(&result)) throw LspError(kRequestFailed, *why);
  std::map<int32_t, json> by_file;
  for (const index::TextEdit& e : std::get<std::vector<index::TextEdit>>(result)) {
    json& edits = by_file[e.range.file.index];
    if (edits.is_null()) edits = json::array();
    edits.push_back({{"range", a->range_json(e.range)}, {"newText", e.new_text}});
  }
  json changes = json::array();
  for (auto& [f, edits] : by_file) {
    FileId file{f};
    json version = file == a->file ? json(a->version) : json(nullptr);
    changes.push_back({{"textDocument", {{"uri", a->uri_of(file)}, {"version", version}}}, {"edits", std::move(edits)}});
  }
  return {{"documentChanges", std::move(changes)}};
}

}  // namespace

void register_rename(Registry& r) {
  r.capabilities()["renameProvider"] = {{"prepareProvider", true}};
  r.request("textDocument/prepareRename", prepare_rename);
  r.request("textDocument/rename", rename);
}

}  // namespace nomec::lsp
