// Definitions and name resolution (see handlers.h): every named top-level definition is
// declared before any statement is checked, so a use above its definition gets a precise
// "used before its definition" in NOME (SLIDE binds late); uses resolve per namespace, and a
// name found in another namespace is a kind error, not a typo.
#include <algorithm>
#include <fmt/format.h>

#include "frontend/check/handlers.h"

namespace nomec::check {

namespace {

// The namespace a top-level definition goes to; nullopt for statements that define no name.
std::optional<Ns> namespace_of(BlockKind kind) {
  switch (kind) {
    case BlockKind::Surface:
    case BlockKind::Backface: return Ns::Surface;  // colours
    case BlockKind::Point: return Ns::Point;
    case BlockKind::Face:
    case BlockKind::Facet: return Ns::Face;
    case BlockKind::Camera:
    case BlockKind::Light:
    case BlockKind::Window:
    case BlockKind::Viewport: return Ns::Scene;
    case BlockKind::Bank:
    case BlockKind::Instance:
    case BlockKind::Delete:
    case BlockKind::Sharp:
    case BlockKind::Savedparameter:
    case BlockKind::Consolidate:
    case BlockKind::Render:
    case BlockKind::Foreground:
    case BlockKind::Background:
    case BlockKind::Insidefaces:
    case BlockKind::Outsidefaces:
    case BlockKind::Offsetfaces:
    case BlockKind::Zipper:
    case BlockKind::Vertex:
    case BlockKind::Path:
    case BlockKind::Transform:
    case BlockKind::Lookat:
    case BlockKind::Consolidateface:
    case BlockKind::Frontcolor:
    case BlockKind::Backcolor:
    case BlockKind::Backgroundcolor: return std::nullopt;
    default: return Ns::Shape;
  }
}

void declare_stmt(Context& c, const ast::Stmt& s, int order) {
  std::optional<Ns> ns = namespace_of(s.kind);
  if (!ns) return;
  if (s.items.empty() || s.items[0].kind != ItemKind::Word) return;  // reported later
  if (s.kind == BlockKind::Merge && s.items[0].text == "epsilon") return;  // NOME2's nameless scene merge
  std::string name(s.items[0].text);
  ir::NodeId id = c.module().add_node(node_kind_for(s.kind), s.keyword, name, s.range);
  if (*ns == Ns::Scene) c.module().get<ir::SceneData>(id).kind = scene_kind_for(s.kind);
  // compat.md §E5: in the 2016 family, further `mesh consolidatedmesh` blocks add to the
  // first (meshes.cpp), so they are not duplicate definitions.
  const bool adds = is_consolidated_mesh(c, s) && c.scopes[static_cast<int>(*ns)].contains(name);
  if (!adds) define(c, *ns, name, Symbol{id, s.items[0].range, order, s.keyword});
  if (ir::NodeId* d = c.declared_slot(s)) *d = id;
}

}  // namespace

namespace {

// The identifier a NOME3 `$name` stands for where a name is expected, or "" when the
// reference is a slider (`$bank.param`), a built-in (`$time`) or has a declared bank as
// its prefix (a misspelt slider, reported as such).
std::string_view dollar_name(Context& c, const ast::Expr& x) {
  if (x.kind != ast::ExprKind::DollarRef || x.in_braces || x.text.size() < 2) return {};
  const std::string_view name = x.text.substr(1);
  if (name == "time" || name == "frame") return {};
  if (lookup_param_text(c, name).is_valid()) return {};
  if (const size_t dot = name.find('.'); dot != std::string_view::npos && c.banks.count(name.substr(0, dot))) {
    return {};
  }
  return name;
}

}  // namespace

void normalize_dollar_names(Context& c, ast::Ast& a) {
  if (c.dialect() != Dialect::Nome3) return;
  // List elements: `( $a $b $c )` in a face is `(a b c)`. Only whole elements: an operand
  // such as `$k * 2` or `{expr $k}` keeps reading a slider (and reports an unknown one).
  for (ast::ParenList& l : a.lists) {
    for (ast::ExprId e : l.elems) {
      ast::Expr& x = a.exprs[e.index];
      if (std::string_view n = dollar_name(c, x); !n.empty()) {
        x.kind = ast::ExprKind::Name;
        x.text = n;
      }
    }
  }
  // Items: `torusknot $k (…)` defines `k`, `instance i $k` places it.
  auto items = [&](std::span<ast::Item> list) {
    for (ast::Item& it : list) {
      if (it.kind != ItemKind::Value) continue;
      if (std::string_view n = dollar_name(c, a.expr(it.expr)); !n.empty()) {
        it.kind = ItemKind::Word;
        it.text = n;
      }
    }
  };
  for (ast::Stmt& s : a.stmts) items(std::span<ast::Item>(s.items.data(), s.items.size()));
  items(a.top);
}

bool is_consolidated_mesh(const Context& c, const ast::Stmt& s) {
  return s.kind == BlockKind::Mesh && (c.dialect() == Dialect::Nome || c.dialect() == Dialect::Nome2) && !s.items.empty() &&
         s.items[0].kind == ItemKind::Word && s.items[0].text == "consolidatedmesh";
}

void declare(Context& c, std::span<const ast::Ast> trees, int order_base) {
  c.reserve_for(trees);
  // Each namespace's table is sized once for the names the trees declare, rather than
  // rehashed as it grows.
  size_t per_ns[static_cast<int>(Ns::Count)] = {};
  for (const ast::Ast& a : trees) {
    for (const ast::Item& it : a.top) {
      if (it.kind != ItemKind::Block) continue;
      if (std::optional<Ns> ns = namespace_of(a.stmt(it.block).kind)) ++per_ns[static_cast<int>(*ns)];
    }
  }
  for (int ns = 0; ns < static_cast<int>(Ns::Count); ++ns) {
    if (per_ns[ns] > 0) c.scopes[ns].reserve(c.scopes[ns].size() + per_ns[ns]);
  }
  int order = order_base;
  for (const ast::Ast& a : trees) {
    for (const ast::Item& it : a.top) {
      ++order;
      if (it.kind == ItemKind::Block) declare_stmt(c, a.stmt(it.block), order);
    }
  }
}

// A second definition of a name (compat.md E1): NOME3 replaces the library entry, so later
// references bind to the new entity and earlier ones keep the old one (a warning); NOME 2016
// keeps the first definition and ignores the second (a warning); NOME2 and SLIDE reject it.
void define(Context& c, Ns ns, std::string_view name, Symbol sym) {
  c.note_declared(name, sym.range, true, true);
  auto& table = c.scopes[static_cast<int>(ns)];
  auto [it, inserted] = table.emplace(name, sym);
  if (inserted) return;
  const Symbol& first = it->second;
  switch (c.dialect()) {
    case Dialect::Nome3: {
      auto& later = c.redefinitions[static_cast<int>(ns)][std::string(name)];
      const Symbol prev = later.empty() ? first : later.back();  // a copy: push_back may move `later`
      later.push_back(sym);
      c.diags()
          .emit(DiagKind::Redefinition, sym.range,
                fmt::format("`{}` is defined again; as in NOME3, uses below this line name the new {} and uses above it "
                            "keep the {} defined first",
                            name, sym.keyword, prev.keyword))
          .note(prev.range, "previous definition is here");
      return;
    }
    case Dialect::Nome:
      c.diags()
          .emit(DiagKind::Redefinition, sym.range,
                fmt::format("`{}` is already defined as a {}; as in NOME 2016, the first definition is kept and this one "
                            "is ignored",
                            name, first.keyword))
          .note(first.range, "the definition in use is here");
      return;
    case Dialect::Nome2:
    case Dialect::Slide: break;
  }
  c.diags()
      .emit(DiagKind::DuplicateDefinition, sym.range, fmt::format("`{}` is already defined as a {}", name, first.keyword))
      .note(first.range, "previous definition is here");
}

ir::NodeId lookup(Context& c, Ns ns, std::string_view name, SourceRange use, bool report_order) {
  auto& table = c.scopes[static_cast<int>(ns)];
  auto it = table.find(name);
  if (it == table.end()) return ir::NodeId::None();
  const Symbol* sym = &it->second;
  // NOME3 redefinitions: the last definition above the use (compat.md E1). Most files have
  // none, and then the name is not hashed a second time.
  const auto& redefined = c.redefinitions[static_cast<int>(ns)];
  if (auto r = redefined.empty() ? redefined.end() : redefined.find(name); r != redefined.end()) {
    for (const Symbol& later : r->second) {
      if (later.order <= c.order) sym = &later;
    }
  }
  if (c.name_uses != nullptr) c.name_uses->push_back({use, sym->node});
  if (report_order && c.dialect() != Dialect::Slide && sym->order > c.order && c.order < (1 << 20)) {
    c.diags()
        .emit(DiagKind::UseBeforeDefinition, use,
              fmt::format("`{}` is used before its definition; NOME requires definitions above their uses", name))
        .note(sym->range, "defined here");
  }
  return sym->node;
}

std::vector<std::string_view> names_in(const Context& c, Ns ns) {
  return sorted_names(c.scopes[static_cast<int>(ns)]);
}

ir::NodeId report_unknown(Context& c, Ns ns, std::string_view name, SourceRange use, std::string_view wanted) {
  if (c.dialect() == Dialect::Slide && c.has_tcl && !c.tcl_available) {
    if (!c.first_tcl_report(std::string(name))) return ir::NodeId::None();
    c.diags().emit(DiagKind::TclDefinedName, use,
                   fmt::format("`{}` is not defined in this file; it may be created by Tcl code in a `tclinit` block, "
                               "which nomec does not evaluate yet",
                               name));
    return ir::NodeId::None();
  }
  std::string hint = closest_match(name, names_in(c, ns));
  auto d = c.diags().emit(DiagKind::UnknownName, use,
                          fmt::format("unknown {} `{}`{}", wanted, name, hint.empty() ? "" : fmt::format("; did you mean `{}`?", hint)));
  if (!hint.empty()) d.fixit(use, hint, fmt::format("replace with `{}`", hint));
  return ir::NodeId::None();
}

ir::NodeId resolve(Context& c, Ns ns, std::string_view name, SourceRange use, std::string_view wanted) {
  ir::NodeId id = lookup(c, ns, name, use, true);
  if (id.is_valid()) return id;
  // Same name in another namespace: a kind error, not a typo.
  for (int other = 0; other < static_cast<int>(Ns::Count); ++other) {
    if (other == static_cast<int>(ns)) continue;
    auto& table = c.scopes[other];
    if (auto it = table.find(name); it != table.end()) {
      c.diags()
          .emit(DiagKind::WrongKind, use,
                fmt::format("`{}` is a {}, but {} is needed here", name, it->second.keyword, wanted))
          .note(it->second.range, "defined here");
      return ir::NodeId::None();
    }
  }
  // `wanted` reads "a surface" after "is needed here"; "unknown surface" drops the article.
  std::string_view noun = wanted;
  for (std::string_view article : {"a ", "an "}) {
    if (noun.starts_with(article)) noun.remove_prefix(article.size());
  }
  return report_unknown(c, ns, name, use, noun);
}

ir::NodeId resolve_any(Context& c, std::string_view name, SourceRange use) {
  for (Ns ns : {Ns::Shape, Ns::Point, Ns::Face, Ns::Surface, Ns::Scene}) {
    ir::NodeId id = lookup(c, ns, name, use, true);
    if (id.is_valid()) return id;
  }
  return report_unknown(c, Ns::Shape, name, use, "name");
}

ir::NodeId resolve_point_like(Context& c, std::string_view name, SourceRange use) {
  for (Ns ns : {Ns::Point, Ns::Shape}) {
    ir::NodeId id = lookup(c, ns, name, use, true);
    if (id.is_valid()) return id;
  }
  return report_unknown(c, Ns::Point, name, use, "point");
}

ir::NodeId resolve_target(Context& c, std::string_view name, SourceRange use) {
  for (Ns ns : {Ns::Shape, Ns::Scene}) {
    ir::NodeId id = lookup(c, ns, name, use, true);
    if (id.is_valid()) return id;
  }
  for (Ns ns : {Ns::Point, Ns::Face, Ns::Surface}) {
    auto& table = c.scopes[static_cast<int>(ns)];
    if (auto it = table.find(name); it != table.end()) {
      c.diags()
          .emit(DiagKind::WrongKind, use,
                fmt::format("`{}` is a {}; an instance needs a mesh, group, generator, curve or block", name,
                            it->second.keyword))
          .note(it->second.range, "defined here");
      return ir::NodeId::None();
    }
  }
  if (name == "consolidatemesh" && (c.is_saved_work || c.base_loaded)) {
    c.diags().emit(DiagKind::UnknownName, use, "`consolidatemesh` is defined by a `consolidate` block, and this scene has none");
    return ir::NodeId::None();
  }
  return report_unknown(c, Ns::Shape, name, use, "mesh, group or generator");
}

}  // namespace nomec::check
