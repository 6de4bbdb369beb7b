// Operand values, transforms and colours for the evaluator (see context.h). Every value is
// memoized with the parameters it reads.
#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include "backend/eval/context.h"

namespace nomec::backend::eval {

Context::Context(const ir::Module& module, bool incremental) : m(module), is_incremental(incremental) {
  placer.assign(m.nodes.size(), ir::NodeId::None());
  for (size_t i = 0; i < m.nodes.size(); ++i) {
    const ir::Node& n = m.nodes[i];
    if (n.kind == ir::NodeKind::Instance) {
      ir::NodeId t = n.as<ir::InstanceData>().target;
      if (t.is_valid() && !placer[t.index].is_valid()) placer[t.index] = ir::NodeId(static_cast<int32_t>(i));
    } else if (n.kind == ir::NodeKind::Delete) {
      for (const ir::DeletedFace& f : m.refs(n.as<ir::DeleteData>().faces)) {
        if (!f.instances.empty()) deletes.push_back(&f);
      }
    }
  }
}

std::string short_name(std::string_view qualified) {
  size_t dot = qualified.rfind('.');
  return std::string(dot == std::string_view::npos ? qualified : qualified.substr(dot + 1));
}

double scalar(Context& c, ir::OperandId o, size_t i, double fallback) {
  if (!o.is_valid()) return fallback;
  const ir::Operand& op = c.m.operand(o);
  if (i >= op.exprs.size) return fallback;
  const ir::ExprId e = c.m.refs(op.exprs)[i];
  auto memo = c.cache.exprs.find(e.index);
  if (memo == c.cache.exprs.end()) {
    memo = c.cache.exprs.emplace(e.index, Memo<ir::EvalResult>{ir::evaluate(c.m, e), Deps{c.cache.params_of(c.m, e), false}}).first;
    if (op.value_node.is_valid()) c.counters.nodes.insert(op.value_node.index);
  }
  c.cache.recorder.note(memo->second.deps);
  const ir::EvalResult& r = memo->second.value;
  if (!r.ok) {
    // An empty problem means an expression the checker could not type (it reported why,
    // e.g. a value only Tcl code defines); the geometry cannot be built without it.
    c.diags().emit(DiagKind::GeometryFailed, r.where.is_valid() ? r.where : op.range,
                   r.problem.empty() ? fmt::format("cannot evaluate `{}`: the value is not known to nomec (see the front "
                                                   "end's diagnostics for it), so the geometry cannot be built",
                                                   op.name)
                                     : fmt::format("cannot evaluate `{}`: {}", op.name, r.problem));
    return fallback;
  }
  return r.value;
}

glm::dvec3 vec3(Context& c, ir::OperandId o, double fallback) {
  return {scalar(c, o, 0, fallback), scalar(c, o, 1, fallback), scalar(c, o, 2, fallback)};
}

namespace {

// SLIDE's `lookat eye (…) target (…) up (…) endlookat`: the origin moves to the eye, −z turns
// towards the target and +y towards up (the inverse of a viewing matrix). With the eye on
// the target only the move remains; an up along the line of sight is replaced by another axis.
glm::dmat4 look_at(Context& c, const ir::TransformOp& op) {
  const glm::dvec3 eye = op.args.is_valid() ? vec3(c, op.args) : glm::dvec3(0.0);
  const glm::dvec3 target = op.target.is_valid() ? vec3(c, op.target) : glm::dvec3(0.0, 0.0, -1.0);
  const glm::dvec3 up = op.up.is_valid() ? vec3(c, op.up) : glm::dvec3(0.0, 1.0, 0.0);
  glm::dmat4 m = glm::translate(glm::dmat4(1.0), eye);
  if (glm::length(target - eye) == 0) return m;
  const glm::dvec3 f = glm::normalize(target - eye);
  glm::dvec3 r = glm::cross(f, up);
  if (glm::length(r) < 1e-12) r = glm::cross(f, std::abs(f.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0));
  r = glm::normalize(r);
  const glm::dvec3 u = glm::cross(r, f);
  m[0] = glm::dvec4(r, 0.0);
  m[1] = glm::dvec4(u, 0.0);
  m[2] = glm::dvec4(-f, 0.0);
  return m;
}

}  // namespace

glm::dmat4 local(Context& c, std::span<const ir::TransformOp> ops) {
  glm::dmat4 t(1.0);
  for (const ir::TransformOp& op : ops) {
    glm::dmat4 step(1.0);
    switch (op.kind) {
      case ir::TransformKind::Translate:
        step = glm::translate(glm::dmat4(1.0), vec3(c, op.args));
        break;
      case ir::TransformKind::Scale:
        step = glm::scale(glm::dmat4(1.0), vec3(c, op.args, 1));
        break;
      case ir::TransformKind::Rotate: {
        glm::dvec3 axis = vec3(c, op.args);
        double deg = scalar(c, op.args, 3, 0);
        if (glm::length(axis) > 0) step = glm::rotate(glm::dmat4(1.0), glm::radians(deg), glm::normalize(axis));
        break;
      }
      case ir::TransformKind::Mirror: {
        glm::dvec3 n = vec3(c, op.args);
        double d = scalar(c, op.args, 3, 0);
        double len = glm::length(n);
        if (len > 0) {
          n /= len;
          d /= len;
          // x' = x - 2 (n·x - d) n
          glm::dmat3 l = glm::dmat3(1.0) - 2.0 * glm::outerProduct(n, n);
          step = glm::dmat4(l);
          step[3] = glm::dvec4(2.0 * d * n, 1.0);
        }
        break;
      }
      case ir::TransformKind::LookAt:
        step = look_at(c, op);
        break;
    }
    t = step * t;
  }
  return t;
}

glm::dmat4 world_of(Context& c, ir::NodeId inst, int depth) {
  if (auto it = c.cache.world.find(inst.index); it != c.cache.world.end()) {
    c.cache.recorder.note(it->second.deps);
    return it->second.value;
  }
  c.cache.recorder.open();
  const ir::Node& n = c.m.node(inst);
  glm::dmat4 parent(1.0);
  if (n.parent.is_valid() && depth < 64) {
    const ir::Node& p = c.m.node(n.parent);
    // The first instance that places the enclosing group or block.
    if ((p.kind == ir::NodeKind::Group || ir::is_block(p.kind)) && c.placer[n.parent.index].is_valid()) {
      parent = world_of(c, c.placer[n.parent.index], depth + 1);
    }
  }
  glm::dmat4 w = parent * local(c, c.m.refs(n.as<ir::InstanceData>().transforms));
  Deps d = c.cache.recorder.close();
  c.cache.world.emplace(inst.index, Memo<glm::dmat4>{w, std::move(d)});
  return w;
}

std::optional<glm::vec3> surface_color(Context& c, ir::NodeId surface) {
  if (!surface.is_valid() || c.m.node(surface).kind != ir::NodeKind::Surface) return std::nullopt;
  const ir::OperandId color = c.m.get<ir::SurfaceData>(surface).color;
  if (!color.is_valid()) return std::nullopt;
  return glm::vec3(glm::clamp(vec3(c, color), 0.0, 1.0));
}

}  // namespace nomec::backend::eval
