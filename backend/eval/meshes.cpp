// Meshes and vertex positions for the evaluator (see context.h): the faces of a mesh or
// object in its local frame (vertices shared by reference), its creases, and the position of
// a vertex reference — a point, a generated vertex, or a vertex through instances — and the
// soup of a flat mesh file.
#include <fmt/format.h>
#include <array>
#include <map>
#include <unordered_set>

#include "backend/eval/context.h"

namespace nomec::backend::eval {

namespace {

// The position of the first vertex in `refs` that `ref` names (by its text or by the name
// of the point it resolves to), resolving it in turn; recursion is bounded by ref_depth.
std::optional<glm::dvec3> position_among(Context& c, std::span<const ir::VertexRef> refs, const ir::VertexRef& ref,
                                         std::string_view inst_path) {
  for (const ir::VertexRef& r : refs) {
    // 2016/NOME2 meshes keep the names of the vertices they copy, with or without the
    // leading `.` NOME2 wrote (`.c.bc3`, `c.bc3`).
    auto bare = [](std::string_view t) { return t.starts_with('.') ? t.substr(1) : t; };
    bool named = bare(r.text) == bare(ref.vertex) ||
                 (r.point.is_valid() && short_name(c.m.node(r.point).name) == ref.vertex);
    if (named && &r != &ref && c.ref_depth < 16) {
      ++c.ref_depth;
      std::optional<glm::dvec3> p = ref_position(c, r, inst_path);
      --c.ref_depth;
      if (p) return p;
    }
  }
  return std::nullopt;
}

// The position of vertex `vertex` of mesh `target` in the mesh's frame: its own point, or a
// vertex one of its faces uses (a global point, or a vertex of another instance).
std::optional<glm::dvec3> mesh_vertex(Context& c, ir::NodeId target, const ir::VertexRef& ref, std::string_view inst_path) {
  std::optional<glm::dvec3> p;
  const ir::Node& tn = c.m.node(target);
  for (ir::NodeId k : c.m.children(tn)) {
    const ir::Node& kn = c.m.node(k);
    if (kn.kind == ir::NodeKind::Point && short_name(kn.name) == ref.vertex) {
      const ir::OperandId pos = kn.as<ir::PointData>().position;
      if (pos.is_valid()) p = vec3(c, pos);
    }
  }
  for (ir::NodeId k : c.m.children(tn)) {
    if (p) break;
    if (c.m.node(k).kind != ir::NodeKind::Face) continue;
    p = position_among(c, c.m.refs(c.m.get<ir::FaceData>(k).vertices), ref, inst_path);
  }
  return p;
}

// The faces of a mesh in order: an object's face list, then the mesh's own faces.
std::vector<ir::NodeId> faces_of(const ir::Module& m, ir::NodeId mesh_id) {
  std::vector<ir::NodeId> faces;
  const ir::Node& mn = m.node(mesh_id);
  for (ir::NodeId f : m.refs(mn.as<ir::MeshData>().faces)) {
    if (f.is_valid() && m.node(f).kind == ir::NodeKind::Face) faces.push_back(f);
  }
  for (ir::NodeId k : m.children(mn)) {
    if (m.node(k).kind == ir::NodeKind::Face) faces.push_back(k);
  }
  return faces;
}

// What a vertex reference names, as a key: references with equal keys are one vertex.
std::string vertex_key(const ir::VertexRef& ref) {
  std::string key;
  if (ref.point.is_valid()) {
    key = fmt::format("p{}", ref.point.index);
  } else {
    for (ir::NodeId i : ref.instances) key += fmt::format("i{}.", i.index);
    key += ref.vertex;
  }
  return key;
}

// A mesh's vertices as soup indices: each reference placed once (keyed by what it names).
class VertexIndex {
 public:
  VertexIndex(Context& c, kernel::PolygonSoup& soup, const std::string& path) : c_(c), soup_(soup), path_(path) {}
  std::optional<int32_t> operator()(const ir::VertexRef& ref) {
    std::string key = vertex_key(ref);
    if (auto it = index_.find(key); it != index_.end()) return it->second;
    std::optional<glm::dvec3> p = ref_position(c_, ref, path_);
    if (!p) return std::nullopt;
    int32_t v = soup_.add_vertex(*p, ref.text);
    index_.emplace(key, v);
    return v;
  }

 private:
  Context& c_;
  kernel::PolygonSoup& soup_;
  const std::string& path_;
  std::map<std::string, int32_t> index_;
};

// The creases and corners of the mesh's `sharp` statements.
void add_creases(Context& c, ir::NodeId mesh_id, const std::string& path, kernel::PolygonSoup& soup, VertexIndex& index) {
  const ir::Node& mn = c.m.node(mesh_id);
  for (ir::NodeId k : c.m.children(mn)) {
    const ir::Node& kn = c.m.node(k);
    if (kn.kind != ir::NodeKind::Sharp) continue;
    const ir::SharpData& sd = kn.as<ir::SharpData>();
    const float s = sd.sharpness.is_valid() ? static_cast<float>(scalar(c, sd.sharpness, 0, 0)) : 0.0f;
    for (const ir::Slice<ir::VertexRef>& chain : c.m.refs(sd.chains)) {
      std::vector<int32_t> vs;
      std::vector<const ir::VertexRef*> refs;
      for (const ir::VertexRef& r : c.m.refs(chain)) {
        if (auto v = index(r)) {
          vs.push_back(*v);
          refs.push_back(&r);
        }
      }
      if (vs.size() == 1) soup.corners.push_back({vs[0], s});
      for (size_t i = 0; i + 1 < vs.size(); ++i) {
        if (!is_soup_edge(soup, vs[i], vs[i + 1])) {
          SourceRange r = refs[i]->range;
          r.end = refs[i + 1]->range.end;
          c.diags().emit(DiagKind::GeometryFailed, r,
                         fmt::format("`{}` and `{}` are not joined by an edge of mesh `{}`; `sharp` marks edges between "
                                     "consecutive vertices of a face (instance `{}`)",
                                     refs[i]->text, refs[i + 1]->text, short_name(mn.name), path));
          continue;
        }
        soup.creases.push_back({vs[i], vs[i + 1], s});
      }
    }
  }
}

}  // namespace

std::optional<glm::dvec3> point_position(Context& c, ir::NodeId point) {
  const ir::Node* pn = &c.m.node(point);
  if (pn->kind == ir::NodeKind::ControlPoint) {
    const ir::NodeId p = pn->as<ir::ControlPointData>().point;
    if (!p.is_valid()) return std::nullopt;
    pn = &c.m.node(p);
  }
  if (pn->kind != ir::NodeKind::Point || !pn->as<ir::PointData>().position.is_valid()) return std::nullopt;
  return vec3(c, pn->as<ir::PointData>().position);
}

std::optional<glm::dvec3> ref_position(Context& c, const ir::VertexRef& ref, std::string_view inst_path) {
  if (ref.point.is_valid()) return point_position(c, ref.point);
  if (ref.instances.empty() || !ref.instances[0].is_valid()) return std::nullopt;
  glm::dmat4 t = world_of(c, ref.instances[0]);
  for (size_t i = 1; i < ref.instances.size(); ++i) {
    if (!ref.instances[i].is_valid()) return std::nullopt;
    t = t * local(c, c.m.refs(c.m.get<ir::InstanceData>(ref.instances[i]).transforms));
  }
  ir::NodeId target = c.m.get<ir::InstanceData>(ref.instances.back()).target;
  if (!target.is_valid()) return std::nullopt;
  const ir::Node& tn = c.m.node(target);
  std::optional<glm::dvec3> p;
  switch (tn.kind) {
    case ir::NodeKind::Generator: {
      const Generated* g = generated(c, target, inst_path);
      if (g == nullptr) return std::nullopt;  // the generator's error was reported
      // NOME3 aliases (`fun.v1_3`) name the same vertices as the 2016 names (`hc3`).
      const std::string wanted = ir::canonical_vertex_name(tn.as<ir::GeneratorData>().gen, ref.vertex);
      for (size_t v = 0; v < g->soup.names.size(); ++v) {
        if (g->soup.names[v] == wanted) {
          p = g->soup.positions[v];
          break;
        }
      }
      for (size_t v = 0; !p && v < g->aliases.size(); ++v) {
        if (g->aliases[v].first == wanted) p = g->aliases[v].second;
      }
      break;
    }
    case ir::NodeKind::Sweep:
    case ir::NodeKind::SweepMorph:
      if (std::optional<kernel::PolygonSoup> sw = sweep(c, target, inst_path)) {
        if (const int32_t v = sweep_vertex(c, target, inst_path, *sw, ref.vertex); v >= 0) p = sw->positions[v];
      }
      break;
    case ir::NodeKind::MorphVisualizer:
      if (std::optional<Generated> g = morph_visualizer(c, target, inst_path)) {
        for (size_t v = 0; v < g->soup.names.size(); ++v) {
          if (g->soup.names[v] == ref.vertex) p = g->soup.positions[v];
        }
      }
      break;
    case ir::NodeKind::Polyline:
      // A vertex of a polyline instance (`_l1_v4`): one of the points it lists.
      p = position_among(c, c.m.refs(tn.as<ir::PolylineData>().points), ref, inst_path);
      break;
    case ir::NodeKind::Mesh:
      p = mesh_vertex(c, target, ref, inst_path);
      break;
    case ir::NodeKind::FlatMesh: {
      const ir::FlatMeshData& fd = tn.as<ir::FlatMeshData>();
      if (const int32_t k = fd.vertex_index(ref.vertex); k >= 0) {
        const std::array<double, 3>& q = fd.geometry->positions[static_cast<size_t>(k)];
        p = glm::dvec3(q[0], q[1], q[2]);
      }
      break;
    }
    default:
      break;
  }
  if (!p) {
    c.diags().emit(DiagKind::GeometryFailed, ref.range,
                   fmt::format("`{}` names no vertex of the geometry of `{}`; it has no vertex `{}`", ref.text,
                               short_name(tn.name), ref.vertex));
    return std::nullopt;
  }
  return glm::dvec3(t * glm::dvec4(*p, 1.0));
}

kernel::PolygonSoup flat_soup(const ir::FlatMeshData& flat) {
  kernel::PolygonSoup soup;
  if (flat.geometry == nullptr) return soup;
  const ir::FlatGeometry& g = *flat.geometry;
  soup.positions.reserve(g.positions.size());
  soup.names.reserve(g.positions.size());
  for (size_t k = 0; k < g.positions.size(); ++k) {
    soup.add_vertex({g.positions[k][0], g.positions[k][1], g.positions[k][2]}, fmt::format("v{}", k));
  }
  for (int32_t f = 0; f < g.face_count(); ++f) {
    const auto b = g.face_starts[static_cast<size_t>(f)];
    const auto e = g.face_starts[static_cast<size_t>(f) + 1];
    soup.add_face(std::span<const int32_t>(g.corners.data() + b, static_cast<size_t>(e - b)));
  }
  return soup;
}

int64_t mesh_vertex_count(Context& c, ir::NodeId mesh_id) {
  if (auto it = c.mesh_vertex_counts.find(mesh_id.index); it != c.mesh_vertex_counts.end()) return it->second;
  std::unordered_set<std::string> keys;
  for (ir::NodeId fid : faces_of(c.m, mesh_id)) {
    std::span<const ir::VertexRef> vertices = c.m.refs(c.m.node(fid).as<ir::FaceData>().vertices);
    if (vertices.size() < 3) continue;  // not placed (see `mesh`)
    for (const ir::VertexRef& r : vertices) keys.insert(vertex_key(r));
  }
  const auto n = static_cast<int64_t>(keys.size());
  c.mesh_vertex_counts.emplace(mesh_id.index, n);
  return n;
}

void mesh(Context& c, ir::NodeId mesh_id, const Placing& at, Collected& out) {
  Collected local_c;
  kernel::PolygonSoup& soup = local_c.soup;
  VertexIndex index(c, soup, at.path);
  for (ir::NodeId fid : faces_of(c.m, mesh_id)) {
    const ir::Node& fn = c.m.node(fid);
    std::span<const ir::VertexRef> vertices = c.m.refs(fn.as<ir::FaceData>().vertices);
    if (vertices.size() < 3) continue;
    std::vector<int32_t> face;
    bool ok = true;
    for (const ir::VertexRef& r : vertices) {
      auto v = index(r);
      if (!v) {
        ok = false;
        break;
      }
      face.push_back(*v);
    }
    if (!ok) continue;
    soup.add_face(face);
    soup.face_sources.push_back({fid.index, at.inst.index});
    std::optional<glm::vec3> fc = surface_color(c, fn.as<ir::FaceData>().surface);
    soup.face_colors.push_back(fc.value_or(at.color.value_or(kDefaultColor)));
    local_c.has_color.push_back(fc || at.color ? 1 : 0);
  }
  add_creases(c, mesh_id, at.path, soup, index);
  // Into `out` with the identity transform: the caller transforms whole collections.
  const int32_t face_base = out.soup.face_count();
  append_soup(out, soup, glm::dmat4(1.0), std::nullopt, true);
  for (int32_t f = 0; f < soup.face_count(); ++f) out.has_color[face_base + f] = local_c.has_color[f];
}

}  // namespace nomec::backend::eval
