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

}  // namespace nomec::backend
