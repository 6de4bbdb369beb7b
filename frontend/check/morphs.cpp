// JIPCAD's morphing sweeps (see handlers.h; compat.md F4): `sweepmorph S [begincap]
// [endcap] [reverse] path P … endpath endsweepmorph`, whose path's control points carry the
// cross-sections it interpolates, and `morphvisualizer V sweep S index E
// endmorphvisualizer`, one of those interpolated cross-sections as a line strip.
#include <fmt/format.h>

#include "frontend/check/handlers.h"

namespace nomec::check {

ir::NodeId handle_sweepmorph(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  size_t pos = 0;
  std::string name = c.read_name(s, pos, "sweepmorph s path p endpath endsweepmorph").value_or("");
  ir::NodeId id = c.node_for(s, c.qualify(ctx, name), ctx);
  read_body(c, a, s, pos, id, options_for(s.kind), [&c, id](const OptionValue& v) {
    ir::SweepMorphData& d = c.module().get<ir::SweepMorphData>(id);
    if (v.spec->key == Opt::BeginCap) d.begin_cap = true;
    if (v.spec->key == Opt::EndCap) d.end_cap = true;
    if (v.spec->key == Opt::Reverse) d.reverse = true;
  });
  int paths = 0;
  for (ir::NodeId child : c.module().children(c.module().node(id))) {
    if (c.module().node(child).kind == ir::NodeKind::SweepPath) ++paths;
  }
  if (paths != 1) {
    c.diags().emit(DiagKind::MissingArgument, s.open_kw,
                   fmt::format("`sweepmorph` needs exactly one `path P … endpath`, got {}", paths));
  }
  if (ctx.parent.is_valid()) c.module().deps.add_edge(id, ctx.parent);
  return id;
}

ir::NodeId handle_morphvisualizer(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  size_t pos = 0;
  std::string name = c.read_name(s, pos, "morphvisualizer v sweep s index 0 endmorphvisualizer").value_or("");
  ir::NodeId id = c.node_for(s, c.qualify(ctx, name), ctx);
  read_body(c, a, s, pos, id, options_for(s.kind), [&c, id](const OptionValue& v) {
    ir::MorphVisualizerData& d = c.module().get<ir::MorphVisualizerData>(id);
    if (v.spec->key == Opt::Index) d.index = v.operand;
    if (v.spec->key != Opt::Sweep || !v.ref.is_valid()) return;
    const ir::Node& target = c.module().node(v.ref);
    if (target.kind != ir::NodeKind::SweepMorph) {
      c.diags()
          .emit(DiagKind::WrongKind, v.value_range,
                fmt::format("`{}` is a {}, but `morphvisualizer` shows a cross-section of a `sweepmorph`", target.name,
                            target.keyword))
          .note(target.range, "defined here");
      return;
    }
    d.sweep = v.ref;
  });
  const ir::MorphVisualizerData& d = c.module().get<ir::MorphVisualizerData>(id);
  if (!d.index.is_valid() || !d.sweep.is_valid()) {
    // Only report what is absent; a wrong `sweep` was reported above.
    bool has_sweep_word = false;
    for (const ast::Item& it : s.items) has_sweep_word = has_sweep_word || (it.kind == ItemKind::Word && it.text == "sweep");
    if (!d.index.is_valid() || !has_sweep_word) {
      c.diags().emit(DiagKind::MissingArgument, s.open_kw,
                     "`morphvisualizer` needs a sweep and an index: `morphvisualizer v sweep s index 0 endmorphvisualizer`");
    }
  }
  return id;
}

}  // namespace nomec::check
