// DLFL-style editing (the second seed, `001_…`, and TopMod's DLFLCore): a mesh seen as
// faces that are cyclic lists of vertex corners, with the minimal operators the
// high-genus constructions are made of — create a point-sphere vertex, insert an edge
// between two corners (co-facial: split the face; non-co-facial: merge the two faces,
// which adds a handle or joins two components, and makes a self-loop edge when both
// corners are at the same vertex), delete an edge and split an edge. Face orientations
// are kept as given, so an edge traversed in the same direction by its two faces is a
// Möbius edge when the result is built back into a winged-edge `Mesh`.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <string>
#include <unordered_map>
#include <vector>

#include "kernel/mesh.h"
#include "kernel/result.h"

namespace nomec::kernel {

/// `v` scaled to unit length, or `fallback` when `v` has (nearly) no length: the
/// directions of point spheres and of handle frames.
glm::dvec3 unit_or(const glm::dvec3& v, const glm::dvec3& fallback);

/// A corner of a `LoopMesh`: the `index`-th vertex of face `face`'s loop. The edge
/// leaving the corner goes to the next vertex of the loop.
struct LoopCorner {
  int32_t face = -1;
  int32_t index = -1;
};

/// Faces as cyclic vertex lists (DLFL's corner cycles), editable in place.
///
/// Invariants (`problem()` reports the first broken one; the operators check them in
/// debug builds): every face index and vertex index is in range; consecutive corners of
/// a face differ unless they form a self-loop edge; an edge (unordered vertex pair) is
/// used by at most two face sides, and a self-loop by exactly two; a face of one corner
/// is a point sphere (a vertex with no edges). Removed faces are empty loops and keep
/// their index so `LoopCorner`s of other faces stay valid.
class LoopMesh {
 public:
  LoopMesh() = default;
  /// Copies positions, faces (in their loop order), sources and colours of `mesh`.
  static LoopMesh from_mesh(const Mesh& mesh);

  int32_t vertex_count() const { return static_cast<int32_t>(positions_.size()); }
  int32_t face_count() const { return static_cast<int32_t>(faces_.size()); }
  const glm::dvec3& position(int32_t v) const { return positions_[v]; }
  void set_position(int32_t v, const glm::dvec3& p) { positions_[v] = p; }
  /// The loop of face `f` (empty for a removed face).
  const std::vector<int32_t>& face(int32_t f) const { return faces_[f]; }
  const FaceSource& source(int32_t f) const { return sources_[f]; }
  /// Number of edges (self-loops included).
  int64_t edge_count() const { return static_cast<int64_t>(edge_uses_.size()); }
  /// Number of face sides using the edge between `a` and `b` (0, 1 or 2).
  int32_t edge_use_count(int32_t a, int32_t b) const;

  /// Appends a vertex used by no face.
  int32_t add_vertex(const glm::dvec3& p);
  /// Appends a face with the given loop, source and colour (no checks: callers build
  /// valid meshes; `problem()` verifies).
  int32_t add_face(std::vector<int32_t> loop, FaceSource source = {}, glm::vec3 color = {});
  /// DLFL CreateVertex: a new vertex and its point-sphere face (one corner, no edge).
  /// Returns the face.
  int32_t create_point_sphere(const glm::dvec3& p);

  /// DLFL InsertEdge between corners `a` and `b`; returns the face that received the
  /// corner `b` side. Co-facial (`a.face == b.face`): the face becomes the loop from `a` to
  /// `b` and a new face (returned) the loop from `b` to `a`. Otherwise the two faces merge
  /// into `a.face` (returned) as a, …, a, b, …, b, and `b.face` is removed; both corners
  /// are visited twice, and equal vertices make a self-loop edge. Fails with
  /// `InvalidArgument` for corners out of range, equal corners, or an edge that already
  /// exists (DLFL would make a double edge).
  Result<int32_t> insert_edge(LoopCorner a, LoopCorner b);
  /// Inserts an edge between each pair of corners, all named in the faces as they are
  /// before the first insertion; the result is that of `insert_edge` on each pair in turn
  /// (faces merged or split as the pairs connect them). Linear in the size of the faces
  /// involved, where inserting one by one rewrites ever larger merged faces. The faces
  /// involved are rewritten (removed faces stay empty) and new faces are appended. Fails
  /// with `InvalidArgument` (and changes nothing) for corners out of range, a corner
  /// used twice, or an edge that exists already or is inserted twice.
  Result<bool> insert_edges(const std::vector<std::pair<LoopCorner, LoopCorner>>& pairs);
  /// DLFL DeleteEdge of the edge leaving corner `c`: two different faces merge (into the
  /// face of `c`); one face on both sides splits in two (or, across a Möbius edge, stays
  /// one face). Returns the face of `c`. Fails with `InvalidArgument` for a corner out of
  /// range or an edge with a single face side (a border edge).
  Result<int32_t> delete_edge(LoopCorner c);
  /// Splits the edge leaving corner `c` with a new vertex at `p`, in both faces that use
  /// it. Returns the new vertex. Fails with `InvalidArgument` for a corner out of range
  /// or a self-loop edge.
  Result<int32_t> split_edge(LoopCorner c, const glm::dvec3& p);
  /// Splits every edge at its midpoint (TopMod's subdivideEdges with n = 2), self-loops
  /// excepted. Returns, per vertex of the result, whether it is one of the new midpoints.
  std::vector<uint8_t> split_all_edges();

  /// The first broken invariant, or "".
  std::string problem() const;

  /// Builds the winged-edge mesh. Self-loop edges (which a winged-edge mesh without
  /// repeated vertices cannot hold) are first realised as a small triangle: the loop at
  /// vertex v gets two new vertices next to v, so the faces on its two sides keep their
  /// corners. Unused vertices are dropped. Fails like `build_mesh`, and with
  /// `DegenerateFace` for point spheres and two-corner faces.
  Result<Mesh> to_mesh() const;

 private:
  static uint64_t key(int32_t a, int32_t b) {
    const uint32_t lo = static_cast<uint32_t>(a < b ? a : b), hi = static_cast<uint32_t>(a < b ? b : a);
    return (static_cast<uint64_t>(hi) << 32) | lo;
  }
  void count_face(int32_t f, int32_t delta);
  bool valid_corner(LoopCorner c) const;
  /// The other side of the edge leaving `c`: its face and index (the corner the other
  /// side's edge leaves from), or face -1.
  LoopCorner other_side(LoopCorner c) const;
  void debug_check() const;

  std::vector<glm::dvec3> positions_;
  std::vector<std::vector<int32_t>> faces_;
  std::vector<FaceSource> sources_;
  std::vector<glm::vec3> colors_;
  bool has_colors_ = false;
  std::unordered_map<uint64_t, int32_t> edge_uses_;
};

}  // namespace nomec::kernel
