// Topology summary of one output mesh (see summary.h).
#include "backend/summary.h"

#include "kernel/topology.h"

namespace nomec::backend {

MeshSummary summarize(const OutputMesh& m) {
  kernel::TopologyReport t = kernel::topology(m.mesh);
  MeshSummary s;
  s.name = m.name;
  s.vertices = t.vertex_count;
  s.edges = t.edge_count;
  s.faces = t.face_count;
  s.euler = t.euler_characteristic;
  s.is_orientable = t.is_orientable;
  s.border_loops = t.border_loop_count;
  for (const auto& c : t.components) s.genus += c.genus;
  s.components = static_cast<int32_t>(t.components.size());
  s.is_closed = t.is_closed && t.face_count > 0;  // curves alone bound no solid
  s.curves = m.curve_count;
  kernel::BoundingBox b = kernel::bounding_box(m.mesh);
  if (b.min.x <= b.max.x) s.bounding_box = MeshSummary::Box{b.min, b.max};
  s.position_hash = kernel::position_hash(m.mesh, 1e-3);
  return s;
}

std::map<int32_t, NodeFacts> node_facts(const ir::Module& module, std::span<const OutputMesh> meshes) {
  std::map<int32_t, NodeFacts> facts;
  auto extend = [](NodeFacts& f, const glm::dvec3& p) {
    for (int k = 0; k < 3; ++k) {
      if (f.vertices == 0 && f.faces == 0) {
        f.min[k] = f.max[k] = p[k];
      } else {
        f.min[k] = std::min(f.min[k], p[k]);
        f.max[k] = std::max(f.max[k], p[k]);
      }
    }
  };
  for (const backend::OutputMesh& m : meshes) {
    const kernel::PolygonSoup& s = m.soup;
    if (m.scene_node.is_valid()) {
      NodeFacts& f = facts[m.scene_node.index];
      NodeFacts local;
      for (const glm::dvec3& p : s.positions) {
        extend(local, p);
        ++local.vertices;
      }
      local.faces = static_cast<int64_t>(s.face_sizes.size());
      local.placements = 1;
      f = local;
    }
    // Per face: the innermost instance that placed it and the statement that made it.
    std::map<int32_t, std::vector<int32_t>> seen;  // node -> vertices (deduplicated below)
    size_t at = 0;
    for (size_t fi = 0; fi < s.face_sizes.size(); ++fi) {
      const int32_t n = s.face_sizes[fi];
      int32_t nodes[2] = {-1, -1};
      if (fi < s.face_sources.size()) {
        nodes[0] = s.face_sources[fi].instance;
        int32_t src = s.face_sources[fi].source_face;
        if (src >= 0 && static_cast<size_t>(src) < module.nodes.size()) {
          const ir::Node& sn = module.nodes[src];
          nodes[1] = sn.kind == ir::NodeKind::Face && sn.parent.is_valid() ? sn.parent.index : src;
        }
      }
      for (int32_t node : nodes) {
        if (node < 0 || static_cast<size_t>(node) >= module.nodes.size() || node == m.scene_node.index) continue;
        NodeFacts& f = facts[node];
        std::vector<int32_t>& verts = seen[node];
        for (int32_t k = 0; k < n && at + k < s.face_vertices.size(); ++k) {
          int32_t v = s.face_vertices[at + k];
          if (v < 0 || static_cast<size_t>(v) >= s.positions.size()) continue;
          if (f.vertices == 0 && f.faces == 0 && verts.empty()) f.min[0] = f.min[1] = f.min[2] = 0;
          verts.push_back(v);
        }
        ++f.faces;
      }
      at += static_cast<size_t>(std::max(n, 0));
    }
    for (auto& [node, verts] : seen) {
      std::sort(verts.begin(), verts.end());
      verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
      NodeFacts& f = facts[node];
      NodeFacts box;
      for (int32_t v : verts) {
        extend(box, s.positions[v]);
        ++box.vertices;
      }
      if (f.vertices == 0) {
        std::copy(box.min, box.min + 3, f.min);
        std::copy(box.max, box.max + 3, f.max);
      } else {
        for (int k = 0; k < 3; ++k) {
          f.min[k] = std::min(f.min[k], box.min[k]);
          f.max[k] = std::max(f.max[k], box.max[k]);
        }
      }
      f.vertices += box.vertices;
      ++f.placements;
    }
  }
  return facts;
}

}  // namespace nomec::backend
