// The checker context's services (see context.h): node and operand creation with their
// dependency edges, statement names, and text helpers for messages.
#include "frontend/check/context.h"

#include <algorithm>
#include <fmt/format.h>

namespace nomec::check {

ir::NodeKind node_kind_for(BlockKind kind) {
  switch (kind) {
    case BlockKind::Surface: return ir::NodeKind::Surface;
    case BlockKind::Point:
    case BlockKind::Vertex: return ir::NodeKind::Point;
    case BlockKind::Polyline: return ir::NodeKind::Polyline;
    case BlockKind::Face:
    case BlockKind::Facet:
    case BlockKind::Consolidateface: return ir::NodeKind::Face;
    case BlockKind::Object:
    case BlockKind::Mesh:
    case BlockKind::Consolidate:
    case BlockKind::Savedworkingmesh: return ir::NodeKind::Mesh;
    case BlockKind::Group: return ir::NodeKind::Group;
    case BlockKind::Instance: return ir::NodeKind::Instance;
    case BlockKind::Sweep: return ir::NodeKind::Sweep;
    case BlockKind::Crosssection: return ir::NodeKind::CrossSection;
    case BlockKind::Path: return ir::NodeKind::SweepPath;
    case BlockKind::Controlpoint: return ir::NodeKind::ControlPoint;
    case BlockKind::Transform: return ir::NodeKind::Transform;
    case BlockKind::Lookat:
    case BlockKind::Camera:
    case BlockKind::Light:
    case BlockKind::Window:
    case BlockKind::Viewport:
    case BlockKind::Render:
    case BlockKind::Foreground:
    case BlockKind::Background:
    case BlockKind::Insidefaces:
    case BlockKind::Outsidefaces:
    case BlockKind::Offsetfaces: return ir::NodeKind::SceneSetup;
    case BlockKind::Frontcolor:
    case BlockKind::Backcolor:
    case BlockKind::Backgroundcolor: return ir::NodeKind::SceneColor;
    case BlockKind::Backface: return ir::NodeKind::Backface;
    case BlockKind::Sweepmorph: return ir::NodeKind::SweepMorph;
    case BlockKind::Morphvisualizer: return ir::NodeKind::MorphVisualizer;
    case BlockKind::Delete: return ir::NodeKind::Delete;
    case BlockKind::Sharp: return ir::NodeKind::Sharp;
    case BlockKind::Zipper: return ir::NodeKind::Zipper;
    case BlockKind::Merge: return ir::NodeKind::Merge;
    case BlockKind::Subdivision: return ir::NodeKind::Subdivision;
    case BlockKind::Offset: return ir::NodeKind::Offset;
    case BlockKind::Handle: return ir::NodeKind::Handle;
    case BlockKind::Rind: return ir::NodeKind::Rind;
    case BlockKind::Sierpinski: return ir::NodeKind::Sierpinski;
    case BlockKind::Menger: return ir::NodeKind::Menger;
    case BlockKind::Mirror: return ir::NodeKind::FaceReversal;
    case BlockKind::Bank:
    case BlockKind::Savedparameter: return ir::NodeKind::Value;
    case BlockKind::Generator: return ir::NodeKind::Generator;
  }
  return ir::NodeKind::Value;
}

void Context::reserve_for(std::span<const ast::Ast> trees) {
  // At most about one IR expression per syntax expression (a generated 1 MiB scene has 0.83)
  // and two nodes (the statement and a value node) per statement: reserving once for all
  // the trees avoids moving the arrays while they grow, and reserving no more than that
  // keeps huge pages from backing a large unused tail.
  size_t exprs = 0, stmts = 0, names = 0;
  for (const ast::Ast& a : trees) {
    exprs += a.exprs.size();
    stmts += a.stmts.size();
    // Vertex references are names in lists (a face's `(v0 v1 v3 v2)`): at most one per name.
    for (const ast::ParenList& l : a.lists) {
      for (ast::ExprId e : l.elems) names += a.expr(e).kind == ast::ExprKind::Name ? 1 : 0;
    }
  }
  m_.exprs.reserve(m_.exprs.size() + exprs);
  m_.nodes.reserve(m_.nodes.size() + 2 * stmts);
  m_.operands.reserve(m_.operands.size() + stmts);
  m_.deps.reserve(m_.nodes.capacity());
  m_.vertex_refs.reserve(m_.vertex_refs.size() + names);
  for (const ast::Ast& a : trees) {
    declared_.push_back({&a, std::vector<ir::NodeId>(a.stmts.size(), ir::NodeId::None())});
  }
}

void Context::forget(const ast::Ast& a) {
  std::erase_if(declared_, [&](const Declared& d) { return d.ast == &a; });
  last_declared_ = 0;
}

ir::NodeId* Context::declared_slot(const ast::Stmt& s) {
  // Statements are mostly looked up in the tree of the one before: try that tree first.
  auto slot = [&](Declared& d) -> ir::NodeId* {
    const std::vector<ast::Stmt>& v = d.ast->stmts;
    if (!v.empty() && &s >= v.data() && &s < v.data() + v.size()) return &d.ids[static_cast<size_t>(&s - v.data())];
    return nullptr;
  };
  if (last_declared_ < declared_.size()) {
    if (ir::NodeId* id = slot(declared_[last_declared_])) return id;
  }
  for (size_t k = 0; k < declared_.size(); ++k) {
    if (ir::NodeId* id = slot(declared_[k])) {
      last_declared_ = k;
      return id;
    }
  }
  return nullptr;
}

ir::NodeId Context::node_for(const ast::Stmt& s, std::string name, const Ctx& ctx) {
  if (const ir::NodeId* d = declared_slot(s); d != nullptr && d->is_valid()) return *d;
  return m_.add_node(node_kind_for(s.kind), s.keyword, std::move(name), s.range, ctx.parent);
}

std::string Context::qualify(const Ctx& ctx, const std::string& name) const {
  if (!ctx.parent.is_valid() || name.empty()) return name;
  // Built by hand, not with a format string: every named statement inside a block passes here.
  const std::string& parent = m_.node(ctx.parent).name;
  std::string out;
  out.reserve(parent.size() + 1 + name.size());
  out += parent;
  out += '.';
  out += name;
  return out;
}

void Context::adopt(ir::NodeId parent, ir::NodeId child) {
  if (!parent.is_valid() || !child.is_valid()) return;
  m_.add_child(parent, child);
  m_.deps.add_edge(child, parent);
}

namespace {

void collect_params(const ir::Module& m, ir::ExprId root, std::vector<int32_t>& out) {
  if (!root.is_valid()) return;
  // Iterative: expressions may be deep.
  SmallVec<ir::ExprId, 16> todo;
  todo.push_back(root);
  while (!todo.empty()) {
    const ir::Expr& x = m.expr(todo.back());
    todo.pop_back();
    if (x.kind == ir::ExprKind::Param) out.push_back(x.param.index);
    for (ir::ExprId c : m.subexprs(x)) todo.push_back(c);
  }
}

}  // namespace

ir::OperandId Context::add_operand(ir::NodeId owner, std::string_view name, SmallVec<ir::ExprId, 4> exprs,
                                   SourceRange range) {
  std::vector<int32_t>& params = params_scratch_;
  params.clear();
  for (ir::ExprId e : exprs) collect_params(m_, e, params);
  std::sort(params.begin(), params.end());
  params.erase(std::unique(params.begin(), params.end()), params.end());
  ir::Operand o;
  o.name = name;
  o.exprs = m_.add_expr_list(std::span<const ir::ExprId>(exprs.data(), exprs.size()));
  o.range = range;
  o.owner = owner;
  const ir::OperandId id = m_.add_operand(std::move(o));
  if (!params.empty()) {
    // A Value node for operands whose expressions depend on parameters.
    const std::string& owner_name = m_.node(owner).name;
    std::string value_name;
    value_name.reserve(owner_name.size() + 1 + name.size());
    value_name.append(owner_name).append(1, '.').append(name);
    ir::NodeId vid = m_.add_node(ir::NodeKind::Value, "value", std::move(value_name), range);
    m_.get<ir::ValueData>(vid).operand = id;
    for (int32_t p : params) m_.deps.add_edge(ir::NodeId(p), vid);
    m_.deps.add_edge(vid, owner);
    m_.operand(id).value_node = vid;
  }
  m_.add_node_operand(owner, id);
  return id;
}

std::optional<std::string> Context::read_name(const ast::Stmt& s, size_t& pos, std::string_view example) {
  if (pos < s.items.size() && s.items[pos].kind == ItemKind::Word) return std::string(s.items[pos++].text);
  diags_.emit(DiagKind::MissingName, s.open_kw,
              fmt::format("`{}` needs a name, e.g. `{}`", s.keyword, example));
  return std::nullopt;
}

void Context::misplaced(const ast::Stmt& s, const Ctx& ctx) {
  diags_.emit(DiagKind::MisplacedStatement, s.open_kw,
              fmt::format("`{}` cannot appear inside `{}`", s.keyword, ctx.parent_keyword));
}

std::string Context::clip(std::string_view t) {
  std::string s(t.substr(0, 40));
  std::replace(s.begin(), s.end(), '\n', ' ');
  return t.size() > 40 ? s + "…" : s;
}

std::string Context::split_text(const ast::Ast& a, const ast::ParenList& list) const {
  if (list.elems.empty()) return "";
  // At most the first 16 parts: a list of millions of numbers makes a message of a line.
  constexpr size_t kShownParts = 16;
  std::vector<std::string> parts;
  for (ast::ExprId e : list.elems) {
    if (parts.size() == kShownParts) break;
    parts.push_back(fmt::format("`{}`", clip(sources_.text(a.expr(e).range))));
  }
  if (list.elems.size() > kShownParts) parts.push_back(fmt::format("… ({} in all)", list.elems.size()));
  return fmt::format("; the list was read as: {}", fmt::join(parts, " | "));
}

void Context::check_commas(const ast::Ast& a, ast::ListId list) {
  const std::span<const ast::ListComma> commas = a.commas_of(list);
  if (commas.empty()) return;
  auto d = diags_.emit(DiagKind::CommaInList, commas.front().range, "NOME lists are separated by spaces; commas are ignored");
  for (const ast::ListComma& c : commas) d.fixit(c.range, "", "remove `,`");
}

}  // namespace nomec::check
