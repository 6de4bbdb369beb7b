// Viewing set-up (see handlers.h): SLIDE's `camera`, `light`, `window`, `viewport` and
// `render` (slide.md §3.18–3.20), NOME3's forms of the first four, `lookat` inside an
// instance (a step of its transform chain), and NOME2's display colours. Their values are
// kept in the IR (the live preview shows the scene through the render's camera, with its
// lights and background); STL/OBJ/PLY do not carry them. A render's camera and light paths
// (`gCam.iCam.cam`) are resolved once every instance is known, since SLIDE files write
// `render` above the groups it names.
#include <algorithm>
#include <fmt/format.h>

#include "frontend/check/handlers.h"

namespace nomec::check {

namespace {

constexpr SymbolEntry<ir::Projection> kProjections[] = {
    {"SLF_PARALLEL", ir::Projection::Parallel},
    {"SLF_PERSPECTIVE", ir::Projection::Perspective},
    {"NOME_ORTHOGONAL", ir::Projection::Parallel},
    {"NOME_FRUSTUM", ir::Projection::Perspective},
};

constexpr SymbolEntry<ir::LightType> kLightTypes[] = {
    {"SLF_AMBIENT", ir::LightType::Ambient},  {"SLF_DIRECTIONAL", ir::LightType::Directional},
    {"SLF_POINT", ir::LightType::Point},      {"SLF_SPOT", ir::LightType::Spot},
    {"NOME_AMBIENT", ir::LightType::Ambient}, {"NOME_DIRECTIONAL", ir::LightType::Directional},
};

constexpr SymbolEntry<bool> kOnOff[] = {{"SLF_ON", true}, {"SLF_OFF", false}};

// A symbol or Tcl value of an enumerated field.
template <typename E, size_t N>
void read_enum(Context& c, ir::SceneEnum<E>& out, const SymbolEntry<E> (&table)[N], const OptionValue& v,
               std::string_view what) {
  if (v.operand.is_valid()) {
    out.value = v.operand;
    out.is_written = true;
  } else if (auto e = resolve_symbol(c, table, v, what)) {
    out.symbol = *e;
    out.is_written = true;
  }
}

bool is_scene(const ir::Module& m, ir::NodeId id, ir::SceneKind kind) {
  const ir::Node& n = m.node(id);
  return n.kind == ir::NodeKind::SceneSetup && n.as<ir::SceneData>().kind == kind;
}

std::string_view scene_kind_word(ir::SceneKind k) {
  switch (k) {
    case ir::SceneKind::Camera: return "camera";
    case ir::SceneKind::Light: return "light";
    case ir::SceneKind::Window: return "window";
    case ir::SceneKind::Viewport: return "viewport";
    case ir::SceneKind::Render: return "render";
    case ir::SceneKind::DisplayColor: return "display colour";
  }
  return "?";
}

// A name that must denote a viewing statement of `kind` (`render VIEWPORT …`, `viewport V
// WINDOW`, `cameraID C`): None (reported) otherwise.
ir::NodeId scene_ref(Context& c, const std::string& name, SourceRange use, ir::SceneKind kind) {
  const std::string wanted = fmt::format("a {}", scene_kind_word(kind));
  ir::NodeId id = resolve(c, Ns::Scene, name, use, wanted);
  if (!id.is_valid() || is_scene(c.module(), id, kind)) return id;
  c.diags()
      .emit(DiagKind::WrongKind, use, fmt::format("`{}` is a {}, but {} is needed here", name, c.module().node(id).keyword, wanted))
      .note(c.module().node(id).range, "defined here");
  return ir::NodeId::None();
}

// `camera`, `light`, `window`, `viewport`: options into the payload by meaning.
void view_option(Context& c, ir::NodeId id, const OptionValue& v) {
  ir::SceneData& d = c.module().get<ir::SceneData>(id);
  switch (v.spec->key) {
    case Opt::Projection: read_enum(c, d.projection, kProjections, v, "projection"); return;
    case Opt::Frustum:
      d.frustum = v.operand;
      d.frustum_is_lrbtnf = v.is_single_list;
      return;
    case Opt::LightType: read_enum(c, d.light_type, kLightTypes, v, "light type"); return;
    case Opt::Color: d.color = v.operand; return;
    case Opt::Direction: d.direction = v.operand; return;
    case Opt::Background: d.background = v.operand; return;
    case Opt::Origin: d.origin = v.operand; return;
    case Opt::Size: d.size = v.operand; return;
    case Opt::Resize: read_enum(c, d.resize, kOnOff, v, "on/off flag"); return;
    case Opt::Ratio: read_enum(c, d.ratio, kOnOff, v, "on/off flag"); return;
    case Opt::CameraId:
      if (v.ref.is_valid() && !is_scene(c.module(), v.ref, ir::SceneKind::Camera)) {
        c.diags()
            .emit(DiagKind::WrongKind, v.value_range,
                  fmt::format("`{}` is a {}, but `cameraID` names a camera", c.module().node(v.ref).name,
                              c.module().node(v.ref).keyword))
            .note(c.module().node(v.ref).range, "defined here");
        return;
      }
      d.camera = v.ref;
      return;
    default: return;  // ribbegin/ribend: RenderMan text
  }
}

ir::NodeId handle_view_definition(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  size_t pos = 0;
  std::string name = c.read_name(s, pos, fmt::format("{} NAME … end{}", s.keyword, s.keyword)).value_or("");
  ir::NodeId id = c.node_for(s, c.qualify(ctx, name), ctx);
  c.module().get<ir::SceneData>(id).kind = scene_kind_for(s.kind);
  // `viewport V WINDOW`: the window it shows in.
  auto positional = [&c, id, &s](const ast::Item& it) {
    if (s.kind != BlockKind::Viewport || it.kind != ItemKind::Word) return false;
    if (c.module().get<ir::SceneData>(id).window.is_valid()) return false;
    ir::NodeId w = scene_ref(c, std::string(it.text), it.range, ir::SceneKind::Window);
    c.module().get<ir::SceneData>(id).window = w;
    if (w.is_valid()) c.module().deps.add_edge(w, id);
    return true;
  };
  read_body(c, a, s, pos, id, options_for(s.kind), [&c, id](const OptionValue& v) { view_option(c, id, v); }, positional);
  return id;
}

// `lookat eye (…) target (…) up (…) endlookat` inside an instance: one step of its chain, in
// written order with its translates and rotates; the operands belong to the instance.
ir::NodeId handle_lookat(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  if (ctx.parent_kind != BlockKind::Instance || c.lookat_chain == nullptr) {
    c.diags().emit(DiagKind::MisplacedStatement, s.open_kw,
                   "`lookat … endlookat` aims an instance; it belongs inside `instance … endinstance`");
    return ir::NodeId::None();
  }
  ir::TransformOp op{ir::TransformKind::LookAt, {}, {}, {}};
  read_body(c, a, s, 0, ctx.parent, options_for(s.kind), [&op](const OptionValue& v) {
    if (v.spec->key == Opt::Eye) op.args = v.operand;
    if (v.spec->key == Opt::Target) op.target = v.operand;
    if (v.spec->key == Opt::Up) op.up = v.operand;
  });
  c.lookat_chain->push_back(op);
  return ir::NodeId::None();
}

constexpr std::string_view kRenderUsage = "`render VIEWPORT CAMERA_PATH ROOT (light PATH [SLF_ON|SLF_OFF])* endrender`";

// `light PATH [onoff]` of a render, from `pos` (after the word `light`).
void read_render_light(Context& c, const ast::Ast& a, const ast::Stmt& s, const ast::Item& kw, size_t& pos, ir::NodeId id) {
  if (pos >= s.items.size() || s.items[pos].kind != ItemKind::Word) {
    c.diags().emit(DiagKind::MissingArgument, kw.range,
                   "`light` in a `render` needs the path of a light, e.g. `light world.front_sun.sun`");
    return;
  }
  ir::RenderLight l;
  l.path.text = std::string(s.items[pos].text);
  l.path.range = s.items[pos].range;
  ++pos;
  if (pos < s.items.size() && s.items[pos].kind == ItemKind::Value) {
    SmallVec<ir::ExprId, 4> exprs;
    exprs.push_back(scalar_of_item(c, a, s.items[pos], false));
    l.on.value = c.add_operand(id, "light", std::move(exprs), s.items[pos].range);
    l.on.is_written = true;
    ++pos;
  } else if (pos < s.items.size() && s.items[pos].kind == ItemKind::Word && s.items[pos].text.starts_with("SLF_")) {
    OptionValue v;
    v.symbol = s.items[pos].text;
    v.value_range = s.items[pos].range;
    if (auto on = resolve_symbol(c, kOnOff, v, "on/off flag")) {
      l.on.symbol = *on;
      l.on.is_written = true;
    }
    ++pos;
  }
  c.module().get<ir::SceneData>(id).lights.push_back(std::move(l));
}

ir::NodeId handle_render(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  ir::NodeId id = c.node_for(s, c.qualify(ctx, ""), ctx);
  c.module().get<ir::SceneData>(id).kind = ir::SceneKind::Render;
  if (!ctx.top) c.misplaced(s, ctx);
  size_t pos = 0;
  for (; pos < 3; ++pos) {
    if (pos >= s.items.size() || s.items[pos].kind != ItemKind::Word || s.items[pos].text == "light") {
      static constexpr std::string_view kWhat[] = {"a viewport", "the path of a camera", "the root group"};
      c.diags().emit(DiagKind::MissingArgument, pos < s.items.size() ? s.items[pos].range : s.open_kw,
                     fmt::format("`render` needs {} here: {}", kWhat[pos], kRenderUsage));
      return id;
    }
    const ast::Item& it = s.items[pos];
    const std::string word(it.text);
    if (pos == 0) {
      ir::NodeId vp = scene_ref(c, word, it.range, ir::SceneKind::Viewport);
      c.module().get<ir::SceneData>(id).viewport = vp;
      if (vp.is_valid()) c.module().deps.add_edge(vp, id);
    } else if (pos == 1) {
      ir::SceneData& d = c.module().get<ir::SceneData>(id);
      d.camera_path.text = word;
      d.camera_path.range = it.range;
    } else {
      ir::NodeId root = resolve(c, Ns::Shape, word, it.range, "a group");
      c.module().get<ir::SceneData>(id).root = root;
      if (root.is_valid()) c.module().deps.add_edge(root, id);
    }
  }
  while (pos < s.items.size()) {
    const ast::Item& it = s.items[pos++];
    if (it.kind == ItemKind::Word && it.text == "light") {
      read_render_light(c, a, s, it, pos, id);
    } else if (it.kind == ItemKind::Block) {
      c.misplaced(a.stmt(it.block), Ctx{id, s.kind, s.keyword, false});
    } else {
      c.diags().emit(it.kind == ItemKind::Word ? DiagKind::UnknownArgument : DiagKind::UnexpectedItem, it.range,
                     fmt::format("unexpected `{}` in `render`; after the viewport, camera and root come only "
                                 "`light PATH [SLF_ON|SLF_OFF]` entries",
                                 Context::clip(c.sources().text(it.range))));
    }
  }
  c.renders.push_back(id);
  return id;
}

bool is_display_color(BlockKind k) {
  return k == BlockKind::Foreground || k == BlockKind::Background || k == BlockKind::Insidefaces ||
         k == BlockKind::Outsidefaces || k == BlockKind::Offsetfaces;
}

// NOME2's `foreground surface S endforeground` and its kin: the surface must exist; the
// colour is the viewer's, which no output format carries.
ir::NodeId handle_display_color(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  c.diags().emit(DiagKind::IgnoredStatement, s.open_kw,
                 fmt::format("`{}` sets a display colour of NOME2's viewer, which nomec's output does not carry; "
                             "accepted and ignored",
                             s.keyword));
  ir::NodeId id = c.node_for(s, c.qualify(ctx, ""), ctx);
  c.module().get<ir::SceneData>(id).kind = ir::SceneKind::DisplayColor;
  bool has_surface = false;
  read_body(c, a, s, 0, id, options_for(s.kind), [&](const OptionValue& v) { has_surface = has_surface || v.spec->key == Opt::Surface; });
  if (!has_surface) {
    c.diags().emit(DiagKind::MissingArgument, s.open_kw,
                   fmt::format("`{}` needs a surface: `{} surface S end{}`", s.keyword, s.keyword, s.keyword));
  }
  return id;
}

// The part `i` of a dotted path and where it is written.
struct PathPart {
  std::string text;
  SourceRange range;
};

std::vector<PathPart> split_path(const ir::ScenePath& p) {
  std::vector<PathPart> parts;
  size_t begin = 0;
  while (true) {
    const size_t dot = p.text.find('.', begin);
    const size_t end = dot == std::string::npos ? p.text.size() : dot;
    parts.push_back({p.text.substr(begin, end - begin),
                     SourceRange{p.range.file, p.range.begin + static_cast<uint32_t>(begin), p.range.begin + static_cast<uint32_t>(end)}});
    if (dot == std::string::npos) return parts;
    begin = dot + 1;
  }
}

void note_use(Context& c, SourceRange r, ir::NodeId node) {
  if (c.name_uses != nullptr) c.name_uses->push_back(NameUse{r, node});
}

// Follows `root.inst….node` through the instance scopes; the last instance must place the
// named node. Reports the first step that does not resolve.
void follow_instances(Context& c, ir::ScenePath& p, const std::vector<PathPart>& parts) {
  ir::Module& m = c.module();
  ir::NodeId scope = p.root;
  for (size_t i = 1; i + 1 < parts.size(); ++i) {
    const auto sc = c.instance_scopes.find(scope.index + 1);
    const ir::NodeId inst = sc == c.instance_scopes.end() || !sc->second.contains(parts[i].text) ? ir::NodeId::None()
                                                                                                  : sc->second.at(parts[i].text);
    if (!inst.is_valid()) {
      const std::vector<std::string_view> names =
          sc != c.instance_scopes.end() ? sorted_names(sc->second) : std::vector<std::string_view>{};
      const std::string hint = closest_match(parts[i].text, names);
      auto d = c.diags().emit(DiagKind::UnknownName, parts[i].range,
                              fmt::format("`{}` has no instance named `{}`{}", m.node(scope).name, parts[i].text,
                                          hint.empty() ? "" : fmt::format("; did you mean `{}`?", hint)));
      if (!hint.empty()) d.fixit(parts[i].range, hint, fmt::format("replace with `{}`", hint));
      return;
    }
    note_use(c, parts[i].range, inst);
    p.instances.push_back(inst);
    const ir::NodeId target = m.get<ir::InstanceData>(inst).target;
    if (!target.is_valid()) return;  // reported at the instance
    const ir::Node& t = m.node(target);
    if (i + 2 < parts.size()) {
      if (t.kind != ir::NodeKind::Group) {
        c.diags()
            .emit(DiagKind::WrongKind, parts[i + 1].range,
                  fmt::format("instance `{}` places the {} `{}`, not a group, so the path cannot go on to `{}`",
                              parts[i].text, t.keyword, t.name, parts[i + 1].text))
            .note(m.node(inst).range, "the instance");
        return;
      }
      scope = target;
      continue;
    }
    if (t.name != parts.back().text) {
      c.diags()
          .emit(DiagKind::UnknownName, parts.back().range,
                fmt::format("instance `{}` places `{}`, not `{}`", parts[i].text, t.name, parts.back().text))
          .note(m.node(inst).range, "the instance")
          .fixit(parts.back().range, t.name, fmt::format("replace with `{}`", t.name));
      return;
    }
    note_use(c, parts.back().range, target);
    p.node = target;
  }
}

void resolve_path(Context& c, ir::ScenePath& p, ir::SceneKind want) {
  if (p.text.empty()) return;  // reported when the render was read
  const std::vector<PathPart> parts = split_path(p);
  const std::string wanted = fmt::format("a {}", scene_kind_word(want));
  if (parts.size() == 1) {
    p.node = scene_ref(c, p.text, p.range, want);
    return;
  }
  if (parts.size() == 2 || std::any_of(parts.begin(), parts.end(), [](const PathPart& x) { return x.text.empty(); })) {
    c.diags().emit(DiagKind::UnknownName, p.range,
                   fmt::format("`{}` is not a path to {}: write the root group, its instances and the {}, e.g. "
                               "`gCam.iCam.cam`, or just the {}'s name",
                               p.text, wanted, scene_kind_word(want), scene_kind_word(want)));
    return;
  }
  p.root = resolve(c, Ns::Shape, parts[0].text, parts[0].range, "a group");
  if (!p.root.is_valid()) return;
  if (c.module().node(p.root).kind != ir::NodeKind::Group) {
    c.diags()
        .emit(DiagKind::WrongKind, parts[0].range,
              fmt::format("`{}` is a {}; a path starts at a group", parts[0].text, c.module().node(p.root).keyword))
        .note(c.module().node(p.root).range, "defined here");
    p.root = ir::NodeId::None();
    return;
  }
  follow_instances(c, p, parts);
  if (p.node.is_valid() && !is_scene(c.module(), p.node, want)) {
    const ir::Node& n = c.module().node(p.node);
    c.diags()
        .emit(DiagKind::WrongKind, parts.back().range, fmt::format("`{}` is a {}, but {} is needed here", n.name, n.keyword, wanted))
        .note(n.range, "defined here");
    p.node = ir::NodeId::None();
  }
}

}  // namespace

ir::SceneKind scene_kind_for(BlockKind k) {
  switch (k) {
    case BlockKind::Camera: return ir::SceneKind::Camera;
    case BlockKind::Light: return ir::SceneKind::Light;
    case BlockKind::Window: return ir::SceneKind::Window;
    case BlockKind::Viewport: return ir::SceneKind::Viewport;
    case BlockKind::Render: return ir::SceneKind::Render;
    default: return ir::SceneKind::DisplayColor;
  }
}

ir::NodeId handle_scene(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  if (is_display_color(s.kind)) return handle_display_color(c, a, s, ctx);
  if (s.kind == BlockKind::Lookat) return handle_lookat(c, a, s, ctx);
  if (s.kind == BlockKind::Render) return handle_render(c, a, s, ctx);
  return handle_view_definition(c, a, s, ctx);
}

void resolve_render_paths(Context& c) {
  ir::Module& m = c.module();
  for (ir::NodeId id : c.renders) {
    ir::ScenePath camera = m.get<ir::SceneData>(id).camera_path;
    resolve_path(c, camera, ir::SceneKind::Camera);
    std::vector<ir::RenderLight> lights = m.get<ir::SceneData>(id).lights;
    for (ir::RenderLight& l : lights) resolve_path(c, l.path, ir::SceneKind::Light);
    // What the render shows depends on the nodes along its paths.
    auto depend = [&](const ir::ScenePath& p) {
      for (ir::NodeId i : p.instances) m.deps.add_edge(i, id);
      if (p.node.is_valid()) m.deps.add_edge(p.node, id);
    };
    depend(camera);
    for (const ir::RenderLight& l : lights) depend(l.path);
    ir::SceneData& d = m.get<ir::SceneData>(id);
    d.camera_path = std::move(camera);
    d.lights = std::move(lights);
  }
}

}  // namespace nomec::check
