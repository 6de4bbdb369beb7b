// textDocument/completion and textDocument/signatureHelp: keywords, names in scope and
// `$bank.param` from the index at the cursor; inside a generator's or statement's
// argument list, its signature with the argument being typed highlighted.
#include "lsp/handler.h"

namespace nomec::lsp {

namespace {

// LSP CompletionItemKind numbers.
int lsp_kind(const index::CompletionItem& c) {
  using K = index::SymbolKind;
  if (c.is_keyword) return 14;  // Keyword
  switch (c.kind) {
    case K::Parameter: return 6;   // Variable
    case K::Bank: return 9;        // Module
    case K::Generator: return 3;   // Function
    case K::Mesh: case K::Object: case K::Surface: return 7;  // Class
    case K::Group: case K::Block: return 9;                     // Module
    case K::Point: return 21;      // Constant
    case K::Instance: return 5;    // Field
    default: return 1;             // Text
  }
}

json completion(Context& ctx) {
  std::shared_ptr<const Analysis> a = ctx.analysis();
  json items = json::array();
  if (!a->index) return items;
  for (const index::CompletionItem& c : a->index->complete(a->file, ctx.position_offset(*a))) {
    json item = {{"label", c.label}, {"kind", lsp_kind(c)}};
    if (!c.detail.empty()) item["detail"] = c.detail;
    if (!c.insert_text.empty() && c.insert_text != c.label) item["insertText"] = c.insert_text;
    items.push_back(std::move(item));
  }
  return {{"isIncomplete", false}, {"items", std::move(items)}};
}

json signature_help(Context& ctx) {
  std::shared_ptr<const Analysis> a = ctx.analysis();
  if (!a->index) return nullptr;
  std::optional<index::SignatureHelp> h = a->index->signature_help(a->file, ctx.position_offset(*a));
  if (!h) return nullptr;
  json params = json::array();
  for (size_t i = 0; i < h->parameters.size(); ++i) {
    auto [b, e] = h->parameters[i];
    b = std::min<uint32_t>(b, static_cast<uint32_t>(h->label.size()));
    e = std::min<uint32_t>(std::max(b, e), static_cast<uint32_t>(h->label.size()));
    // Offsets inside the label are UTF-16 code units in LSP.
    std::string_view label = h->label;
    json p = {{"label", {LineIndex::utf16_length(label.substr(0, b)), LineIndex::utf16_length(label.substr(0, e))}}};
    if (i < h->parameter_docs.size() && !h->parameter_docs[i].empty()) p["documentation"] = h->parameter_docs[i];
    params.push_back(std::move(p));
  }
  return {{"signatures", json::array({{{"label", h->label}, {"parameters", params}}})},
          {"activeSignature", 0},
          {"activeParameter", std::max(0, h->active_parameter)}};
}

}  // namespace

void register_completion(Registry& r) {
  r.capabilities()["completionProvider"] = {{"triggerCharacters", {"$", "."}}};
  r.capabilities()["signatureHelpProvider"] = {{"triggerCharacters", {"(", " "}}};
  r.request("textDocument/completion", completion);
  r.request("textDocument/signatureHelp", signature_help);
}

}  // namespace nomec::lsp
