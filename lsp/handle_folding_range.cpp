// textDocument/foldingRange: multi-line blocks (`mesh … endmesh`, banks, groups, …) and
// multi-line `(* *)` comments from the index, as line ranges.
#include "lsp/handler.h"

namespace nomec::lsp {

namespace {

json folding_range(Context& ctx) {
  std::shared_ptr<const Analysis> a = ctx.analysis();
  json out = json::array();
  if (!a->index) return out;
  for (const index::FoldingRange& f : a->index->folding_ranges(a->file)) {
    if (f.range.file != a->file) continue;
    uint32_t start = a->lines.position(f.range.begin).line;
    uint32_t end = a->lines.position(f.range.end).line;
    if (end <= start) continue;
    json j = {{"startLine", start}, {"endLine", end}};
    if (f.is_comment) j["kind"] = "comment";
    out.push_back(std::move(j));
  }
  return out;
}

}  // namespace

void register_folding_range(Registry& r) {
  r.capabilities()["foldingRangeProvider"] = true;
  r.request("textDocument/foldingRange", folding_range);
}

}  // namespace nomec::lsp
