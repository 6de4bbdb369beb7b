// Face deletion. Rather than patching wings in place, the remaining faces are re-emitted
// as a polygon soup and rebuilt: the builder already restores the F_a-before-F_b order,
// Möbius flags and border loops in linear time. Before that, face corners at each vertex
// are grouped into fans with a union-find over the edges that keep both faces, and every
// fan gets its own output vertex, so deleting faces never leaves a bowtie vertex.
#include "kernel/edit.h"

#include <fmt/format.h>

#include <numeric>

namespace nomec::kernel {

Result<DeleteResult> delete_faces(const Mesh& mesh, std::span<const FaceId> faces) {
  const int32_t F = mesh.face_count();
  const int32_t E = mesh.edge_count();
  std::vector<uint8_t> is_deleted(F, 0);
  for (FaceId f : faces) {
    if (f.index < 0 || f.index >= F) {
      return KernelError{KernelError::Kind::InvalidArgument,
                         fmt::format("face {} does not exist; the mesh has {} faces", f.index, F),
                         {},
                         {f},
                         {}};
    }
    is_deleted[f.index] = 1;
  }
  auto is_kept_use = [&](EdgeUse u) {
    FaceId f = mesh.use_face(u);
    return f.is_valid() && !is_deleted[f.index];
  };

  // Union-find over corners; a corner is the use whose tail is the corner's vertex.
  std::vector<int32_t> parent(2 * static_cast<size_t>(E));
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int32_t x) {
    while (parent[x] != x) {
      parent[x] = parent[parent[x]];
      x = parent[x];
    }
    return x;
  };
  auto corner_at = [&](EdgeUse u, VertexId v) { return mesh.use_tail(u) == v ? u : mesh.next(u); };
  for (int32_t e = 0; e < E; ++e) {
    const EdgeUse a(EdgeId(e), 0), b(EdgeId(e), 1);
    if (!is_kept_use(a) || !is_kept_use(b)) {
      continue;
    }
    for (int end = 0; end < 2; ++end) {
      const VertexId v = mesh.edge_vertex(EdgeId(e), end);
      const int32_t x = find(corner_at(a, v).index);
      const int32_t y = find(corner_at(b, v).index);
      if (x != y) {
        parent[std::max(x, y)] = std::min(x, y);
      }
    }
  }

  // One output vertex per (vertex, fan root), numbered in face order of first use.
  DeleteResult result;
  PolygonSoup soup;
  std::vector<int32_t> root_vertex(2 * static_cast<size_t>(E), -1);
  std::vector<int32_t> first_copy(mesh.vertex_count(), -1);
  std::vector<int32_t> loop;
  for (int32_t f = 0; f < F; ++f) {
    if (is_deleted[f]) {
      continue;
    }
    loop.clear();
    mesh.for_each_face_use(FaceId(f), [&](EdgeUse u) {
      const int32_t root = find(u.index);
      if (root_vertex[root] < 0) {
        const VertexId v = mesh.use_tail(u);
        root_vertex[root] = soup.add_vertex(mesh.position(v));
        result.vertex_parents.push_back(v);
        if (first_copy[v.index] < 0) {
          first_copy[v.index] = root_vertex[root];
        } else {
          ++result.split_vertex_count;
        }
      }
      loop.push_back(root_vertex[root]);
    });
    soup.add_face(loop);
    soup.face_sources.push_back(mesh.face_source(FaceId(f)));
    if (mesh.has_face_colors()) {
      soup.face_colors.push_back(mesh.face_color(FaceId(f)));
    }
    result.face_parents.push_back(FaceId(f));
  }
  if (mesh.has_vertex_names()) {
    for (VertexId v : result.vertex_parents) {
      soup.names.emplace_back(mesh.vertex_name(v));
    }
  }
  // Corners on every copy of their vertex.
  for (size_t i = 0; i < result.vertex_parents.size(); ++i) {
    const float s = mesh.vertex_sharpness(result.vertex_parents[i]);
    if (s > 0.0f) {
      soup.corners.push_back({static_cast<int32_t>(i), s});
    }
  }
  // Creases of surviving edges, on the output vertices of one of their faces.
  for (int32_t e = 0; e < E; ++e) {
    if (mesh.sharpness(EdgeId(e)) <= 0.0f) {
      continue;
    }
    EdgeUse u(EdgeId(e), 0);
    if (!is_kept_use(u)) {
      u = u.twin();
      if (!is_kept_use(u)) {
        continue;
      }
    }
    soup.creases.push_back({root_vertex[find(u.index)], root_vertex[find(mesh.next(u).index)],
                            mesh.sharpness(EdgeId(e))});
  }

  auto built = build_mesh(soup);
  if (!built.has_value()) {
    KernelError error = built.error();
    error.message = "face deletion left a non-manifold mesh: " + error.message;
    return error;
  }
  result.mesh = std::move(*built);
  return result;
}

}  // namespace nomec::kernel
