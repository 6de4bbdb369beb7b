// Connected components and their classification, plus the order-independent summary
// helpers (bounding box, rounded-position hash) used by mesh goldens. Orientability is
// decided by a breadth-first propagation of a ±1 orientation per face: crossing a
// regular edge keeps the neighbour's sign equal, crossing a Möbius edge flips it; a
// contradiction means the component is single-sided.
#include "kernel/topology.h"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <glm/common.hpp>

namespace nomec::kernel {

std::vector<int32_t> face_components(const Mesh& mesh) {
  const int32_t face_count = mesh.face_count();
  std::vector<int32_t> component(face_count, -1);
  std::vector<int32_t> queue;
  queue.reserve(face_count);
  int32_t next_component = 0;
  for (int32_t seed = 0; seed < face_count; ++seed) {
    if (component[seed] >= 0) {
      continue;
    }
    component[seed] = next_component;
    queue.clear();
    queue.push_back(seed);
    for (size_t head = 0; head < queue.size(); ++head) {
      mesh.for_each_face_use(FaceId(queue[head]), [&](EdgeUse u) {
        FaceId other = mesh.use_face(u.twin());
        if (other.is_valid() && component[other.index] < 0) {
          component[other.index] = next_component;
          queue.push_back(other.index);
        }
      });
    }
    ++next_component;
  }
  return component;
}

TopologyReport topology(const Mesh& mesh) {
  TopologyReport report;
  const std::vector<int32_t> component = face_components(mesh);
  int32_t component_count = 0;
  for (int32_t c : component) {
    component_count = std::max(component_count, c + 1);
  }
  report.components.resize(component_count);
  for (int32_t f = mesh.face_count() - 1; f >= 0; --f) {
    ComponentTopology& c = report.components[component[f]];
    ++c.face_count;
    c.first_face = FaceId(f);
  }
  for (int32_t e = 0; e < mesh.edge_count(); ++e) {
    ComponentTopology& c = report.components[component[mesh.edge_face(EdgeId(e), 0).index]];
    ++c.edge_count;
    if (mesh.is_mobius(EdgeId(e))) {
      ++c.mobius_edge_count;
    }
  }
  for (int32_t v = 0; v < mesh.vertex_count(); ++v) {
    EdgeId e = mesh.vertex_edge(VertexId(v));
    if (!e.is_valid()) {
      ++report.isolated_vertex_count;
      continue;
    }
    ++report.components[component[mesh.edge_face(e, 0).index]].vertex_count;
  }
  for (EdgeId start : mesh.border_loops()) {
    ++report.components[component[mesh.edge_face(start, 0).index]].border_loop_count;
  }

  // Orientation propagation.
  std::vector<int8_t> sign(mesh.face_count(), 0);
  std::vector<int32_t> queue;
  queue.reserve(mesh.face_count());
  for (int32_t seed = 0; seed < mesh.face_count(); ++seed) {
    if (sign[seed] != 0) {
      continue;
    }
    ComponentTopology& c = report.components[component[seed]];
    sign[seed] = 1;
    queue.clear();
    queue.push_back(seed);
    for (size_t head = 0; head < queue.size(); ++head) {
      const int32_t f = queue[head];
      mesh.for_each_face_use(FaceId(f), [&](EdgeUse u) {
        FaceId other = mesh.use_face(u.twin());
        if (!other.is_valid()) {
          return;
        }
        const int8_t expected = static_cast<int8_t>(mesh.is_mobius(u.edge()) ? -sign[f] : sign[f]);
        if (sign[other.index] == 0) {
          sign[other.index] = expected;
          queue.push_back(other.index);
        } else if (sign[other.index] != expected) {
          c.is_orientable = false;
        }
      });
    }
  }

  for (ComponentTopology& c : report.components) {
    c.euler_characteristic = c.vertex_count - c.edge_count + c.face_count;
    c.is_closed = c.border_loop_count == 0;
    const int32_t deficit = 2 - c.euler_characteristic - c.border_loop_count;
    c.genus = c.is_orientable ? deficit / 2 : deficit;
    report.vertex_count += c.vertex_count;
    report.edge_count += c.edge_count;
    report.face_count += c.face_count;
    report.border_loop_count += c.border_loop_count;
    report.is_orientable = report.is_orientable && c.is_orientable;
    report.is_closed = report.is_closed && c.is_closed;
  }
  report.euler_characteristic = report.vertex_count - report.edge_count + report.face_count;
  return report;
}

BoundingBox bounding_box(const Mesh& mesh) {
  BoundingBox box;
  for (int32_t v = 0; v < mesh.vertex_count(); ++v) {
    if (!mesh.vertex_edge(VertexId(v)).is_valid()) {
      continue;
    }
    box.min = glm::min(box.min, mesh.position(VertexId(v)));
    box.max = glm::max(box.max, mesh.position(VertexId(v)));
  }
  return box;
}

uint64_t position_hash(const Mesh& mesh, double quantum) {
  // Sum (mod 2^64) of a strong mix of each rounded coordinate triple: commutative, so
  // independent of vertex order.
  auto mix = [](uint64_t x) {
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ull;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebull;
    x ^= x >> 31;
    return x;
  };
  uint64_t hash = 0;
  for (int32_t v = 0; v < mesh.vertex_count(); ++v) {
    if (!mesh.vertex_edge(VertexId(v)).is_valid()) {
      continue;
    }
    const glm::dvec3& p = mesh.position(VertexId(v));
    uint64_t h = 0x9e3779b97f4a7c15ull;
    for (int c = 0; c < 3; ++c) {
      const double rounded = std::round(p[c] / quantum);
      h = mix(h ^ static_cast<uint64_t>(static_cast<int64_t>(rounded == 0.0 ? 0.0 : rounded)));
    }
    hash += h;
  }
  return hash;
}

std::string mesh_problem(const Mesh& m) {
  const int32_t V = m.vertex_count(), E = m.edge_count(), F = m.face_count();
  auto use_ok = [&](EdgeUse u) { return u.index >= 0 && u.index < 2 * E; };
  for (int32_t v = 0; v < V; ++v) {
    const glm::dvec3& p = m.position(VertexId(v));
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      return fmt::format("vertex {} has a non-finite position", v);
    }
  }
  for (int32_t e = 0; e < E; ++e) {
    for (int end = 0; end < 2; ++end) {
      const VertexId v = m.edge_vertex(EdgeId(e), end);
      if (v.index < 0 || v.index >= V) return fmt::format("edge {} has an out-of-range vertex", e);
    }
    const FaceId f = m.edge_face(EdgeId(e), 0);
    if (!f.is_valid() || f.index >= F) return fmt::format("edge {} has no face", e);
  }
  for (int32_t f = 0; f < F; ++f) {
    const EdgeUse first = m.face_use(FaceId(f));
    if (!use_ok(first)) return fmt::format("face {} has an out-of-range first use", f);
    EdgeUse u = first;
    int32_t steps = 0;
    do {
      if (m.use_face(u) != FaceId(f)) return fmt::format("face {}: a use of its loop belongs to another face", f);
      const EdgeUse n = m.next(u);
      if (!use_ok(n) || !use_ok(m.prev(u))) return fmt::format("face {}: a use links out of range", f);
      if (m.prev(n) != u) return fmt::format("face {}: prev(next(u)) is not u", f);
      if (m.use_head(u) != m.use_tail(n)) return fmt::format("face {}: consecutive uses do not share a vertex", f);
      u = n;
      if (++steps > 2 * E) return fmt::format("face {}: its loop of uses does not close", f);
    } while (u != first);
    if (steps < 3) return fmt::format("face {} has {} sides", f, steps);
  }
  return {};
}

}  // namespace nomec::kernel
