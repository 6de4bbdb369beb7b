// Instances, groups and transforms (see handlers.h): `instance NAME TARGET translate (…)
// rotate (…) (…) surface S endinstance` (SLIDE: `instance TARGET [id NAME]`), the scopes in
// which instance names live (the top level, a group, a block), and groups.
#include <fmt/format.h>
#include <utility>

#include "frontend/check/handlers.h"

namespace nomec::check {

namespace {

// The transform an option adds to a chain, if it is one.
std::optional<ir::TransformKind> transform_of(Opt key) {
  switch (key) {
    case Opt::Translate: return ir::TransformKind::Translate;
    case Opt::Rotate: return ir::TransformKind::Rotate;
    case Opt::Scale: return ir::TransformKind::Scale;
    case Opt::Mirror: return ir::TransformKind::Mirror;
    default: return std::nullopt;
  }
}

// SLIDE's level of detail (slide.md §5): `lod SLF_OFF` … as written, or its value
// (`lod {if {$par_n >= 2} {expr $SLF_FULL} else {expr $SLF_OFF}}`); None after an unknown
// word (reported).
ir::OperandId lod_operand(Context& c, ir::NodeId id, const OptionValue& v) {
  if (v.operand.is_valid() || v.symbol.empty()) return v.operand;
  static constexpr std::string_view kWords[] = {"SLF_OFF", "SLF_BOUND", "SLF_EDGES", "SLF_FULL"};
  for (size_t i = 0; i < std::size(kWords); ++i) {
    if (v.symbol != kWords[i]) continue;
    ir::Expr e;
    e.kind = ir::ExprKind::Const;
    e.value = static_cast<double>(i);
    e.range = v.value_range;
    SmallVec<ir::ExprId, 4> exprs;
    exprs.push_back(c.module().add_expr(std::move(e)));
    return c.add_operand(id, "lod", std::move(exprs), v.word);
  }
  const std::string hint = closest_match(v.symbol, std::span<const std::string_view>(kWords));
  auto d = c.diags().emit(DiagKind::UnknownSymbol, v.value_range,
                          fmt::format("unknown level of detail `{}`{}", v.symbol,
                                      hint.empty() ? "" : fmt::format("; did you mean `{}`?", hint)));
  if (!hint.empty()) d.fixit(v.value_range, hint, fmt::format("replace with `{}`", hint));
  d.note(SourceRange{}, "known values: `SLF_OFF` (not drawn), `SLF_BOUND`, `SLF_EDGES`, `SLF_FULL` (nomec draws these three "
                        "in full)");
  return ir::OperandId::None();
}

// Transforms of one statement in written order, stored as one contiguous slice when the
// statement is done.
struct TransformChain {
  std::vector<ir::TransformOp> ops;
  ir::Slice<ir::TransformOp> store(ir::Module& m) const {
    ir::Slice<ir::TransformOp> s{static_cast<uint32_t>(m.transforms.size()), static_cast<uint32_t>(ops.size())};
    m.transforms.insert(m.transforms.end(), ops.begin(), ops.end());
    return s;
  }
};

// Reads `instance NAME TARGET` (NOME) or `instance TARGET [id NAME]` (SLIDE).
struct InstanceHead {
  std::string name;
  const ast::Item* target = nullptr;
  size_t id_at = 0;  // the position of SLIDE's `id` word, when the statement has one
};

// The position of an `id NAME` pair after the first word, or 0.
size_t slide_id_pair(const ast::Stmt& s) {
  for (size_t i = 1; i + 1 < s.items.size(); ++i) {
    if (s.items[i].kind == ItemKind::Word && s.items[i].text == "id" && s.items[i + 1].kind == ItemKind::Word) return i;
  }
  return 0;
}

// `instance TARGET … id NAME` in a NOME file: SLIDE's order. Say so, offer the NOME order,
// and read it as meant so the rest of the statement is checked.
InstanceHead read_slide_head_in_nome(Context& c, const ast::Stmt& s, size_t id_at, size_t& pos) {
  const ast::Item& target = s.items[0];
  const ast::Item& name = s.items[id_at + 1];
  std::string middle;
  if (id_at > 1) {
    middle = " " + std::string(c.sources().text(SourceRange{s.open_kw.file, s.items[1].range.begin, s.items[id_at - 1].range.end}));
  }
  const std::string nome_order = fmt::format("{} {}{}", name.text, target.text, middle);
  c.diags()
      .emit(DiagKind::SlideSyntaxInNome, SourceRange{s.open_kw.file, target.range.begin, name.range.end},
            fmt::format("`instance {} … id {}` is SLIDE's form; in a {} file the instance's name comes first: "
                        "`instance {} endinstance`",
                        target.text, name.text, dialect_name(c.dialect()), nome_order))
      .note(s.open_kw, "to check the file as SLIDE, give it the `.slf` extension (or pass `--dialect slide`)")
      .fixit(SourceRange{s.open_kw.file, target.range.begin, name.range.end}, nome_order, "write it in NOME's order");
  pos = 1;
  return InstanceHead{std::string(name.text), &target, id_at};
}

InstanceHead read_head(Context& c, const ast::Stmt& s, size_t& pos) {
  InstanceHead h;
  if (c.dialect() != Dialect::Slide) {
    if (size_t id_at = slide_id_pair(s); id_at != 0 && s.items[0].kind == ItemKind::Word) {
      return read_slide_head_in_nome(c, s, id_at, pos);
    }
    if (auto n = c.read_name(s, pos, "instance i mesh_name endinstance")) h.name = *n;
    if (pos < s.items.size() && s.items[pos].kind == ItemKind::Word && !is_option(options_for(s.kind), s.items[pos].text)) {
      h.target = &s.items[pos++];
    } else if (!h.name.empty()) {
      c.diags().emit(DiagKind::MissingArgument, s.items[0].range,
                     fmt::format("instance `{}` needs a target after its name: `instance {} MESH endinstance`", h.name, h.name));
    }
    return h;
  }
  if (pos < s.items.size() && s.items[pos].kind == ItemKind::Word) {
    h.target = &s.items[pos++];
    h.name = std::string(h.target->text);
  } else {
    c.diags().emit(DiagKind::MissingName, s.open_kw, "`instance` needs a target: `instance MESH endinstance`");
  }
  for (size_t i = pos; i + 1 < s.items.size(); ++i) {
    if (s.items[i].kind == ItemKind::Word && s.items[i].text == "id" && s.items[i + 1].kind == ItemKind::Word) {
      h.name = std::string(s.items[i + 1].text);
    }
  }
  return h;
}

}  // namespace

// `instance MESH NAME` in a NOME file (the target first, as SLIDE orders it): the unknown
// target's error says so, with a fix-it that swaps the two. The instance is still read as
// written (editor features such as rename see the words where they are).
bool check_swapped(Context& c, const ast::Stmt& s, const InstanceHead& head) {
  if (c.dialect() == Dialect::Slide || head.target == nullptr || head.name.empty() || s.items.empty()) return false;
  const std::string target(head.target->text);
  auto defined = [&](const std::string& n) {
    // Shapes first: an instance's target is one in all but misspelt files.
    for (Ns ns : {Ns::Shape, Ns::Surface, Ns::Point, Ns::Face, Ns::Scene}) {
      if (c.scopes[static_cast<int>(ns)].contains(n)) return true;
    }
    return false;
  };
  const auto& shapes = c.scopes[static_cast<int>(Ns::Shape)];
  if (defined(target) || !shapes.contains(head.name)) return false;
  const SourceRange both{s.items[0].range.file, s.items[0].range.begin, head.target->range.end};
  c.diags()
      .emit(DiagKind::UnknownName, head.target->range,
            fmt::format("unknown mesh, group or generator `{}`; `{}` is a {}: NOME writes the instance's name first, "
                        "`instance {} {}`",
                        target, head.name, shapes.at(head.name).keyword, target, head.name))
      .fixit(both, fmt::format("{} {}", target, head.name), "swap the name and the target");
  return true;
}

ir::NodeId handle_instance(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  size_t pos = 0;
  InstanceHead head = read_head(c, s, pos);
  const bool swapped = check_swapped(c, s, head);
  ir::NodeId id = c.node_for(s, c.qualify(ctx, head.name), ctx);
  if (head.target != nullptr && !swapped) {
    ir::NodeId target = resolve_target(c, head.target->text, head.target->range);
    c.module().get<ir::InstanceData>(id).target = target;
    c.module().deps.add_edge(target, id);
  }
  // Instance names live in the scope of their parent (top level, group or block).
  if (!head.name.empty()) {
    c.note_declared(head.name, s.items.empty() ? s.open_kw : s.items[0].range, ctx.top);
    auto& scope = c.instance_scopes[ctx.parent.index + 1];
    if (auto it = scope.find(head.name); it != scope.end()) {
      c.diags()
          .emit(DiagKind::DuplicateInstanceName, s.items[0].range,
                fmt::format("instance name `{}` is used twice in this {}; paths through `{}` will be ambiguous", head.name,
                            ctx.top ? "file" : ctx.parent_keyword, head.name))
          .note(c.module().node(it->second).range, "first instance with this name");
    } else {
      scope[head.name] = id;
    }
  }
  TransformChain chain;
  // A `lookat … endlookat` inside adds its step to the chain (viewing.cpp).
  std::vector<ir::TransformOp>* outer_chain = std::exchange(c.lookat_chain, &chain.ops);
  read_body(c, a, s, pos, id, options_for(s.kind), [&](const OptionValue& v) {
    ir::InstanceData& d = c.module().get<ir::InstanceData>(id);
    if (v.spec->key == Opt::Mirror && c.dialect() == Dialect::Nome2) {
      // NOME2's bison parser reads `mirror (a b c d)` and drops it (compat.md A2).
      c.diags()
          .emit(DiagKind::IgnoredInDialect, v.word,
                "NOME2 reads `mirror (a b c d)` on an instance but does not apply it; ignored as NOME2 did")
          .fixit(SourceRange{v.word.file, v.word.begin, v.value_range.end}, "", "remove the `mirror`");
    } else if (auto t = transform_of(v.spec->key)) {
      chain.ops.push_back(ir::TransformOp{*t, v.operand, {}, {}});
    } else if (v.spec->key == Opt::Reverse) {
      d.is_reversed = true;
    } else if (v.spec->key == Opt::Surface) {
      d.surface = v.ref;
    } else if (v.spec->key == Opt::Backface) {
      d.backface = v.ref;
    } else if (v.spec->key == Opt::Hidden) {
      d.is_hidden = true;
    } else if (v.spec->key == Opt::Lod) {
      const ir::OperandId lod = lod_operand(c, id, v);
      c.module().get<ir::InstanceData>(id).lod = lod;  // `d` may have moved: the operand added a node
    }
  }, [&head, &s](const ast::Item& it) {
    // The `id NAME` of a SLIDE-order instance in a NOME file was read with its head.
    return head.id_at != 0 && (&it == &s.items[head.id_at] || &it == &s.items[head.id_at + 1]);
  });
  c.lookat_chain = outer_chain;
  c.module().get<ir::InstanceData>(id).transforms = chain.store(c.module());
  c.adopt(ctx.parent, id);
  return id;
}

ir::NodeId handle_group(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  size_t pos = 0;
  std::string name = c.read_name(s, pos, "group g … endgroup").value_or("");
  ir::NodeId id = c.node_for(s, c.qualify(ctx, name), ctx);
  auto option = [&c, id](const OptionValue& v) {
    if (v.spec->key == Opt::Surface) c.module().get<ir::GroupData>(id).surface = v.ref;
    if (v.spec->key == Opt::Lod) {
      const ir::OperandId lod = lod_operand(c, id, v);
      c.module().get<ir::GroupData>(id).lod = lod;
    }
  };
  read_body(c, a, s, pos, id, options_for(s.kind), option);
  // SLIDE: instances Tcl code added with `slide create instance I G N` (tcl.cpp).
  if (auto it = c.tcl_group_additions.find(name); it != c.tcl_group_additions.end() && ctx.top) {
    const auto [added_ast, added] = it->second;
    c.tcl_group_additions.erase(it);
    read_body(c, *added_ast, *added, 1, id, options_for(s.kind), option);
  }
  if (ctx.parent.is_valid()) c.module().deps.add_edge(id, ctx.parent);
  return id;
}

ir::NodeId handle_transform(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  ir::NodeId id = c.node_for(s, c.qualify(ctx, ""), ctx);
  TransformChain chain;
  read_body(c, a, s, 0, id, options_for(s.kind), [&](const OptionValue& v) {
    if (auto t = transform_of(v.spec->key)) chain.ops.push_back(ir::TransformOp{*t, v.operand, {}, {}});
  });
  c.module().get<ir::TransformData>(id).ops = chain.store(c.module());
  return id;
}

}  // namespace nomec::check
