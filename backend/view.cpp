// The viewing set-up of a scene (see view.h): the render's camera and lights placed by the
// instance transforms along their paths, composed parent · child as the evaluator places
// geometry, and its window's background.
#include "backend/view.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "backend/eval/context.h"

namespace nomec::backend {

namespace {

using eval::Context;

Vec3 to_vec(const glm::dvec3& v) { return {v.x, v.y, v.z}; }

Vec3 unit(const glm::dvec3& v, const Vec3& fallback) {
  const double len = glm::length(v);
  return len > 0 && std::isfinite(len) ? to_vec(v / len) : fallback;
}

template <size_t N>
std::array<double, N> values_or(Context& c, ir::OperandId o, const std::array<double, N>& fallback) {
  std::array<double, N> out = fallback;
  if (!o.is_valid()) return out;
  for (size_t i = 0; i < N; ++i) out[i] = eval::scalar(c, o, i, fallback[i]);
  return out;
}

Vec3 color_or(Context& c, ir::OperandId o, const Vec3& fallback) {
  Vec3 v = values_or(c, o, fallback);
  for (double& x : v) x = std::isfinite(x) ? std::clamp(x, 0.0, 1.0) : 0.0;
  return v;
}

// An enumerated field's value: its symbol, or its Tcl value read as the enum's number.
template <typename E>
E enum_of(Context& c, const ir::SceneEnum<E>& e, E fallback, int max) {
  if (!e.is_written) return fallback;
  if (!e.value.is_valid()) return e.symbol;
  const double v = eval::scalar(c, e.value, 0, static_cast<double>(fallback));
  if (!std::isfinite(v)) return fallback;
  return static_cast<E>(std::clamp(static_cast<int>(std::lround(v)), 0, max));
}

bool is_scene(const ir::Module& m, ir::NodeId id, ir::SceneKind kind) {
  return id.is_valid() && m.node(id).kind == ir::NodeKind::SceneSetup && m.node(id).as<ir::SceneData>().kind == kind;
}

// The world transform of a path's node: its instances' transforms, outermost first.
glm::dmat4 path_world(Context& c, const ir::ScenePath& p) {
  glm::dmat4 w(1.0);
  for (ir::NodeId inst : p.instances) w = w * eval::local(c, c.m.refs(c.m.get<ir::InstanceData>(inst).transforms));
  return w;
}

ViewCamera camera_at(Context& c, ir::NodeId cam, const glm::dmat4& w) {
  const ir::SceneData& d = c.m.get<ir::SceneData>(cam);
  ViewCamera v;
  v.name = c.m.node(cam).name;
  v.position = to_vec(glm::dvec3(w * glm::dvec4(0, 0, 0, 1)));
  v.direction = unit(glm::dvec3(w * glm::dvec4(0, 0, -1, 0)), v.direction);
  v.up = unit(glm::dvec3(w * glm::dvec4(0, 1, 0, 0)), v.up);
  v.projection = enum_of(c, d.projection, ir::Projection::Parallel, 1);
  if (d.frustum.is_valid()) {
    const std::array<double, 6> f = values_or(c, d.frustum, ir::kDefaultFrustum);
    // NOME3 writes (left right bottom top near far), near and far as distances.
    v.frustum = d.frustum_is_lrbtnf ? std::array<double, 6>{f[0], f[2], -f[5], f[1], f[3], -f[4]} : f;
  }
  return v;
}

ViewLight light_at(Context& c, ir::NodeId light, const glm::dmat4& w, bool on) {
  const ir::SceneData& d = c.m.get<ir::SceneData>(light);
  ViewLight l;
  l.name = c.m.node(light).name;
  l.type = enum_of(c, d.light_type, ir::kDefaultLightType, 3);
  l.color = color_or(c, d.color, ir::kDefaultLightColor);
  l.position = to_vec(glm::dvec3(w * glm::dvec4(0, 0, 0, 1)));
  const glm::dvec3 local = d.direction.is_valid() ? eval::vec3(c, d.direction) : glm::dvec3(0, 0, -1);
  l.direction = unit(glm::dvec3(w * glm::dvec4(local, 0)), l.direction);
  l.on = on;
  return l;
}

bool light_on(Context& c, const ir::SceneEnum<bool>& e) {
  if (!e.is_written) return true;
  if (!e.value.is_valid()) return e.symbol;
  return eval::scalar(c, e.value, 0, 1.0) != 0;
}

// A window's background; the window a viewport shows in.
std::optional<Vec3> window_background(Context& c, ir::NodeId window) {
  if (!is_scene(c.m, window, ir::SceneKind::Window)) return std::nullopt;
  return color_or(c, c.m.get<ir::SceneData>(window).background, ir::kDefaultBackground);
}

void from_render(Context& c, const ir::SceneData& r, SceneView& out) {
  if (is_scene(c.m, r.camera_path.node, ir::SceneKind::Camera)) {
    out.camera = camera_at(c, r.camera_path.node, path_world(c, r.camera_path));
  }
  for (const ir::RenderLight& l : r.lights) {
    if (!is_scene(c.m, l.path.node, ir::SceneKind::Light)) continue;
    out.lights.push_back(light_at(c, l.path.node, path_world(c, l.path), light_on(c, l.on)));
  }
  if (is_scene(c.m, r.viewport, ir::SceneKind::Viewport)) {
    out.background = window_background(c, c.m.get<ir::SceneData>(r.viewport).window);
  }
}

// Without a `render` (NOME3): the first camera instance, every light instance, the first window.
void from_instances(Context& c, SceneView& out) {
  for (size_t i = 0; i < c.m.nodes.size(); ++i) {
    const ir::Node& n = c.m.nodes[i];
    if (n.kind != ir::NodeKind::Instance) continue;
    const ir::NodeId inst(static_cast<int32_t>(i));
    const ir::NodeId target = n.as<ir::InstanceData>().target;
    if (is_scene(c.m, target, ir::SceneKind::Camera) && !out.camera) {
      out.camera = camera_at(c, target, eval::world_of(c, inst));
    } else if (is_scene(c.m, target, ir::SceneKind::Light)) {
      out.lights.push_back(light_at(c, target, eval::world_of(c, inst), true));
    }
  }
  for (size_t i = 0; i < c.m.nodes.size() && !out.background; ++i) {
    out.background = window_background(c, ir::NodeId(static_cast<int32_t>(i)));
  }
}

}  // namespace

SceneView scene_view(const ir::Module& module) {
  SceneView out;
  Context c(module, false);
  // Values the checker could not read were reported there; here they take their defaults.
  DiagnosticEngine quiet;
  c.cache.recorder.begin_pass(quiet);
  const ir::SceneData* render = nullptr;
  std::optional<Vec3> background_color;  // JIPCAD `backgroundcolor`: the last one is in effect
  for (const ir::Node& n : module.nodes) {
    if (n.kind == ir::NodeKind::SceneSetup && n.as<ir::SceneData>().kind == ir::SceneKind::Render && render == nullptr) {
      render = &n.as<ir::SceneData>();
    }
    if (n.kind == ir::NodeKind::SceneColor && n.as<ir::SceneColorData>().kind == ir::SceneColorKind::Background) {
      background_color = color_or(c, n.as<ir::SceneColorData>().color, ir::kDefaultBackground);
    }
  }
  if (render != nullptr) {
    from_render(c, *render, out);
  } else {
    from_instances(c, out);
  }
  if (background_color && !out.background) out.background = background_color;
  return out;
}

}  // namespace nomec::backend
