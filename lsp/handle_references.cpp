// textDocument/references: every use of the symbol under the cursor (and its definition
// when `context.includeDeclaration`), in source order.
#include "lsp/handler.h"

namespace nomec::lsp {

namespace {

json references(Context& ctx) {
  std::shared_ptr<const Analysis> a = ctx.analysis();
  json out = json::array();
  if (!a->index) return out;
  std::optional<index::Occurrence> o = a->index->occurrence_at(a->file, ctx.position_offset(*a));
  if (!o || o->symbol < 0) return out;
  bool with_declaration = ctx.params.value("context", json::object()).value("includeDeclaration", true);
  for (const index::Occurrence& r : a->index->references(o->symbol, with_declaration)) {
    ctx.check_cancelled();
    out.push_back(a->location_json(r.range));
  }
  return out;
}

}  // namespace

void register_references(Registry& r) {
  r.capabilities()["referencesProvider"] = true;
  r.request("textDocument/references", references);
}

}  // namespace nomec::lsp
