// The winged-edge mesh at the centre of the kernel (seed report §2) and its builder
// from a polygon soup. Faces keep the orientation they were given in; an edge shared by
// two faces of opposite orientation is a Möbius edge, so single-sided surfaces (Möbius
// bands, Klein bottles) are represented without special cases in the callers.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "kernel/ids.h"
#include "kernel/large_arrays.h"
#include "kernel/result.h"

namespace nomec::kernel {

/// Edge sharpness meaning "infinitely sharp" (boundary edges are always treated so).
inline constexpr float kInfiniteSharpness = std::numeric_limits<float>::infinity();

/// Where a face came from: the face of the input mesh and the scene instance that
/// produced it, e.g. face `f1` of `instance i1 cube endinstance`. Both are opaque to the
/// kernel (-1 = unknown) and are copied to every face derived from this one.
struct FaceSource {
  int32_t source_face = -1;
  int32_t instance = -1;
  friend bool operator==(const FaceSource&, const FaceSource&) = default;
};

/// A polygon soup: positions (optionally named) and faces as cyclic lists of vertex
/// indices in their input orientation, e.g. the points and faces of a NOME `mesh` block.
struct PolygonSoup {
  /// Semi-sharp or sharp crease between two soup vertices, e.g. NOME's `sharp 2 (a b)`.
  struct Crease {
    int32_t a = -1;
    int32_t b = -1;
    float sharpness = 0.0f;
  };

  std::vector<glm::dvec3> positions;
  /// Empty, or one (possibly empty) name per vertex.
  std::vector<std::string> names;
  /// Number of vertices of each face; `face_vertices` holds them back to back.
  std::vector<int32_t> face_sizes;
  std::vector<int32_t> face_vertices;
  /// Empty, or one entry per face. When empty, face i gets source_face = i.
  std::vector<FaceSource> face_sources;
  /// Empty, or one RGB colour per face.
  std::vector<glm::vec3> face_colors;
  std::vector<Crease> creases;
  /// Sharp vertex (corner sharpness), e.g. NOME's `sharp 3 (a) endsharp`.
  struct Corner {
    int32_t vertex = -1;
    float sharpness = 0.0f;
  };
  std::vector<Corner> corners;

  /// Appends a vertex and returns its index.
  int32_t add_vertex(const glm::dvec3& position, std::string name = {});
  /// Appends a face; the vertex indices are checked only by `build_mesh`.
  int32_t add_face(std::span<const int32_t> vertices);
  int32_t add_face(std::initializer_list<int32_t> vertices) {
    return add_face(std::span<const int32_t>(vertices.begin(), vertices.size()));
  }
  /// Appends a face given by vertex names. Fails with `UnknownVertex` naming the first
  /// unknown name. Lookup is linear in the vertex count (names are for small inputs).
  Result<int32_t> add_face_by_names(std::span<const std::string> vertex_names);
  int32_t face_count() const { return static_cast<int32_t>(face_sizes.size()); }
  int32_t vertex_count() const { return static_cast<int32_t>(positions.size()); }
};

/// One corner of the fan around a vertex, as produced by `Mesh::vertex_ring`.
struct VertexCorner {
  /// The face of this corner.
  FaceId face;
  /// The use (side of an edge) of `face` that starts at the vertex.
  EdgeUse use;
  /// True if `face`'s orientation is opposite to the first corner's, i.e. an odd number
  /// of Möbius edges was crossed to get here (the seed's Möbius counter, §5.1).
  bool is_flipped = false;
};

/// A winged-edge 2-manifold mesh with Möbius edges.
///
/// Representation (rationale): everything is an int32 index into structure-of-arrays
/// storage. Per edge we store its two end vertices in the direction F_a traverses it,
/// its faces F_a and F_b (F_a is filled first, so boundary edges have no F_b), and the
/// four wings as `EdgeUse`s: the next and previous edge use around F_a and around F_b.
/// The Möbius flag says F_b traverses the edge in the *same* direction as F_a (faces of
/// opposite orientation); otherwise F_b traverses it backwards. The unused F_b wings of
/// a boundary edge hold the neighbouring boundary edges of its border loop. Per vertex we
/// keep one incident edge (a boundary edge for boundary vertices, so a single walk
/// covers the fan); per face one edge use. Face size, vertex valence and normals are
/// redundant and are not stored: they are recomputed by traversal when needed. Optional
/// properties (sharpness, colours, names) are empty arrays when absent, so a smooth
/// uncoloured mesh pays nothing for them.
class Mesh {
 public:
  Mesh() = default;

  int32_t vertex_count() const { return static_cast<int32_t>(positions_.size()); }
  int32_t edge_count() const { return static_cast<int32_t>(edge_flags_.size()); }
  int32_t face_count() const { return static_cast<int32_t>(face_uses_.size()); }

  // ---- vertices ----
  const glm::dvec3& position(VertexId v) const { return positions_[v.index]; }
  void set_position(VertexId v, const glm::dvec3& p) { positions_[v.index] = p; }
  const OverwriteVector<glm::dvec3>& positions() const { return positions_; }
  /// One incident edge (a boundary edge if the vertex is on a border), or None for a
  /// vertex no face uses.
  EdgeId vertex_edge(VertexId v) const { return vertex_edges_[v.index]; }
  bool is_boundary_vertex(VertexId v) const {
    EdgeId e = vertex_edges_[v.index];
    return e.is_valid() && is_boundary(e);
  }
  /// Name given in the soup, or "" (meshes derived by subdivision carry no names).
  /// Optional per-vertex normal property (see `assign_vertex_normals` in offset.h). Not
  /// inherited by derived meshes, whose geometry differs: recompute it on them.
  bool has_vertex_normals() const { return !normals_.empty(); }
  /// Precondition: `has_vertex_normals()`.
  const glm::dvec3& vertex_normal(VertexId v) const { return normals_[v.index]; }
  /// Sets all vertex normals; fails with `InvalidArgument` unless there is one per vertex.
  Result<bool> set_vertex_normals(std::vector<glm::dvec3> normals);
  bool has_vertex_names() const { return !names_.empty(); }
  std::string_view vertex_name(VertexId v) const {
    return names_.empty() ? std::string_view() : std::string_view(names_[v.index]);
  }

  // ---- edges ----
  /// End vertex 0 or 1, in the direction face F_a traverses the edge.
  VertexId edge_vertex(EdgeId e, int end) const { return edge_vertices_[2 * e.index + end]; }
  /// F_a (side 0) or F_b (side 1); F_b is None for a boundary edge.
  FaceId edge_face(EdgeId e, int side) const { return use_faces_[2 * e.index + side]; }
  bool is_boundary(EdgeId e) const { return !use_faces_[2 * e.index + 1].is_valid(); }
  bool is_mobius(EdgeId e) const { return edge_flags_[e.index] & kMobiusFlag; }
  /// Crease sharpness (0 = smooth). Boundary edges are infinitely sharp regardless.
  float sharpness(EdgeId e) const { return sharpness_.empty() ? 0.0f : sharpness_[e.index]; }
  void set_sharpness(EdgeId e, float s) {
    if (sharpness_.empty()) {
      sharpness_.assign(edge_count(), 0.0f);
    }
    sharpness_[e.index] = s;
  }
  /// True if some edge may carry a non-zero sharpness (the array is allocated).
  bool has_sharpness() const { return !sharpness_.empty(); }
  /// Vertex (corner) sharpness: a vertex with sharpness > 0 follows the corner rule.
  float vertex_sharpness(VertexId v) const {
    return vertex_sharpness_.empty() ? 0.0f : vertex_sharpness_[v.index];
  }
  void set_vertex_sharpness(VertexId v, float s) {
    if (vertex_sharpness_.empty()) {
      vertex_sharpness_.assign(vertex_count(), 0.0f);
    }
    vertex_sharpness_[v.index] = s;
  }
  /// The edge joining `a` and `b` (either direction), or None. Linear in the valence.
  EdgeId find_edge(VertexId a, VertexId b) const;

  // ---- edge uses (one face's side of an edge) and the four wings ----
  FaceId use_face(EdgeUse u) const { return use_faces_[u.index]; }
  /// Next / previous use around the use's face. Precondition: `use_face(u)` is valid.
  EdgeUse next(EdgeUse u) const { return next_[u.index]; }
  EdgeUse prev(EdgeUse u) const { return prev_[u.index]; }
  /// True if the use's face traverses the edge from end 0 to end 1.
  bool is_forward(EdgeUse u) const { return u.side() == 0 || is_mobius(u.edge()); }
  VertexId use_tail(EdgeUse u) const {
    return edge_vertices_[2 * u.edge().index + (is_forward(u) ? 0 : 1)];
  }
  VertexId use_head(EdgeUse u) const {
    return edge_vertices_[2 * u.edge().index + (is_forward(u) ? 1 : 0)];
  }

  // ---- faces ----
  /// The first use of the face's loop (its first input edge).
  EdgeUse face_use(FaceId f) const { return face_uses_[f.index]; }
  /// Calls `fn(EdgeUse)` for each use around `f`, in the face's own orientation.
  template <typename Fn>
  void for_each_face_use(FaceId f, Fn&& fn) const {
    EdgeUse start = face_uses_[f.index];
    EdgeUse u = start;
    do {
      fn(u);
      u = next_[u.index];
    } while (u != start);
  }
  int32_t face_size(FaceId f) const;
  /// Vertices around `f` in its orientation, starting at the first input vertex.
  std::vector<VertexId> face_vertices(FaceId f) const;
  const FaceSource& face_source(FaceId f) const { return face_sources_[f.index]; }
  void set_face_source(FaceId f, const FaceSource& s) { face_sources_[f.index] = s; }
  bool has_face_colors() const { return !face_colors_.empty(); }
  /// Precondition: `has_face_colors()`.
  const glm::vec3& face_color(FaceId f) const { return face_colors_[f.index]; }

  // ---- traversals ----
  /// The fan of corners around `v`, consistent across Möbius edges. For a border vertex
  /// it starts at the face of one border edge and ends at the other border edge. Empty for
  /// an unused vertex.
  std::vector<VertexCorner> vertex_ring(VertexId v) const;
  /// Calls `fn(const VertexCorner&)` for each corner around `v` (see `vertex_ring`).
  template <typename Fn>
  void for_each_vertex_corner(VertexId v, Fn&& fn) const;
  /// Number of edges at `v` (the valence), found by traversal.
  int32_t vertex_valence(VertexId v) const;

  // ---- borders ----
  /// One edge per border loop.
  const std::vector<EdgeId>& border_loops() const { return border_loops_; }
  /// The two neighbours of boundary edge `e` in its border loop (consistent cyclic order,
  /// which may change direction relative to face orientation across Möbius edges).
  EdgeId border_next(EdgeId e) const { return next_[2 * e.index + 1].edge(); }
  EdgeId border_prev(EdgeId e) const { return prev_[2 * e.index + 1].edge(); }
  /// The edges of border loop `loop` in order.
  std::vector<EdgeId> border_loop_edges(int32_t loop) const;

  /// True if some edge is a Möbius edge.
  bool has_mobius_edges() const;

  /// Rough heap bytes owned by this mesh (for the benchmarks).
  size_t memory_bytes() const;

 private:
  friend struct MeshAccess;
  static constexpr uint8_t kMobiusFlag = 1;

  // vertices
  OverwriteVector<glm::dvec3> positions_;  // `resize(n)` leaves new positions unwritten
  OverwriteVector<EdgeId> vertex_edges_;
  std::vector<std::string> names_;
  std::vector<glm::dvec3> normals_;
  std::vector<float> vertex_sharpness_;
  // edges (2 entries per edge: end vertices / per-use arrays indexed by EdgeUse)
  OverwriteVector<VertexId> edge_vertices_;
  OverwriteVector<FaceId> use_faces_;
  OverwriteVector<EdgeUse> next_;
  OverwriteVector<EdgeUse> prev_;
  OverwriteVector<uint8_t> edge_flags_;
  std::vector<float> sharpness_;
  // faces
  OverwriteVector<EdgeUse> face_uses_;
  OverwriteVector<FaceSource> face_sources_;  // `resize(n)` leaves new sources unwritten
  std::vector<glm::vec3> face_colors_;
  // borders
  std::vector<EdgeId> border_loops_;
};

/// Builds a mesh from `soup` in time linear in the number of edges.
///
/// Vertex i of the soup becomes VertexId(i) and face i FaceId(i). Edges are numbered in
/// order of first appearance. Fails with
/// - `UnknownVertex` if a face references an index outside the soup;
/// - `DegenerateFace` for faces with fewer than 3 vertices or a repeated consecutive
///   vertex (`faces` lists them);
/// - `NonManifoldEdge` if an edge is used by three or more faces (`vertices` holds the
///   end-vertex pairs, `faces` all faces on those edges);
/// - `NonManifoldVertex` if the faces around a vertex form more than one fan.
Result<Mesh> build_mesh(const PolygonSoup& soup);

/// True if `a` and `b` differ at most in vertex positions and vertex normals: the same
/// counts, connectivity, Möbius flags, sharpness, names, face sources and colours, and
/// border loops. Such meshes stay interchangeable after a position-only edit, e.g. a
/// moved instance whose reassembled scene is patched in place of rebuilt.
bool has_same_topology(const Mesh& a, const Mesh& b);

/// The inverse of `build_mesh`: positions, faces in loop order, sources, colours and
/// creases (edges with non-zero sharpness) and corners (sharp vertices).
PolygonSoup to_soup(const Mesh& mesh);

/// Internal access to the storage for kernel algorithms (subdivision, offset); not part
/// of the public API.
struct MeshAccess {
  static OverwriteVector<glm::dvec3>& positions(Mesh& m) { return m.positions_; }
  static OverwriteVector<EdgeId>& vertex_edges(Mesh& m) { return m.vertex_edges_; }
  static OverwriteVector<VertexId>& edge_vertices(Mesh& m) { return m.edge_vertices_; }
  static OverwriteVector<FaceId>& use_faces(Mesh& m) { return m.use_faces_; }
  static OverwriteVector<EdgeUse>& next(Mesh& m) { return m.next_; }
  static OverwriteVector<EdgeUse>& prev(Mesh& m) { return m.prev_; }
  static OverwriteVector<uint8_t>& edge_flags(Mesh& m) { return m.edge_flags_; }
  static std::vector<float>& sharpness(Mesh& m) { return m.sharpness_; }
  static std::vector<float>& vertex_sharpness(Mesh& m) { return m.vertex_sharpness_; }
  static OverwriteVector<EdgeUse>& face_uses(Mesh& m) { return m.face_uses_; }
  static OverwriteVector<FaceSource>& face_sources(Mesh& m) { return m.face_sources_; }
  static std::vector<glm::vec3>& face_colors(Mesh& m) { return m.face_colors_; }
  static const OverwriteVector<glm::dvec3>& positions(const Mesh& m) { return m.positions_; }
  static const OverwriteVector<EdgeId>& vertex_edges(const Mesh& m) { return m.vertex_edges_; }
  static const OverwriteVector<VertexId>& edge_vertices(const Mesh& m) { return m.edge_vertices_; }
  static const OverwriteVector<FaceId>& use_faces(const Mesh& m) { return m.use_faces_; }
  static const OverwriteVector<EdgeUse>& next(const Mesh& m) { return m.next_; }
  static const OverwriteVector<EdgeUse>& prev(const Mesh& m) { return m.prev_; }
  static const OverwriteVector<uint8_t>& edge_flags(const Mesh& m) { return m.edge_flags_; }
  static const std::vector<float>& sharpness(const Mesh& m) { return m.sharpness_; }
  static const std::vector<float>& vertex_sharpness(const Mesh& m) { return m.vertex_sharpness_; }
  static const OverwriteVector<EdgeUse>& face_uses(const Mesh& m) { return m.face_uses_; }
  static const OverwriteVector<FaceSource>& face_sources(const Mesh& m) { return m.face_sources_; }
  static const std::vector<glm::vec3>& face_colors(const Mesh& m) { return m.face_colors_; }
  static std::vector<std::string>& names(Mesh& m) { return m.names_; }
  static const std::vector<std::string>& names(const Mesh& m) { return m.names_; }
  static uint8_t mobius_flag() { return Mesh::kMobiusFlag; }
  /// Links boundary edges into border loops (uses the F_b wings of boundary edges).
  static void link_borders(Mesh& m);
  /// `build_mesh(soup)` for a caller that already knows which uses share an edge, e.g. the
  /// offset, whose edges follow from the input's: `twin[k]` is the other use (soup corner
  /// index, corner k running from the k-th face vertex to the next) of use k's edge, or -1
  /// on a border. Preconditions, not checked: the soup is valid, `twin` is an involution
  /// pairing exactly the uses with equal unordered vertex pairs (no pair is used more than
  /// twice), and every vertex's faces form one fan. The result equals `build_mesh(soup)`.
  static Result<Mesh> build_paired(PolygonSoup soup, std::vector<int32_t> twin);
};

template <typename Fn>
void Mesh::for_each_vertex_corner(VertexId v, Fn&& fn) const {
  EdgeId anchor = vertex_edges_[v.index];
  if (!anchor.is_valid()) {
    return;
  }
  // Walk state: a use `x` of the current face touching v. Unflipped: x ends at v and
  // the walk crosses next(x); flipped (after an odd number of Möbius edges): x starts at
  // v and the walk crosses prev(x). Starting on the anchor makes a border walk begin at
  // one border edge and end at the other.
  EdgeUse x(anchor, 0);
  bool is_flipped = use_tail(x) == v;
  const bool start_flipped = is_flipped;
  const EdgeUse start = x;
  const int32_t limit = 2 * edge_count() + 2;
  for (int32_t step = 0; step < limit; ++step) {
    EdgeUse corner = is_flipped ? x : next_[x.index];
    fn(VertexCorner{use_faces_[corner.index], corner, is_flipped != start_flipped});
    EdgeUse crossing = is_flipped ? prev_[x.index] : next_[x.index];
    if (is_boundary(crossing.edge())) {
      return;
    }
    x = crossing.twin();
    is_flipped = use_tail(x) == v;
    if (x == start && is_flipped == start_flipped) {
      return;
    }
  }
}

}  // namespace nomec::kernel
