// JIPCAD's colours (see handlers.h; compat.md F1, F2): the viewer's front-face, back-face
// and background colours (`frontcolor (r g b) endfrontcolor` …, no geometry) and named
// back-face colours (`backface B color (r g b) endbackface`) that faces and instances apply
// with `backface B` (read with their other options in options.cpp).
#include <fmt/format.h>

#include "frontend/check/handlers.h"

namespace nomec::check {

ir::NodeId handle_scene_color(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  if (!ctx.top) c.misplaced(s, ctx);
  ir::NodeId id = c.node_for(s, "", ctx);
  ir::SceneColorData& d = c.module().get<ir::SceneColorData>(id);
  d.kind = s.kind == BlockKind::Frontcolor ? ir::SceneColorKind::Front
           : s.kind == BlockKind::Backcolor ? ir::SceneColorKind::Back
                                            : ir::SceneColorKind::Background;
  // The colour list is read as a surface's `color` is: 3 numbers in [0, 1].
  bool took = false;
  auto positional = [&](const ast::Item& it) {
    if (it.kind != ItemKind::List || took) return false;
    took = true;
    const ast::ParenList& list = a.list(it.list);
    c.check_commas(a, it.list);
    if (list.elems.size() != 3) {
      c.diags().emit(DiagKind::ListArity, list.range,
                     fmt::format("`{}` needs a colour of 3 numbers `(r g b)`, got {}{}", s.keyword, list.elems.size(),
                                 c.split_text(a, list)));
    }
    SmallVec<ir::ExprId, 4> exprs;
    for (ast::ExprId e : list.elems) exprs.push_back(lower_expr(c, a, e, false));
    c.module().get<ir::SceneColorData>(id).color = c.add_operand(id, "color", std::move(exprs), list.range);
    check_color_list(c, a, it);
    return true;
  };
  read_body(c, a, s, 0, id, {}, {}, positional);
  if (!took) {
    c.diags().emit(DiagKind::MissingArgument, s.open_kw,
                   fmt::format("`{}` needs a colour `(r g b)`, e.g. `{} (1 0.5 0) end{}`", s.keyword, s.keyword, s.keyword));
  }
  return id;
}

ir::NodeId handle_backface(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  size_t pos = 0;
  std::string name = c.read_name(s, pos, "backface B color (1 0 0) endbackface").value_or("");
  ir::NodeId id = c.node_for(s, c.qualify(ctx, name), ctx);
  read_body(c, a, s, pos, id, options_for(s.kind), [&c, id](const OptionValue& v) {
    if (v.spec->key == Opt::Color) c.module().get<ir::BackfaceData>(id).color = v.operand;
  });
  if (!c.module().get<ir::BackfaceData>(id).color.is_valid()) {
    c.diags().emit(DiagKind::MissingArgument, s.open_kw, "`backface` needs a colour: `backface B color (1 0 0) endbackface`");
  }
  return id;
}

}  // namespace nomec::check
