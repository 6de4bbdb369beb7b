// Boundary merging (seed report §3.3): boundary edges whose end vertices coincide within
// a tolerance are joined; the vertices of matched edges are merged by connected
// components of the matching graph; joins between faces of opposite orientation become
// Möbius edges; merges that would make the mesh non-manifold are refused.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "kernel/mesh.h"
#include "kernel/result.h"

namespace nomec::kernel {

/// Options for `merge`, e.g. from NOME's `merge m tolerance 0.001 … endmerge`.
struct MergeOptions {
  /// Two vertices coincide when their distance is at most this. Must be >= 0.
  double tolerance = 1e-6;
};

/// A merged mesh. Faces keep their IDs (face i of the input is face i of the result).
struct MergeResult {
  Mesh mesh;
  /// Input vertex -> merged vertex.
  std::vector<VertexId> vertex_map;
  /// Number of pairs of boundary edges that were joined.
  int32_t joined_edge_count = 0;
};

/// Merges the boundaries of the (possibly many) components of `mesh`.
///
/// Only boundary edges are joined, and only when both end vertices coincide pairwise
/// (in either direction). A merged vertex is placed at the average of the input vertices
/// it replaces; creases keep the larger sharpness. Fails with
/// - `InvalidArgument` for a negative tolerance;
/// - `NonManifoldMerge` if a boundary edge coincides with two or more other boundary
///   edges (`edges` lists the input edges involved), or if the joins would create an
///   edge with three faces or a vertex whose faces do not form one fan (`faces` /
///   `vertices` list the offending input faces / vertices).
Result<MergeResult> merge(const Mesh& mesh, const MergeOptions& options = {});

/// Concatenates `meshes` and merges the result; `vertex_map` is indexed by the
/// concatenated vertex numbering (see `concatenate`). Fails as `merge` above.
Result<MergeResult> merge(std::span<const Mesh* const> meshes, const MergeOptions& options = {});

/// Concatenates meshes into one (vertex and face IDs are offset by the sizes of the
/// preceding meshes; face sources and colours are kept). Never fails.
Mesh concatenate(std::span<const Mesh* const> meshes);

/// The disjoint union of `meshes` made by offsetting their arrays, without rebuilding: the
/// same vertices, faces and topology as `concatenate`, and each part keeps its own edge
/// numbering (offset by the preceding parts' edge counts). Linear with a small constant;
/// used to reassemble a scene from cached parts. Vertex normals are dropped.
Mesh append_disjoint(std::span<const Mesh* const> meshes);

}  // namespace nomec::kernel
