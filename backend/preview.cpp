// The drawable form of output meshes for live previews (see preview.h).
#include "backend/preview.h"

#include <algorithm>
#include <cmath>

namespace nomec::backend {

namespace {

uint8_t channel(float c) { return static_cast<uint8_t>(std::lround(std::clamp(c, 0.0f, 1.0f) * 255.0f)); }

uint64_t mix(uint64_t h, uint64_t v) {
  h ^= v + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
  return h;
}

}  // namespace

std::vector<float> preview_positions(const OutputMesh& out) {
  const kernel::Mesh& m = out.mesh;
  std::vector<float> p;
  p.reserve(3 * static_cast<size_t>(m.vertex_count()));
  for (const glm::dvec3& v : m.positions()) {
    p.push_back(static_cast<float>(v.x));
    p.push_back(static_cast<float>(v.y));
    p.push_back(static_cast<float>(v.z));
  }
  return p;
}

PreviewGeometry preview_geometry(const OutputMesh& out) {
  const kernel::Mesh& m = out.mesh;
  PreviewGeometry g;
  g.positions = preview_positions(out);
  g.face_count = m.face_count();
  std::vector<uint32_t> ring;
  for (int32_t f = 0; f < m.face_count(); ++f) {
    ring.clear();
    m.for_each_face_use(kernel::FaceId(f), [&](kernel::EdgeUse u) {
      ring.push_back(static_cast<uint32_t>(m.use_tail(u).index));
    });
    for (size_t i = 1; i + 1 < ring.size(); ++i) {  // a fan: NOME faces are mostly convex
      g.triangles.insert(g.triangles.end(), {ring[0], ring[i], ring[i + 1]});
      g.triangle_faces.push_back(static_cast<uint32_t>(f));
    }
  }
  if (m.has_face_colors()) {
    g.face_colors.reserve(3 * static_cast<size_t>(m.face_count()));
    for (int32_t f = 0; f < m.face_count(); ++f) {
      const glm::vec3& c = m.face_color(kernel::FaceId(f));
      g.face_colors.insert(g.face_colors.end(), {channel(c.r), channel(c.g), channel(c.b)});
    }
  }
  g.edges.reserve(2 * static_cast<size_t>(m.edge_count()));
  for (int32_t e = 0; e < m.edge_count(); ++e) {
    const kernel::EdgeId id(e);
    const uint32_t a = static_cast<uint32_t>(m.edge_vertex(id, 0).index);
    const uint32_t b = static_cast<uint32_t>(m.edge_vertex(id, 1).index);
    g.edges.insert(g.edges.end(), {a, b});
    if (m.is_mobius(id)) g.mobius_edges.insert(g.mobius_edges.end(), {a, b});
  }
  for (int32_t loop = 0; loop < static_cast<int32_t>(m.border_loops().size()); ++loop) {
    for (kernel::EdgeId e : m.border_loop_edges(loop)) {
      g.border_edges.push_back(static_cast<uint32_t>(m.edge_vertex(e, 0).index));
      g.border_edges.push_back(static_cast<uint32_t>(m.edge_vertex(e, 1).index));
    }
  }
  for (const Curve& k : out.curves) {
    const uint32_t first = static_cast<uint32_t>(g.curve_points.size() / 3);
    for (const glm::dvec3& p : k.points) {
      g.curve_points.insert(g.curve_points.end(), {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)});
    }
    const uint32_t n = static_cast<uint32_t>(k.points.size());
    for (uint32_t i = 0; i + 1 < n; ++i) g.curve_segments.insert(g.curve_segments.end(), {first + i, first + i + 1});
    if (k.is_closed && n > 2) g.curve_segments.insert(g.curve_segments.end(), {first + n - 1, first});
  }
  return g;
}

uint64_t preview_topology_key(const OutputMesh& out) {
  const kernel::Mesh& m = out.mesh;
  uint64_t h = mix(mix(mix(0, static_cast<uint64_t>(m.vertex_count())), static_cast<uint64_t>(m.edge_count())),
                   static_cast<uint64_t>(m.face_count()));
  for (int32_t f = 0; f < m.face_count(); ++f) {
    m.for_each_face_use(kernel::FaceId(f), [&](kernel::EdgeUse u) {
      h = mix(h, static_cast<uint64_t>(m.use_tail(u).index));
    });
    h = mix(h, 0xffffffffull);
    if (m.has_face_colors()) {
      const glm::vec3& c = m.face_color(kernel::FaceId(f));
      h = mix(h, (uint64_t{channel(c.r)} << 16) | (uint64_t{channel(c.g)} << 8) | channel(c.b));
    }
  }
  for (int32_t e = 0; e < m.edge_count(); ++e) {
    if (m.is_mobius(kernel::EdgeId(e))) h = mix(h, static_cast<uint64_t>(e) + 1);
  }
  return h;
}

}  // namespace nomec::backend
