// The readable IR dump (`nomec --emit ir`, the IR golden tests) and the dependency graph as
// DOT (`--emit deps`). One node per line, `%index = keyword name`, then its payload: its
// operands in written order, then what the checker resolved (references, vertices, rules).
#include <cmath>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "ir/ir.h"

namespace nomec::ir {

namespace {

int precedence(const Expr& e) {
  switch (e.kind) {
    case ExprKind::Binary:
      return e.op == '+' || e.op == '-' ? 1 : e.op == '^' ? 4 : 2;
    case ExprKind::Unary:
      return 3;
    default:
      return 5;
  }
}

std::string node_ref(const Module& m, NodeId id) {
  if (!id.is_valid()) return "<none>";
  const Node& n = m.node(id);
  return n.name.empty() ? fmt::format("%{}", id.index) : fmt::format("%{} `{}`", id.index, n.name);
}

bool depends_on_input(const Module& m, ExprId id) {
  // Iterative: expressions may be deep.
  std::vector<ExprId> todo{id};
  while (!todo.empty()) {
    const Expr& e = m.expr(todo.back());
    todo.pop_back();
    if (e.kind == ExprKind::Param || e.kind == ExprKind::Builtin || e.kind == ExprKind::Variable ||
        e.kind == ExprKind::External) {
      return true;
    }
    for (ExprId c : m.subexprs(e)) todo.push_back(c);
  }
  return false;
}

// An expression with its current value when it depends on sliders; constants print as
// their value; functions of variables print as written.
std::string value_text(const Module& m, ExprId id) {
  std::string text = expr_text(m, id);
  if (!depends_on_input(m, id)) {
    EvalResult r = evaluate(m, id);
    return r.ok ? fmt::format("{}", r.value) : text;
  }
  EvalResult r = evaluate(m, id);
  return r.ok ? fmt::format("{{{} = {}}}", text, r.value) : fmt::format("{{{}}}", text);
}

std::string operand_text(const Module& m, const Operand& o) {
  std::vector<std::string> parts;
  for (ExprId e : m.refs(o.exprs)) parts.push_back(value_text(m, e));
  if (o.name == "rotate" && parts.size() == 4) {  // axis, then angle in degrees
    return fmt::format("({} {} {}) ({})", parts[0], parts[1], parts[2], parts[3]);
  }
  return parts.size() == 1 ? parts[0] : fmt::format("({})", fmt::join(parts, " "));
}

std::string vertices_text(const Module& m, Slice<VertexRef> s) {
  std::vector<std::string> parts;
  for (const VertexRef& v : m.refs(s)) {
    if (v.point.is_valid()) {
      parts.push_back(fmt::format("%{}", v.point.index));
    } else if (v.instances.empty()) {
      parts.push_back(fmt::format("<{}>", v.text));
    } else {
      std::vector<std::string> chain;
      for (NodeId i : v.instances) chain.push_back(fmt::format("%{}", i.index));
      parts.push_back(fmt::format("{}.{}", fmt::join(chain, "."), v.vertex));
    }
  }
  return fmt::format("({})", fmt::join(parts, " "));
}

std::string nodes_text(const Module& m, Slice<NodeId> s) {
  std::vector<std::string> parts;
  for (NodeId n : m.refs(s)) parts.push_back(node_ref(m, n));
  return fmt::format("({})", fmt::join(parts, " "));
}

// The lines under a node: its operands, then its resolved payload.
class NodeLines {
 public:
  NodeLines(const Module& m, std::string& out) : m_(m), out_(out) {}

  void line(std::string_view name, const std::string& text = {}) {
    out_ += fmt::format("    {}{}{}\n", name, text.empty() ? "" : " ", text);
  }
  void ref(std::string_view name, NodeId id) {
    if (id.is_valid()) line(name, node_ref(m_, id));
  }
  void flag(std::string_view name, const FlagArg& f) {
    if (!f.is_present) return;
    line(name, f.value.is_valid() ? operand_text(m_, m_.operand(f.value)) : std::string());
  }
  // Operands in written order, except those `skip` prints its own way.
  void operands(const Node& n) {
    for (OperandId o : m_.operands_of(n)) line(m_.operand(o).name, operand_text(m_, m_.operand(o)));
  }

  void payload(NodeId id, const Node& n) {
    switch (n.kind) {
      case NodeKind::Param:
      case NodeKind::Value:
        return;
      case NodeKind::Surface:
      case NodeKind::Point:
      case NodeKind::Merge:
      case NodeKind::Sierpinski:
      case NodeKind::Menger:
      case NodeKind::FaceReversal:
      case NodeKind::Transform:
        operands(n);
        return;
      case NodeKind::SceneSetup:
        if (n.as<SceneData>().kind == SceneKind::DisplayColor) return;
        for (const auto& [name, text] : scene_fields(m_, n, true)) line(name, text);
        return;
      case NodeKind::ControlPoint: {
        const auto& cp = n.as<ControlPointData>();
        ref("point", cp.point);
        operands(n);
        ref("crosssection", cp.cross_section);
        if (cp.reverse) line("reverse");
        return;
      }
      case NodeKind::SceneColor:
        line("kind", std::string(scene_color_name(n.as<SceneColorData>().kind)));
        operands(n);
        return;
      case NodeKind::Backface:
        operands(n);
        return;
      case NodeKind::SweepMorph: {
        const auto& d = n.as<SweepMorphData>();
        if (d.begin_cap) line("begincap");
        if (d.end_cap) line("endcap");
        if (d.reverse) line("reverse");
        return;
      }
      case NodeKind::MorphVisualizer:
        ref("sweep", n.as<MorphVisualizerData>().sweep);
        operands(n);
        return;
      case NodeKind::Polyline: {
        const auto& p = n.as<PolylineData>();
        if (!p.points.empty()) line("points", vertices_text(m_, p.points));
        if (!p.point_list.empty()) line("pointlist", nodes_text(m_, p.point_list));
        flag("closed", p.closed);
        return;
      }
      case NodeKind::Face: {
        const auto& f = n.as<FaceData>();
        line("vertices", vertices_text(m_, f.vertices));
        ref("surface", f.surface);
        ref("backface", f.backface);
        return;
      }
      case NodeKind::Mesh: {
        const auto& d = n.as<MeshData>();
        if (!d.faces.empty()) line("faces", nodes_text(m_, d.faces));
        ref("surface", d.surface);
        return;
      }
      case NodeKind::FlatMesh: {
        const auto& d = n.as<FlatMeshData>();
        line("format", std::string(flat_format_name(d.format)));
        if (d.geometry != nullptr) {
          line("vertices", std::to_string(d.geometry->positions.size()));
          line("faces", std::to_string(d.geometry->face_count()));
        }
        return;
      }
      case NodeKind::Generator:
        generator(n.as<GeneratorData>());
        return;
      case NodeKind::Sweep:
        operands(n);
        if (n.as<SweepData>().mintorsion) line("mintorsion");
        return;
      case NodeKind::SweepPath: {
        const auto& p = n.as<SweepPathData>();
        ref("curve", p.curve);
        operands(n);
        if (p.mintorsion) line("mintorsion");
        if (p.cut_begin) line("cutbegin");
        if (p.cut_end) line("cutend");
        return;
      }
      case NodeKind::CrossSection: {
        const auto& c = n.as<CrossSectionData>();
        ref("curve", c.curve);
        if (c.is_circle) line("circle");
        operands(n);
        flag("begincap", c.begin_cap);
        flag("endcap", c.end_cap);
        if (c.reverse) line("reverse");
        return;
      }
      case NodeKind::Group:
        operands(n);
        ref("surface", n.as<GroupData>().surface);
        return;
      case NodeKind::Instance:
        operands(n);
        ref("surface", n.as<InstanceData>().surface);
        ref("backface", n.as<InstanceData>().backface);
        return;
      case NodeKind::Subdivision:
        line("rule", std::string(subdivision_rule_name(n.as<SubdivisionData>().rule)));
        operands(n);
        return;
      case NodeKind::Offset:
        line("kind", std::string(offset_kind_name(n.as<OffsetData>().kind)));
        operands(n);
        return;
      case NodeKind::Handle: {
        const auto& h = n.as<HandleData>();
        for (const DeletedFace& f : m_.refs(h.faces)) line("face", deleted_text(f));
        if (!h.corners.empty()) line("corners", vertices_text(m_, h.corners));
        operands(n);
        return;
      }
      case NodeKind::Rind: {
        const auto& r = n.as<RindData>();
        operands(n);
        for (const DeletedFace& f : m_.refs(r.punch)) line("punch", deleted_text(f));
        for (const DeletedFace& f : m_.refs(r.peel)) line("peel", deleted_text(f));
        return;
      }
      case NodeKind::Delete:
        for (const DeletedFace& f : m_.refs(n.as<DeleteData>().faces)) line("face", deleted_text(f));
        return;
      case NodeKind::Sharp:
        operands(n);
        for (const Slice<VertexRef>& chain : m_.refs(n.as<SharpData>().chains)) line("edges", vertices_text(m_, chain));
        return;
      case NodeKind::Zipper: {
        const auto& z = n.as<ZipperData>();
        for (int32_t k = 0; k < std::min<int32_t>(z.border_count, 2); ++k) line("border", vertices_text(m_, z.borders[k]));
        operands(n);
        return;
      }
    }
    (void)id;
  }

 private:
  void generator(const GeneratorData& g) {
    const GeneratorInfo& info = ir::generator(g.gen);
    for (const GenArgBinding& b : m_.refs(g.args)) {
      std::string_view name = b.value.is_valid() ? m_.operand(b.value).name : info.display_name(b.arg, m_.dialect);
      if (b.value.is_valid()) {
        const std::string text = operand_text(m_, m_.operand(b.value));
        line(name, b.is_truncated ? text + " (truncated)" : text);
      } else if (b.ref.is_valid()) {
        line(name, node_ref(m_, b.ref));
      } else if (!b.refs.empty()) {
        line(name, nodes_text(m_, b.refs));
      } else {
        line(name);
      }
    }
  }

  std::string deleted_text(const DeletedFace& f) {
    std::vector<std::string> chain;
    for (NodeId i : f.instances) chain.push_back(fmt::format("%{}", i.index));
    std::string which = f.face.is_valid() ? fmt::format("%{}", f.face.index) : fmt::format("#{}", f.index);
    return fmt::format("{} = {}.{}", f.text, fmt::join(chain, "."), which);
  }

  const Module& m_;
  std::string& out_;
};

// `values` written as a list, or the default marked as such.
template <size_t N>
std::string list_or_default(const Module& m, OperandId o, const std::array<double, N>& fallback) {
  if (o.is_valid()) return operand_text(m, m.operand(o));
  return fmt::format("({}) (default)", fmt::join(fallback, " "));
}

// An enumerated field: its symbol, its Tcl value with the name it reads as, or the default.
template <typename E, typename Name>
std::string enum_text(const Module& m, const SceneEnum<E>& e, E fallback, Name name) {
  if (!e.is_written) return fmt::format("{} (default)", name(fallback));
  if (!e.value.is_valid()) return std::string(name(e.symbol));
  const Operand& op = m.operand(e.value);
  const EvalResult r = op.exprs.empty() ? EvalResult{0, false, {}, {}} : evaluate(m, m.refs(op.exprs)[0]);
  return r.ok ? fmt::format("{} ({})", operand_text(m, op), name(static_cast<E>(std::lround(r.value))))
              : operand_text(m, op);
}

std::string on_off(const Module& m, const SceneEnum<bool>& e) {
  return enum_text(m, e, true, [](bool on) { return on ? std::string_view("on") : std::string_view("off"); });
}

std::string frustum_text(const Module& m, const SceneData& d) {
  if (!d.frustum.is_valid()) {
    return fmt::format("({} {} {}) ({} {} {}) (default)", kDefaultFrustum[0], kDefaultFrustum[1], kDefaultFrustum[2],
                       kDefaultFrustum[3], kDefaultFrustum[4], kDefaultFrustum[5]);
  }
  const Operand& op = m.operand(d.frustum);
  std::vector<std::string> v;
  for (ExprId e : m.refs(op.exprs)) v.push_back(value_text(m, e));
  if (v.size() != 6) return operand_text(m, op);
  if (d.frustum_is_lrbtnf) return fmt::format("({}) (left right bottom top near far)", fmt::join(v, " "));
  return fmt::format("({} {} {}) ({} {} {})", v[0], v[1], v[2], v[3], v[4], v[5]);
}

std::string path_text(const Module& m, const ScenePath& p, bool with_ids) {
  if (!with_ids) return p.text;
  if (!p.node.is_valid()) return fmt::format("{} <unresolved>", p.text);
  std::vector<std::string> chain;
  if (p.root.is_valid()) chain.push_back(fmt::format("%{}", p.root.index));
  for (NodeId i : p.instances) chain.push_back(fmt::format("%{}", i.index));
  chain.push_back(fmt::format("%{}", p.node.index));
  return fmt::format("{} = {}", p.text, fmt::join(chain, "."));
}

}  // namespace

std::vector<std::pair<std::string, std::string>> scene_fields(const Module& m, const Node& n, bool with_ids) {
  std::vector<std::pair<std::string, std::string>> out;
  if (n.kind != NodeKind::SceneSetup) return out;
  const SceneData& d = n.as<SceneData>();
  auto ref = [&](NodeId id) {
    if (!id.is_valid()) return std::string("<none>");
    return with_ids ? node_ref(m, id) : fmt::format("`{}`", m.node(id).name);
  };
  switch (d.kind) {
    case SceneKind::Camera:
      out.emplace_back("projection", enum_text(m, d.projection, Projection::Parallel, projection_name));
      out.emplace_back("frustum", frustum_text(m, d));
      break;
    case SceneKind::Light:
      out.emplace_back("type", enum_text(m, d.light_type, kDefaultLightType, light_type_name));
      out.emplace_back("color", list_or_default(m, d.color, kDefaultLightColor));
      if (d.direction.is_valid()) out.emplace_back("direction", operand_text(m, m.operand(d.direction)));
      break;
    case SceneKind::Window:
      out.emplace_back("background", list_or_default(m, d.background, kDefaultBackground));
      out.emplace_back("origin", list_or_default(m, d.origin, kDefaultWindowOrigin));
      out.emplace_back("size", list_or_default(m, d.size, kDefaultWindowSize));
      out.emplace_back("resize", on_off(m, d.resize));
      out.emplace_back("ratio", on_off(m, d.ratio));
      break;
    case SceneKind::Viewport:
      if (d.window.is_valid()) out.emplace_back("window", ref(d.window));
      if (d.camera.is_valid()) out.emplace_back("cameraID", ref(d.camera));
      out.emplace_back("origin", list_or_default(m, d.origin, kDefaultViewportOrigin));
      out.emplace_back("size", list_or_default(m, d.size, kDefaultViewportSize));
      break;
    case SceneKind::Render:
      out.emplace_back("viewport", ref(d.viewport));
      out.emplace_back("camera", path_text(m, d.camera_path, with_ids));
      out.emplace_back("root", ref(d.root));
      for (const RenderLight& l : d.lights) {
        out.emplace_back("light", fmt::format("{} {}", path_text(m, l.path, with_ids), on_off(m, l.on)));
      }
      break;
    case SceneKind::DisplayColor:
      break;
  }
  return out;
}

std::string expr_text(const Module& m, ExprId id) {
  const Expr& e = m.expr(id);
  auto sub = [&](ExprId c, int min_prec) {
    std::string s = expr_text(m, c);
    return precedence(m.expr(c)) < min_prec ? "(" + s + ")" : s;
  };
  switch (e.kind) {
    case ExprKind::Const:
      return fmt::format("{}", e.value);
    case ExprKind::Param:
      return "$" + m.node(e.param).name;
    case ExprKind::Builtin:
      return "$" + std::string(e.name);
    case ExprKind::Variable:
      return std::string(e.name);
    case ExprKind::External: {
      std::string script = m.external ? std::string(m.external->text(m.external_script(e).script)) : std::string("?");
      std::vector<std::string> reads;
      for (ExprId a : m.subexprs(e)) reads.push_back(expr_text(m, a));
      return fmt::format("tcl{{{}}}({})", script, fmt::join(reads, ", "));
    }
    case ExprKind::Error:
      return "<error>";
    case ExprKind::Unary:
      return std::string(1, e.op) + sub(e.lhs(), 3);
    case ExprKind::Binary: {
      int p = precedence(e);
      std::string op = e.op == 'i' ? "//" : std::string(1, e.op);
      if (e.op == '^') return sub(e.lhs(), 5) + " ^ " + sub(e.rhs(), 3);
      return sub(e.lhs(), p) + " " + op + " " + sub(e.rhs(), p + 1);
    }
    case ExprKind::Call: {
      std::vector<std::string> args;
      for (ExprId a : m.refs(e.args)) args.push_back(expr_text(m, a));
      return fmt::format("{}({})", func_name(e.func), fmt::join(args, ", "));
    }
  }
  return "?";
}

std::string dump_ir(const Module& m, const SourceManager& sources) {
  std::string out = fmt::format("module dialect={} nodes={} exprs={} edges={}\n", dialect_name(m.dialect),
                                m.nodes.size(), m.exprs.size(), m.deps.edge_count());
  NodeLines lines(m, out);
  for (size_t i = 0; i < m.nodes.size(); ++i) {
    const Node& n = m.nodes[i];
    if (n.kind == NodeKind::Value) continue;  // shown through their operands
    std::string loc;
    if (n.range.is_valid()) {
      LineCol lc = sources.line_col(n.range.file, n.range.begin);
      loc = fmt::format("  # {}:{}", lc.line, lc.column);
    }
    if (n.kind == NodeKind::Param) {
      const ParamData& p = n.as<ParamData>();
      out += fmt::format("%{} = param `{}` {} in [{}, {}] step {}{}\n", i, n.name, p.value, p.min, p.max, p.step, loc);
      continue;
    }
    out += fmt::format("%{} = {} {}", i, n.keyword, n.name.empty() ? std::string("<anonymous>") : "`" + n.name + "`");
    if (n.parent.is_valid()) out += fmt::format(" in %{}", n.parent.index);
    if (n.kind == NodeKind::Instance) {
      const InstanceData& inst = n.as<InstanceData>();
      if (inst.target.is_valid()) out += " -> " + node_ref(m, inst.target);
      if (inst.is_hidden) out += " hidden";
      if (inst.is_reversed) out += " reversed";
    }
    out += loc + "\n";
    lines.payload(NodeId(static_cast<int32_t>(i)), n);
  }
  std::vector<std::string> scene;
  for (NodeId s : m.scene) scene.push_back(fmt::format("%{}", s.index));
  out += fmt::format("scene ({})\n", fmt::join(scene, " "));
  return out;
}

std::string dump_deps_dot(const Module& m) {
  std::string out = "digraph deps {\n  rankdir=LR;\n";
  for (size_t i = 0; i < m.nodes.size(); ++i) {
    const Node& n = m.nodes[i];
    std::string label = n.kind == NodeKind::Value ? fmt::format("value {}", n.name)
                                                  : fmt::format("{} {}", n.kind == NodeKind::Param ? "param" : n.keyword, n.name);
    const char* shape = n.kind == NodeKind::Param      ? "ellipse"
                        : n.kind == NodeKind::Value    ? "plaintext"
                        : n.kind == NodeKind::Instance ? "box"
                                                       : "component";
    out += fmt::format("  n{} [label=\"{}\", shape={}];\n", i, label, shape);
  }
  for (size_t i = 0; i < m.nodes.size(); ++i) {
    for (NodeId to : m.deps.users(NodeId(static_cast<int32_t>(i)))) out += fmt::format("  n{} -> n{};\n", i, to.index);
  }
  out += "}\n";
  return out;
}

}  // namespace nomec::ir
