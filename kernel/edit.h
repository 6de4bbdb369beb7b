// Interactive editing operations on meshes (seed report §7.3.3): deleting faces with the
// cleanup that keeps the result a valid 2-manifold (unused edges and vertices removed,
// F_a refilled, vertices left with two separate fans split in two).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "kernel/mesh.h"
#include "kernel/result.h"

namespace nomec::kernel {

/// The mesh after `delete_faces`, with maps back to the input.
struct DeleteResult {
  Mesh mesh;
  /// Output face -> input face.
  std::vector<FaceId> face_parents;
  /// Output vertex -> input vertex (several outputs share an input when it was split).
  std::vector<VertexId> vertex_parents;
  /// Number of extra vertices created by splitting pinched vertices.
  int32_t split_vertex_count = 0;
};

/// Deletes `faces` (duplicates allowed) from `mesh`, e.g. the faces picked with
/// `delete face inst.f1 endface … enddelete`. Edges left without faces and vertices left without
/// edges are removed; an edge that loses F_a keeps its other face as F_a; a vertex whose
/// remaining faces form several fans becomes one vertex per fan. Remaining faces keep
/// their order, orientation, sources and colours; creases are kept. Linear in the number
/// of edges. Fails with `InvalidArgument` if a face ID is out of range.
Result<DeleteResult> delete_faces(const Mesh& mesh, std::span<const FaceId> faces);

}  // namespace nomec::kernel
