// The drawable form of an output mesh for a live preview (the language server's
// `nome/preview`, `nomec view`): float positions, the faces fanned into triangles with the
// face each triangle came from, per-face RGB colours, and the mesh's edges, border edges
// and Möbius edges as vertex-index pairs, and its curves (polylines) as line segments. Plain arrays, JSON-free: lsp/ encodes them. E.g.
// a unit quad gives 4 positions, 2 triangles (both from face 0), 4 edges, all 4 of them
// border edges and no Möbius edge.
#pragma once

#include <cstdint>
#include <vector>

#include "backend/evaluate.h"

namespace nomec::backend {

struct PreviewGeometry {
  std::vector<float> positions;          // x y z per vertex
  std::vector<uint32_t> triangles;       // 3 vertex indices per triangle
  std::vector<uint32_t> triangle_faces;  // the face of each triangle
  std::vector<uint8_t> face_colors;      // r g b per face (0-255); empty when uncoloured
  std::vector<uint32_t> edges;           // 2 vertex indices per edge of the mesh
  std::vector<uint32_t> border_edges;    // 2 per border edge, loop after loop
  std::vector<uint32_t> mobius_edges;    // 2 per Möbius edge
  std::vector<float> curve_points;       // x y z per point of the output's curves
  std::vector<uint32_t> curve_segments;  // 2 indices into curve_points per segment
  int32_t face_count = 0;
};

/// Everything a preview draws of `mesh`.
PreviewGeometry preview_geometry(const OutputMesh& mesh);
/// Only the positions (for an update whose topology did not change).
std::vector<float> preview_positions(const OutputMesh& mesh);
/// A hash of what `preview_geometry` returns except positions (vertex, edge and face
/// counts, faces, Möbius flags, colours): equal keys mean a client may keep its triangles
/// and edges and take new positions only.
uint64_t preview_topology_key(const OutputMesh& mesh);

}  // namespace nomec::backend
