// Offset slabs (seed report §5): Newell face normals, vertex normals with the Möbius
// counter, positive and negative offset surfaces that join across Möbius edges, and
// ribbons along the borders. The result is always a closed, orientable 2-manifold
// without Möbius edges, which can be subdivided again to round its rims (§5.4). Also the
// lattice variant (NOME3's `width`): every face becomes a frame and the frames are
// thickened, turning the edges into prisms.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <optional>
#include <vector>

#include "kernel/mesh.h"
#include "kernel/result.h"

namespace nomec::kernel {

/// One edge's term of Newell's normal: summed over a polygon's edges (a, b) in order it
/// gives twice the polygon's area vector, for planar and non-planar polygons alike.
inline glm::dvec3 newell_term(const glm::dvec3& a, const glm::dvec3& b) {
  return glm::dvec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
}

/// Unit normal of the closed polygon `points` by Newell's method (zero vector when it has
/// zero area).
glm::dvec3 newell_normal(const std::vector<glm::dvec3>& points);

/// Unit face normals by Newell's method, in each face's own orientation (zero vector
/// for a face with zero area).
std::vector<glm::dvec3> face_normals(const Mesh& mesh);

/// Vertex normals and the per-corner signs of the Möbius counter.
struct VertexNormals {
  /// Unit normal per vertex, relative to the first face of its ring (zero if unused).
  std::vector<glm::dvec3> normals;
  /// Per edge use (indexed by `EdgeUse::index`, for uses whose face is valid): +1 if the
  /// face of the use agrees with the vertex normal at the use's tail vertex, -1 if an
  /// odd number of Möbius edges separates it from the ring's first face.
  std::vector<int8_t> corner_signs;
  /// Vertices touching at least one Möbius edge (the seed's "Möbius" vertex mark).
  std::vector<uint8_t> is_mobius_vertex;
};

/// Averages the signed face normals around every vertex (§5.1). Never fails.
VertexNormals vertex_normals(const Mesh& mesh, const std::vector<glm::dvec3>& face_normals);

/// Computes `vertex_normals(mesh, face_normals(mesh))` and stores the normals as the
/// mesh's vertex-normal property (e.g. for OBJ/PLY output). Never fails.
void assign_vertex_normals(Mesh& mesh);

/// Options for `offset`, e.g. from NOME's `offset o height 0.1 … endoffset`.
struct OffsetOptions {
  /// Distance of each offset surface from the input (NOME's `height`); the slab is twice
  /// as thick.
  double distance = 0.1;
  /// Fill `OffsetResult::face_parents` and `vertex_parents` (16 bytes per output face and
  /// vertex that a caller keeping only the mesh, like `nomec --offset`, does not need).
  bool has_parent_maps = true;
};

/// What an offset face was made from.
struct OffsetParent {
  enum class Kind : uint8_t { PositiveFace, NegativeFace, Ribbon };
  Kind kind = Kind::PositiveFace;
  /// The input face (for ribbons: the face of the border edge).
  FaceId face;
  /// For ribbons: the input border edge; None otherwise.
  EdgeId edge;
};

/// An offset or lattice slab with its child→parent maps.
struct OffsetResult {
  Mesh mesh;
  std::vector<OffsetParent> face_parents;
  /// Output vertex -> input vertex it was offset from (lattice: vertex of the frame).
  std::vector<VertexId> vertex_parents;
  /// Corners at Möbius vertices where the seed's dot-product check (vertex normal vs.
  /// face normal, §5.2) disagrees with the Möbius counter. The counter is used (it is
  /// exact); a non-zero count flags strongly folded geometry.
  int32_t inconsistent_normal_count = 0;
};

/// Thickens `mesh` into a closed orientable slab: a positive copy (input orientation),
/// a negative copy (reversed) and one quad ribbon per border edge. For a closed input
/// the result has χ = 2·χ(input); for input with borders the ribbons close it, and still
/// χ = 2·χ(input) (a disk gives a sphere, a Möbius band a torus). Faces inherit sources
/// and colours. Linear in the number of edges. Fails with `InvalidArgument` if
/// `distance` is not positive and finite.
Result<OffsetResult> offset(const Mesh& mesh, const OffsetOptions& options);

/// `offset` of a mesh the caller no longer needs (the pipeline's `--offset`), equal bit for
/// bit to `offset(mesh, options)`; afterwards `mesh` is valid only to be destroyed or
/// assigned (some of its arrays may have been freed). Rationale: as for
/// `subdivide_last_level`, which takes its mesh by value, the arrays the construction has
/// finished reading (the positions, the `prev` wings and the vertex anchors: about 36 MB
/// for an input of 830k quads) are freed before the slab's own arrays are made, which then
/// reuse that memory instead of taking fresh pages.
Result<OffsetResult> offset_consuming(Mesh&& mesh, const OffsetOptions& options);

/// `offset` by the reference construction, kept for differential tests: the slab as a
/// polygon soup (positive copies, reversed negative copies, ribbons) rebuilt by the mesh
/// builder. `offset` writes the same mesh's arrays directly and falls back to this when the
/// input's corners do not pair up. Ignores `has_parent_maps` (the maps are filled).
Result<OffsetResult> offset_through_builder(const Mesh& mesh, const OffsetOptions& options);

/// `offset`'s direct construction alone, for tests that must see it run: nothing where
/// `offset` falls back to `offset_through_builder` (input whose corners do not pair up), so
/// a mistake that only sent valid input down the fallback is not hidden by it.
std::optional<OffsetResult> offset_direct_only(const Mesh& mesh, const OffsetOptions& options);

/// Options for `lattice`, e.g. from NOME's `offset o offset_type NOME_OFFSET_GRID
/// height 0.05 width 0.1 … endoffset`.
struct LatticeOptions {
  /// How far each face's inner hole boundary lies from its edges (moved towards the face
  /// centre, at most 90% of the way).
  double width = 0.1;
  /// Half the thickness of the beams (as `OffsetOptions::distance`).
  double distance = 0.05;
};

/// Replaces every face by a frame (a ring of quads around a hole) and thickens the
/// frames, so every edge becomes a prism and every face a window. The result is closed
/// and orientable with χ = 2·(χ(input) - F). `face_parents` refer to input faces.
/// Fails with `InvalidArgument` for non-positive width or distance.
Result<OffsetResult> lattice(const Mesh& mesh, const LatticeOptions& options);

}  // namespace nomec::kernel
