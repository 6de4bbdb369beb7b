// textDocument/documentSymbol: the hierarchical outline — banks with their sliders, meshes
// with points and faces, groups with their instances, generators, pipeline blocks.
#include <map>

#include "lsp/handler.h"

namespace nomec::lsp {

namespace {

// LSP SymbolKind numbers.
int lsp_kind(index::SymbolKind k) {
  using K = index::SymbolKind;
  switch (k) {
    case K::Bank: return 3;        // Namespace
    case K::Parameter: return 13;  // Variable
    case K::Point: return 14;      // Constant
    case K::Polyline: return 18;   // Array
    case K::Face: return 23;       // Struct
    case K::Mesh: return 5;        // Class
    case K::Object: return 19;     // Object
    case K::Group: return 2;       // Module
    case K::Instance: return 19;   // Object
    case K::Generator: return 12;  // Function
    case K::Surface: return 11;    // Interface
    case K::Block: return 4;       // Package
    case K::Other: return 20;      // Key
  }
  return 20;
}

json symbol_json(const Analysis& a, const index::Symbol& s, const std::map<int32_t, std::vector<int32_t>>& children) {
  SourceRange full = s.full_range.is_valid() && s.full_range.file == a.file ? s.full_range : s.name_range;
  // The selection range must lie inside the full range.
  full.begin = std::min(full.begin, s.name_range.begin);
  full.end = std::max(full.end, s.name_range.end);
  json j = {{"name", s.name.empty() ? std::string("(anonymous)") : s.name},
            {"kind", lsp_kind(s.kind)},
            {"range", a.range_json(full)},
            {"selectionRange", a.range_json(s.name_range)}};
  if (!s.detail.empty()) j["detail"] = s.detail;
  auto it = children.find(s.id);
  if (it != children.end()) {
    json kids = json::array();
    for (int32_t c : it->second) kids.push_back(symbol_json(a, a.index->symbols()[c], children));
    j["children"] = std::move(kids);
  }
  return j;
}

json document_symbol(Context& ctx) {
  std::shared_ptr<const Analysis> a = ctx.analysis();
  json out = json::array();
  if (!a->index) return out;
  const auto& symbols = a->index->symbols();
  std::map<int32_t, std::vector<int32_t>> children;
  for (const index::Symbol& s : symbols) {
    if (s.parent >= 0 && s.name_range.file == a->file) children[s.parent].push_back(s.id);
  }
  for (index::SymbolId id : a->index->outline(a->file)) out.push_back(symbol_json(*a, symbols[id], children));
  return out;
}

}  // namespace

void register_document_symbol(Registry& r) {
  r.capabilities()["documentSymbolProvider"] = true;
  r.request("textDocument/documentSymbol", document_symbol);
}

}  // namespace nomec::lsp
