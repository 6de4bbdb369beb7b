// textDocument/hover: the index's markdown for the word under the cursor (parameters with
// value, range, bank and the instances they control; instances, meshes, generators;
// keywords), plus geometry facts — vertex and face counts, bounding box — from the latest
// background evaluation of this version when the word names an instance, mesh or generator.
#include <fmt/format.h>

#include "lsp/handler.h"

namespace nomec::lsp {

namespace {

std::string facts_markdown(const backend::NodeFacts& f, const ir::Node& node) {
  std::string where = node.kind == ir::NodeKind::Instance ? "placed by this instance" : "in the scene";
  std::string s = fmt::format("**Geometry** ({}): {} vertices, {} faces", where, f.vertices, f.faces);
  if (node.kind != ir::NodeKind::Instance && f.placements > 1) s += fmt::format(" over {} placements", f.placements);
  s += fmt::format("  \nbounding box ({:.4g}, {:.4g}, {:.4g}) – ({:.4g}, {:.4g}, {:.4g})", f.min[0], f.min[1], f.min[2],
                   f.max[0], f.max[1], f.max[2]);
  return s;
}

json hover(Context& ctx) {
  std::shared_ptr<const Analysis> a = ctx.analysis();
  if (!a->index) return nullptr;
  std::optional<index::Hover> h = a->index->hover(a->file, ctx.position_offset(*a));
  if (!h) return nullptr;
  std::string markdown = h->markdown;
  const auto& symbols = a->index->symbols();
  if (h->symbol >= 0 && static_cast<size_t>(h->symbol) < symbols.size()) {
    ir::NodeId node = symbols[h->symbol].node;
    if (node.is_valid()) {
      if (std::shared_ptr<const Geometry> g = ctx.geometry(a->uri, a->version)) {
        auto it = g->facts.find(node.index);
        if (it != g->facts.end()) markdown += "\n\n---\n" + facts_markdown(it->second, a->module().node(node));
      }
    }
  }
  json result = {{"contents", {{"kind", "markdown"}, {"value", markdown}}}};
  if (h->range.is_valid() && h->range.file == a->file) result["range"] = a->range_json(h->range);
  return result;
}

}  // namespace

void register_hover(Registry& r) {
  r.capabilities()["hoverProvider"] = true;
  r.request("textDocument/hover", hover);
}

}  // namespace nomec::lsp
