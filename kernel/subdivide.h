// Catmull-Clark subdivision on winged-edge meshes with Möbius edges (seed report §4):
// face, edge and vertex points with boundary edges infinitely sharp, the corner /
// crease / smooth vertex rules chosen by the number of sharp edges, semi-sharp creases
// whose sharpness drops by one per level, and child→parent maps for every level.
#pragma once

#include <cstdint>
#include <vector>

#include "kernel/mesh.h"
#include "kernel/result.h"

namespace nomec::kernel {

/// The smooth-vertex rule (n_sharp <= 1), seed §4.1.3.
enum class VertexRule : uint8_t {
  /// (n-3)/n v + 2/n avg(edge midpoints) + 1/n avg(face points); OpenSubdiv's Catmark.
  CatmullClark,
  /// (n-2)/n v + 1/n avg(new edge points) + 1/n avg(face points) (DeRose et al.).
  DeRose,
};

/// Whether the passes of a level run on two threads. The result is the same bit for bit.
enum class Threading : uint8_t {
  /// Two threads for a level whose parent has at least `kTwoThreadEdges` edges, on a
  /// machine that runs two threads at once; one thread otherwise.
  Automatic,
  OneThread,
  /// Two threads for every level, however small (for tests).
  TwoThreads,
};

/// The parent edge count from which `Threading::Automatic` splits a level's passes over two
/// threads. Rationale: measured on a 2-core machine (bench/kernel); below it the cost of
/// starting the threads and of the vertex sums set aside at the seam is not repaid.
inline constexpr int32_t kTwoThreadEdges = 1 << 15;

/// Options for `subdivide`, e.g. from NOME's `subdivision s sd_type NOME_SD_CC_sharp
/// sd_level 3 … endsubdivision`.
struct SubdivisionOptions {
  int32_t levels = 1;
  VertexRule vertex_rule = VertexRule::CatmullClark;
  /// Honour crease and corner sharpness (NOME_SD_CC_sharp, the default); false gives
  /// plain Catmull-Clark where only boundary edges are sharp (NOME_SD_CatmullClark) and
  /// the child meshes carry no sharpness.
  bool is_sharpness_honoured = true;
  /// Fill the child→parent face map of each level whose parent has faces other than quads
  /// (4 bytes per child face; see `SubdivisionLevel`).
  bool has_parent_maps = true;
  /// Refuse (InvalidArgument) a level whose mesh would have more vertices than this; 0 is
  /// no limit. Each level has V + E + F vertices of the level before.
  int64_t max_vertices = 0;
  Threading threading = Threading::Automatic;
};

/// What a child vertex was created from.
struct VertexParent {
  enum class Kind : uint8_t { Face, Edge, Vertex };
  Kind kind = Kind::Vertex;
  /// Index of the parent face, edge or vertex.
  int32_t index = -1;
};

/// What a child edge was created from: half of a parent edge, or the inside of a parent
/// face (joining an edge point to the face point).
struct EdgeParent {
  enum class Kind : uint8_t { Edge, Face };
  Kind kind = Kind::Edge;
  int32_t index = -1;
};

/// One refinement level: the child mesh and its child→parent maps.
///
/// Layout (stable, relied on by the maps): child vertices are the F face points, then
/// the E edge points, then the V vertex points; child edges are the two halves of each
/// parent edge (2e near end 0, 2e+1 near end 1), then one edge per face corner (joining
/// the corner's edge point to the face point); the child faces of parent face f are
/// consecutive, one per corner in loop order.
///
/// Rationale: because of this layout the vertex and edge parents are pure index
/// arithmetic, and so is the face parent when every parent face is a quad (every level
/// after the first): child face q then comes from parent face q / 4. Only the face map of
/// a level whose parent has other polygons is stored, at 4 bytes per child face;
/// `face_parent`, `vertex_parent` and `edge_parent` read the maps.
struct SubdivisionLevel {
  Mesh mesh;
  /// Child face -> parent face, filled only when `has_parent_maps` was set and some parent
  /// face is not a quad; read it through `face_parent`.
  std::vector<FaceId> face_parents;
  /// Every parent face is a quad, so `face_parents` is left empty.
  bool are_parent_faces_quads = false;
  int32_t parent_face_count = 0;
  int32_t parent_edge_count = 0;

  /// The parent face of a child face. Precondition: `has_parent_maps` was set or the parent
  /// faces are all quads.
  FaceId face_parent(FaceId f) const {
    return are_parent_faces_quads ? FaceId(f.index / 4) : face_parents[f.index];
  }

  /// The parent element of a child vertex. Precondition: `v` is a vertex of `mesh`.
  VertexParent vertex_parent(VertexId v) const {
    if (v.index < parent_face_count) {
      return {VertexParent::Kind::Face, v.index};
    }
    if (v.index < parent_face_count + parent_edge_count) {
      return {VertexParent::Kind::Edge, v.index - parent_face_count};
    }
    return {VertexParent::Kind::Vertex, v.index - parent_face_count - parent_edge_count};
  }
  /// The parent element of a child edge. Precondition: `has_parent_maps` was set.
  EdgeParent edge_parent(EdgeId e) const {
    if (e.index < 2 * parent_edge_count) {
      return {EdgeParent::Kind::Edge, e.index / 2};
    }
    return {EdgeParent::Kind::Face, face_parent(FaceId(e.index - 2 * parent_edge_count)).index};
  }
};

/// One level of Catmull-Clark. Precondition: `mesh` came from `build_mesh` or a kernel
/// operation (so it is a 2-manifold). Never fails. Möbius flags, colours and face
/// sources are inherited; edge and vertex sharpness s become max(s - 1, 0) (infinity
/// stays), and a vertex with sharpness > 0 follows the corner rule.
SubdivisionLevel subdivide_once(const Mesh& mesh, const SubdivisionOptions& options = {});

/// `options.levels` levels; element i is level i + 1. Fails with `InvalidArgument` if
/// levels is outside [0, 12] or a level would exceed `options.max_vertices`.
Result<std::vector<SubdivisionLevel>> subdivide(const Mesh& mesh,
                                                const SubdivisionOptions& options);

/// The last of `options.levels` levels only, equal bit for bit to
/// `subdivide(mesh, options)->back().mesh` (`mesh` itself for 0 levels), with the same
/// failures; `has_parent_maps` is ignored (no maps are returned).
///
/// Rationale: a caller that wants only the result (the pipeline's `--subdivide N`, a
/// scene's `subdivision` block) should not pay for every level at once. Taking `mesh` by
/// value lets it be freed as soon as level 1 exists, and each intermediate level as soon as
/// the next one does, so the peak is the last two levels instead of all of them. An
/// intermediate level also stores only what the next refinement reads: no `prev` wings, no
/// border links, and no face sources or colours when its parent faces are all quads (its
/// face q then inherits from its parent face q / 4, so the last level reads them from the
/// nearest level that stores them).
Result<Mesh> subdivide_last_level(Mesh mesh, const SubdivisionOptions& options);

}  // namespace nomec::kernel
