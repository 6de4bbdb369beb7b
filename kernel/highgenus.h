// High-genus constructions of the second seed (`001_…`, TopMod's DLFLConnect,
// DLFLCrust and DLFLMultiConnect): handles between two faces (one-segment pipes and
// multi-segment Hermite handles with weights and twists), rinds with punched and peeled
// faces, generalized Sierpinski polyhedra and generalized Menger sponges. All work on any
// 2-manifold mesh, including single-sided ones: face orientations are kept as given and
// the builder marks Möbius edges where they result.
#pragma once

#include <cstdint>
#include <vector>

#include "kernel/mesh.h"
#include "kernel/result.h"

namespace nomec::kernel {

/// Options for `connect_faces`, e.g. from NOME's `handle h faces (f1 f2) segments 8
/// weights (1 1) twist 0.5 … endhandle`.
struct HandleOptions {
  /// The two faces to join (different, sharing no vertex).
  FaceId faces[2];
  /// The corners to pair first, a vertex of each face; None = automatic (the pairing
  /// of the two loops, first face forwards and second backwards, with the smallest sum
  /// of squared distances).
  VertexId corners[2];
  /// 1: a straight pipe of quads (TopMod's connectFaces); more: a handle of that many
  /// rings of quads along a cubic Hermite curve between the face centroids.
  int32_t segments = 1;
  /// End tangents of the Hermite curve along the faces' normals, as multiples of the
  /// distance between the centroids.
  double weights[2] = {1.0, 1.0};
  /// Extra turns of the handle's cross-section about its centre line (may be fractional).
  double twist = 0.0;
};

/// Joins two faces by a handle: both faces are removed and their loops joined by rings
/// of quads. A face with fewer sides first gets its longest edges split at their middle
/// until both have the same number (this also adds a vertex to the face across each split
/// edge). Faces in one component add one to its genus (a handle, or a cross-cap pair on a
/// single-sided surface); faces of two components join them. Fails with
/// `InvalidArgument` for faces out of range or equal, faces sharing a vertex, corners not
/// on their face, fewer than 1 segment, or a non-finite weight or twist.
Result<Mesh> connect_faces(const Mesh& mesh, const HandleOptions& options);

/// Options for `rind`, e.g. from NOME's `rind r thickness 0.1 punch (f1) … endrind`.
struct RindOptions {
  /// Distance between the two sheets (each lies thickness/2 from the surface).
  double thickness = 0.1;
  /// Faces whose two sheets are removed and joined by a wall along the region's edge:
  /// one hole through the crust per connected region.
  std::vector<FaceId> punch;
  /// Faces whose outer sheet is removed and whose region's edge gets a wall down to the
  /// inner sheet, which stays as the floor of the peeled region.
  std::vector<FaceId> peel;
};

/// Thickens `mesh` into a crust (as `offset`: the positive sheet, the negative sheet and
/// ribbons along borders), then punches and peels. For a closed input with punched
/// regions R, χ = 2·χ(input) − 2·R; a border edge of a punched or peeled face loses its
/// ribbon, opening the crust there. Fails with `InvalidArgument` for a non-positive
/// thickness, faces out of range, a face both punched and peeled, or a punched face
/// sharing an edge with a peeled one.
Result<Mesh> rind(const Mesh& mesh, const RindOptions& options);

/// Options for `sierpinski`, e.g. from NOME's `sierpinski s level 2 … endsierpinski`.
struct SierpinskiOptions {
  int32_t levels = 1;
  /// The most faces the result may have (0: no limit); checked before each level.
  int64_t max_faces = 0;
};

/// TopMod's multiConnectMidpoints applied `levels` times: every edge is split at its
/// midpoint, every original corner is cut off as a triangle (a corner next to a self-loop
/// spans it; the second corner of a vertex with two edges is skipped, as TopMod does), and
/// the central polygons are joined at every interior midpoint by a self-loop edge (merging
/// two faces or splitting one); they end as one closing face per cluster of corners. With
/// N non-loop edges a level maps a closed mesh to χ' = 2(V − N): a tetrahedron gives genus
/// 3, then 15. Self-loops are built as a small triangle at their vertex after the last
/// level (see `LoopMesh::to_mesh`), which leaves χ as is. Fails with `InvalidArgument`
/// for levels < 0 or a result over `max_faces`.
Result<Mesh> sierpinski(const Mesh& mesh, const SierpinskiOptions& options);

/// Options for `menger`, e.g. from NOME's `menger m level 2 thickness 0.33 … endmenger`.
struct MengerOptions {
  int32_t levels = 1;
  /// Frame width and tunnel depth of the first level; each further level uses a third of
  /// the previous one (the classic sponge's proportions).
  double thickness = 0.1;
  /// Inner-wall edges shorter than collapse × thickness are collapsed (TopMod's collapse
  /// threshold factor); values up to 0.001 mean 0.01.
  double collapse = 0.0;
  int64_t max_faces = 0;
};

/// TopMod's createSponge applied `levels` times: every face becomes a frame of 2n quads
/// around an inset hole, a tunnel of depth `thickness` leads from the hole to an inner
/// copy of the face, and the inner copies are joined by walls along the edges and
/// polygons at the vertices (collapsed where they are shorter than the threshold). A
/// closed mesh gets χ' = 2·(V − E): a cube (level 1) is a genus-5 surface, the level-1
/// Menger sponge when the thickness is a third of the edge. Faces should be convex.
/// Fails with `InvalidArgument` for levels < 0, a non-positive thickness, or a result
/// over `max_faces`; with the builder's errors if collapsing made the mesh non-manifold.
Result<Mesh> menger(const Mesh& mesh, const MengerOptions& options);

}  // namespace nomec::kernel
