// textDocument/definition: the defining word of the symbol under the cursor, e.g. the
// `set n …` line of bank `fp` for `$fp_n`, possibly in an included file.
#include "lsp/handler.h"

namespace nomec::lsp {

namespace {

json definition(Context& ctx) {
  std::shared_ptr<const Analysis> a = ctx.analysis();
  if (!a->index) return nullptr;
  std::optional<index::Occurrence> o = a->index->occurrence_at(a->file, ctx.position_offset(*a));
  if (!o || o->symbol < 0) return nullptr;
  const index::Symbol& s = a->index->symbols()[o->symbol];
  if (!s.name_range.is_valid()) return nullptr;
  return a->location_json(s.name_range);
}

}  // namespace

void register_definition(Registry& r) {
  r.capabilities()["definitionProvider"] = true;
  r.request("textDocument/definition", definition);
}

}  // namespace nomec::lsp
