// Instances, groups and transforms (see handlers.h): `instance NAME TARGET translate (…)
// rotate (…) (…) surface S endinstance` (SLIDE: `instance TARGET [id NAME]`), the scopes in
// which instance names live (the top level, a group, a block), and groups.
#include <fmt/format.h>

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
};

InstanceHead read_head(Context& c, const ast::Stmt& s, size_t& pos) {
  InstanceHead h;
  if (c.dialect() != Dialect::Slide) {
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
    for (const auto& scope : c.scopes) {
      if (scope.contains(n)) return true;
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
    ir::NodeId target = resolve_target(c, std::string(head.target->text), head.target->range);
    c.module().get<ir::InstanceData>(id).target = target;
    c.module().deps.add_edge(target, id);
  }
  // Instance names live in the scope of their parent (top level, group or block).
  if (!head.name.empty()) {
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
  read_body(c, a, s, pos, id, options_for(s.kind), [&](const OptionValue& v) {
    ir::InstanceData& d = c.module().get<ir::InstanceData>(id);
    if (auto t = transform_of(v.spec->key)) {
      chain.ops.push_back({*t, v.operand});
    } else if (v.spec->key == Opt::Surface) {
      d.surface = v.ref;
    } else if (v.spec->key == Opt::Hidden) {
      d.is_hidden = true;
    }
  });
  c.module().get<ir::InstanceData>(id).transforms = chain.store(c.module());
  c.adopt(ctx.parent, id);
  return id;
}

ir::NodeId handle_group(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  size_t pos = 0;
  std::string name = c.read_name(s, pos, "group g … endgroup").value_or("");
  ir::NodeId id = c.node_for(s, c.qualify(ctx, name), ctx);
  read_body(c, a, s, pos, id, options_for(s.kind), [&c, id](const OptionValue& v) {
    if (v.spec->key == Opt::Surface) c.module().get<ir::GroupData>(id).surface = v.ref;
  });
  if (ctx.parent.is_valid()) c.module().deps.add_edge(id, ctx.parent);
  return id;
}

ir::NodeId handle_transform(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  ir::NodeId id = c.node_for(s, c.qualify(ctx, ""), ctx);
  TransformChain chain;
  read_body(c, a, s, 0, id, options_for(s.kind), [&](const OptionValue& v) {
    if (auto t = transform_of(v.spec->key)) chain.ops.push_back({*t, v.operand});
  });
  c.module().get<ir::TransformData>(id).ops = chain.store(c.module());
  return id;
}

}  // namespace nomec::check
