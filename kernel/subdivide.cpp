// Catmull-Clark refinement of one level, written as a few linear passes over flat
// arrays: (1) walk every face once for its face point, (2) edge points and the child edges
// that halve the parent edges, (3) per-vertex sums (neighbours and face points gathered in
// the vertex point's own slot, sharp neighbours) scattered from edges and face corners,
// then the corner / crease / smooth rule, (4) the child winged-edge topology written
// arithmetically (the child IDs of every parent element are known in advance, see
// `SubdivisionLevel`), so no hashing and no generic builder are needed.
//
// Vertex rules follow the seed (§4.1.3) and coincide with OpenSubdiv's Catmark scheme
// with edge-only boundary interpolation and uniform creasing, including the blend used
// when a semi-sharp crease becomes smooth in the child level.
#include "kernel/subdivide.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <span>
#include <glm/geometric.hpp>

#include "kernel/large_arrays.h"

namespace nomec::kernel {
namespace {

using glm::dvec3;

float child_sharpness(float s) {
  if (std::isinf(s)) {
    return s;
  }
  return s > 1.0f ? s - 1.0f : 0.0f;
}

// Rule from the number of sharp incident edges: 0 = smooth (or dart), 2 = crease,
// 3 = corner.
int rule_of(int sharp_count) {
  if (sharp_count >= 3) {
    return 3;
  }
  return sharp_count == 2 ? 2 : 0;
}

// Per-vertex sums that only sharp edges contribute to (allocated only if the parent has
// boundary or crease edges).
struct SharpSums {
  dvec3 parent_neighbours{0.0};  // other ends of edges sharp in the parent level
  dvec3 child_neighbours{0.0};   // other ends of edges still sharp in the child level
  float transition_sum = 0.0f;   // sharpness of edges that become smooth in the child
  int16_t transition_count = 0;
  int16_t parent_count = 0;
  int16_t child_count = 0;
};

// Where the parent's faces find their sources and colours: parent face f reads element
// f >> shift of these arrays. They are the parent's own arrays (shift 0), or those of the
// nearest ancestor that stores them when the levels in between do not (each such level
// splits every face into four consecutive children, so going up one level is q / 4).
struct FaceInheritance {
  std::span<const FaceSource> sources;
  std::span<const glm::vec3> colors;  // empty: the faces have no colours
  int shift = 0;
};

// One level of refinement as named passes over the parent's flat arrays (see the top of
// the file); the passes share the parent's arrays and the child being built. Every child
// array is allocated once at its exact size, and the only scratch memory is a valence per
// parent vertex (plus `SharpSums` when there are sharp edges).
//
// An intermediate child (`is_intermediate`, see `subdivide_last_level`) is only ever read
// by the next refinement, which reads neither its `prev` wings nor its border links, and
// reads its face sources and colours through `FaceInheritance`; so it gets none of them,
// except sources and colours when some parent face is not a quad (q / 4 fails).
// `has_border_loops` says whether the child's border loops are linked (the parent's were).
class Refiner {
 public:
  Refiner(const Mesh& parent, const SubdivisionOptions& options, const FaceInheritance& inheritance,
          bool is_intermediate, bool has_border_loops)
      : p_(parent),
        options_(options),
        inheritance_(inheritance),
        is_intermediate_(is_intermediate),
        has_border_loops_(has_border_loops),
        stores_face_properties_(!is_intermediate),
        F_(parent.face_count()),
        E_(parent.edge_count()),
        V_(parent.vertex_count()),
        pos_(parent.positions()),
        pev_(MeshAccess::edge_vertices(parent)),
        puf_(MeshAccess::use_faces(parent)),
        pnext_(MeshAccess::next(parent)),
        pflags_(MeshAccess::edge_flags(parent)),
        psharp_(MeshAccess::sharpness(parent)),
        pvsharp_(MeshAccess::vertex_sharpness(parent)),
        pface_uses_(MeshAccess::face_uses(parent)),
        mobius_flag_(MeshAccess::mobius_flag()),
        has_creases_(options.is_sharpness_honoured && !psharp_.empty()),
        has_corners_(options.is_sharpness_honoured && !pvsharp_.empty()),
        cpos_(MeshAccess::positions(level_.mesh)) {}

  SubdivisionLevel run() {
    count_corners();
    child_edge_halves();
    faces();
    edge_points();
    vertex_points();
    child_vertex_edges();
    inherit_corners_and_creases();
    level_.parent_face_count = F_;
    level_.parent_edge_count = E_;
    return std::move(level_);
  }

 private:
  // The vertex whose position starts use `u` (Möbius edges are read forwards on both sides).
  int32_t tail_of(EdgeUse u) const {
    const int32_t e = u.index >> 1;
    const bool is_forward = (u.index & 1) == 0 || (pflags_[e] & mobius_flag_);
    return pev_[2 * e + (is_forward ? 0 : 1)].index;
  }

  // Every use of an edge belongs to a face except the second side of a border edge, so
  // the parent has 2E minus its border edges corners (= child faces).
  void count_corners() {
    int64_t border_edges = 0;
    for (int32_t e = 0; e < E_; ++e) border_edges += puf_[2 * e + 1].is_valid() ? 0 : 1;
    corner_total_ = static_cast<int32_t>(2 * int64_t{E_} - border_edges);
  }

  // (a) The two child edges of every parent edge (edge 2e from its tail's vertex point to
  // the edge point, 2e+1 on to its head's), which depend on the parent's edges alone. Every
  // child array is allocated here at its exact size: arrays written in index order are
  // filled by push_back (one pass over the memory), the per-use arrays, written out of
  // order by `faces`, are sized.
  void child_edge_halves() {
    Mesh& child = level_.mesh;
    const size_t cE = 2 * static_cast<size_t>(E_) + corner_total_;
    auto& cev = MeshAccess::edge_vertices(child);
    auto& cuf = MeshAccess::use_faces(child);
    auto& cflags = MeshAccess::edge_flags(child);
    auto& csharp = MeshAccess::sharpness(child);
    auto& cvertex_edges = MeshAccess::vertex_edges(child);
    reserve_large(cev, 2 * cE);
    auto& cnext = MeshAccess::next(child);
    auto& cprev = MeshAccess::prev(child);
    // Every element of these four is written below or by `faces` (the per-use arrays: the
    // uses of the faces there, the unused side of a border edge here) or, for vertex
    // anchors, by `faces` (face points), here (edge points) and `child_vertex_edges`.
    resize_for_overwrite(cuf, 2 * cE);
    resize_for_overwrite(cnext, 2 * cE);
    if (!is_intermediate_) resize_for_overwrite(cprev, 2 * cE);
    reserve_large(cflags, cE);
    if (has_creases_) reserve_large(csharp, cE);
    resize_for_overwrite(cvertex_edges, static_cast<size_t>(F_) + E_ + V_);
    reserve_large(MeshAccess::face_uses(child), corner_total_);
    if (stores_face_properties_) reserve_face_properties();
    const int32_t vp_base = F_ + E_;
    for (int32_t e = 0; e < E_; ++e) {
      cev.push_back(VertexId(vp_base + pev_[2 * e].index));
      cev.push_back(VertexId(F_ + e));
      cev.push_back(VertexId(F_ + e));
      cev.push_back(VertexId(vp_base + pev_[2 * e + 1].index));
      cflags.push_back(pflags_[e]);
      cflags.push_back(pflags_[e]);
      if (has_creases_) {
        const float cs = child_sharpness(psharp_[e]);
        csharp.push_back(cs);
        csharp.push_back(cs);
        has_child_creases_ = has_child_creases_ || cs > 0.0f;
      }
      if (!puf_[2 * e + 1].is_valid()) {  // no wings yet; `link_borders` may add some
        for (const int32_t u : {4 * e + 1, 4 * e + 3}) {
          cuf[u] = FaceId::None();
          cnext[u] = EdgeUse::None();
          if (!is_intermediate_) cprev[u] = EdgeUse::None();
        }
      }
      cvertex_edges[F_ + e] = EdgeId(2 * e);
    }
  }

  // (b) One walk around every parent face: its face point, scattered into the slots of its
  // vertices' points (each slot starts as the sum of the face points around the vertex),
  // and its child quads with their interior edges (from the edge point to the face point),
  // whose wings are known arithmetically, so no hashing.
  void faces() {
    Mesh& child = level_.mesh;
    auto& cev = MeshAccess::edge_vertices(child);
    auto& cflags = MeshAccess::edge_flags(child);
    auto& csharp = MeshAccess::sharpness(child);
    auto& cvertex_edges = MeshAccess::vertex_edges(child);
    resize_large(cpos_, static_cast<size_t>(F_) + E_ + V_);  // zero-initialised
    dvec3* vertex_points = cpos_.data() + F_ + E_;
    bool are_quads = true;  // so far; the face map is stored from the first other polygon
    int32_t o = 0;
    for (int32_t f = 0; f < F_; ++f) {
      face_loop_.clear();
      dvec3 sum(0.0);
      const EdgeUse start = pface_uses_[f];
      EdgeUse u = start;
      do {
        face_loop_.push_back(u);
        sum += pos_[tail_of(u)];
        u = pnext_[u.index];
      } while (u != start);
      const int32_t n = static_cast<int32_t>(face_loop_.size());
      if (n != 4 && are_quads) {
        are_quads = false;
        if (options_.has_parent_maps) start_face_map(o);
        if (!stores_face_properties_) start_face_properties(o);
      }
      const dvec3 fp = sum / double(n);
      cpos_[f] = fp;
      for (const EdgeUse x : face_loop_) vertex_points[tail_of(x)] += fp;
      cvertex_edges[f] = EdgeId(2 * E_ + o);
      link_face_children(o, n);
      for (int32_t i = 0; i < n; ++i) {
        cev.push_back(VertexId(F_ + (face_loop_[i].index >> 1)));
        cev.push_back(VertexId(f));
        cflags.push_back(0);
        if (has_creases_) csharp.push_back(0.0f);
        if (stores_face_properties_) inherit_face_properties(f);
        if (!are_quads && options_.has_parent_maps) level_.face_parents.push_back(FaceId(f));
      }
      o += n;
    }
    level_.are_parent_faces_quads = are_quads;
  }

  void reserve_face_properties() {
    reserve_large(MeshAccess::face_sources(level_.mesh), corner_total_);
    if (!inheritance_.colors.empty()) reserve_large(MeshAccess::face_colors(level_.mesh), corner_total_);
  }

  // Appends the source and colour of a child of parent face `f`.
  void inherit_face_properties(int32_t f) {
    const size_t i = static_cast<size_t>(f) >> inheritance_.shift;
    MeshAccess::face_sources(level_.mesh).push_back(inheritance_.sources[i]);
    if (!inheritance_.colors.empty()) MeshAccess::face_colors(level_.mesh).push_back(inheritance_.colors[i]);
  }

  // An intermediate child's sources and colours up to child face `o`, whose parent faces
  // were all quads, and from there on.
  void start_face_properties(int32_t o) {
    stores_face_properties_ = true;
    reserve_face_properties();
    for (int32_t q = 0; q < o; ++q) inherit_face_properties(q / 4);
  }

  // The face map up to child face `o`, whose parent faces were all quads.
  void start_face_map(int32_t o) {
    reserve_large(level_.face_parents, corner_total_);
    for (int32_t q = 0; q < o; ++q) level_.face_parents.push_back(FaceId(q / 4));
  }

  // (c) Edge points, and per-vertex sums over edges: the other ends of a vertex's edges (or
  // its edge points, DeRose) are added to its vertex-point slot, and its valence is counted.
  void edge_points() {
    valence_.assign(V_, 0);
    const bool is_derose = options_.vertex_rule == VertexRule::DeRose;
    dvec3* edge_points = cpos_.data() + F_;
    dvec3* vertex_points = edge_points + E_;
    for (int32_t e = 0; e < E_; ++e) {
      const int32_t a = pev_[2 * e].index;
      const int32_t b = pev_[2 * e + 1].index;
      const dvec3& pa = pos_[a];
      const dvec3& pb = pos_[b];
      const bool is_boundary = !puf_[2 * e + 1].is_valid();
      const float s = is_boundary ? kInfiniteSharpness : (has_creases_ ? psharp_[e] : 0.0f);
      dvec3 point;
      if (s >= 1.0f) {
        point = 0.5 * (pa + pb);
      } else {
        const dvec3 smooth = 0.25 * (pa + pb + cpos_[puf_[2 * e].index] + cpos_[puf_[2 * e + 1].index]);
        point = s <= 0.0f ? smooth : double(s) * (0.5 * (pa + pb)) + (1.0 - double(s)) * smooth;
      }
      edge_points[e] = point;
      ++valence_[a];
      ++valence_[b];
      vertex_points[a] += is_derose ? point : pb;
      vertex_points[b] += is_derose ? point : pa;
      if (s > 0.0f) add_sharp_edge(a, b, s);
    }
  }

  void add_sharp_edge(int32_t a, int32_t b, float s) {
    if (sharp_.empty()) sharp_.resize(V_);
    const float cs = child_sharpness(s);
    for (int end = 0; end < 2; ++end) {
      SharpSums& ss = sharp_[end == 0 ? a : b];
      const dvec3& other = pos_[end == 0 ? b : a];
      ss.parent_neighbours += other;
      ++ss.parent_count;
      if (cs > 0.0f) {
        ss.child_neighbours += other;
        ++ss.child_count;
      } else {
        ss.transition_sum += s;
        ++ss.transition_count;
      }
    }
  }

  // (d) Vertex points, overwriting each vertex's sum of face points and neighbours once it
  // is read.
  void vertex_points() {
    dvec3* vertex_points = cpos_.data() + F_ + E_;
    for (int32_t v = 0; v < V_; ++v) vertex_points[v] = vertex_point(v, vertex_points[v]);
    std::vector<int32_t>().swap(valence_);
    std::vector<SharpSums>().swap(sharp_);
  }

  dvec3 vertex_point(int32_t v, const dvec3& ring_sum) const {
    const dvec3& p0 = pos_[v];
    const int32_t n = valence_[v];
    auto smooth_point = [&]() {
      if (n == 0) return p0;
      const double inv_n = 1.0 / n;
      return (double(n - 2) * inv_n) * p0 + (inv_n * inv_n) * ring_sum;
    };
    const float corner = has_corners_ ? pvsharp_[v] : 0.0f;
    const bool has_sharp = !sharp_.empty();
    if (corner <= 0.0f && (!has_sharp || sharp_[v].parent_count < 2)) return smooth_point();
    const SharpSums ss = has_sharp ? sharp_[v] : SharpSums{};
    // A sharp vertex is a corner while its sharpness lasts.
    const float child_corner = child_sharpness(corner);
    const int parent_rule = corner > 0.0f ? 3 : rule_of(ss.parent_count);
    const int child_rule = child_corner > 0.0f ? 3 : rule_of(ss.child_count);
    auto point_for = [&](int rule, const dvec3& sharp_neighbours) {
      if (rule == 3) return p0;
      if (rule == 2) return 0.75 * p0 + 0.125 * sharp_neighbours;
      return smooth_point();
    };
    const dvec3 parent_point = point_for(parent_rule, ss.parent_neighbours);
    if (child_rule == parent_rule) return parent_point;
    // A semi-sharp feature relaxes in this level: blend by the average sharpness of the
    // edges that become smooth (OpenSubdiv's fractional weight, uniform creasing).
    double transition_sum = ss.transition_sum;
    int transition_count = ss.transition_count;
    if (corner > 0.0f && child_corner <= 0.0f) {
      transition_sum += corner;
      ++transition_count;
    }
    const double w = std::min(transition_count > 0 ? transition_sum / transition_count : 0.0, 1.0);
    return w * parent_point + (1.0 - w) * point_for(child_rule, ss.child_neighbours);
  }

  // The wings of the `n` child quads of the face whose uses are `face_loop_`, numbered from
  // `o`: quad i runs tail half of use i, interior edge i (edge point to face point),
  // interior edge i-1 backwards, head half of use i-1.
  void link_face_children(int32_t o, int32_t n) {
    Mesh& child = level_.mesh;
    FaceId* cuf = MeshAccess::use_faces(child).data();
    EdgeUse* cnext = MeshAccess::next(child).data();
    EdgeUse* cprev = is_intermediate_ ? nullptr : MeshAccess::prev(child).data();
    auto& cface_uses = MeshAccess::face_uses(child);
    // Half near the head of the previous use, and that use's side.
    const EdgeUse last = face_loop_[n - 1];
    const bool last_forward = (last.index & 1) == 0 || (pflags_[last.index >> 1] & mobius_flag_);
    int32_t prev_head_half = 2 * (last.index >> 1) + (last_forward ? 1 : 0);
    int32_t prev_side = last.index & 1;
    for (int32_t i = 0; i < n; ++i) {
      const EdgeUse u = face_loop_[i];
      const int32_t e = u.index >> 1;
      const int32_t s = u.index & 1;
      const bool is_forward = s == 0 || (pflags_[e] & mobius_flag_);
      const int32_t tail_half = 2 * e + (is_forward ? 0 : 1);
      const int32_t head_half = 2 * e + (is_forward ? 1 : 0);
      const int32_t q = o + i;
      const int32_t interior = 2 * E_ + o + i;
      const int32_t interior_prev = 2 * E_ + o + (i == 0 ? n - 1 : i - 1);
      const int32_t u0 = 2 * tail_half + s;
      const int32_t u1 = 2 * interior;
      const int32_t u2 = 2 * interior_prev + 1;
      const int32_t u3 = 2 * prev_head_half + prev_side;
      cuf[u0] = cuf[u1] = cuf[u2] = cuf[u3] = FaceId(q);
      cnext[u0] = EdgeUse(u1);
      cnext[u1] = EdgeUse(u2);
      cnext[u2] = EdgeUse(u3);
      cnext[u3] = EdgeUse(u0);
      if (cprev != nullptr) {
        cprev[u0] = EdgeUse(u3);
        cprev[u1] = EdgeUse(u0);
        cprev[u2] = EdgeUse(u1);
        cprev[u3] = EdgeUse(u2);
      }
      cface_uses.push_back(EdgeUse(u0));
      prev_head_half = head_half;
      prev_side = s;
    }
  }

  // (e) Each vertex point's first edge, and the child's border loops (not for an
  // intermediate child, which has no `prev` wings to link them in).
  void child_vertex_edges() {
    auto& cvertex_edges = MeshAccess::vertex_edges(level_.mesh);
    for (int32_t v = 0; v < V_; ++v) {
      const EdgeId a = p_.vertex_edge(VertexId(v));
      cvertex_edges[F_ + E_ + v] =
          a.is_valid() ? EdgeId(2 * a.index + (pev_[2 * a.index].index == v ? 0 : 1)) : EdgeId::None();
    }
    if (has_border_loops_ && !is_intermediate_) MeshAccess::link_borders(level_.mesh);
  }

  // Corner sharpness decays like crease sharpness; only vertex points inherit it. A level
  // where every crease has relaxed drops the property.
  void inherit_corners_and_creases() {
    if (has_corners_) {
      bool has_child_corners = false;
      for (int32_t v = 0; v < V_ && !has_child_corners; ++v) has_child_corners = child_sharpness(pvsharp_[v]) > 0.0f;
      if (has_child_corners) {
        auto& cvsharp = MeshAccess::vertex_sharpness(level_.mesh);
        cvsharp.assign(static_cast<size_t>(F_) + E_ + V_, 0.0f);
        for (int32_t v = 0; v < V_; ++v) cvsharp[F_ + E_ + v] = child_sharpness(pvsharp_[v]);
      }
    }
    if (has_creases_ && !has_child_creases_) MeshAccess::sharpness(level_.mesh).clear();
  }

  const Mesh& p_;
  const SubdivisionOptions& options_;
  const FaceInheritance inheritance_;
  const bool is_intermediate_;
  const bool has_border_loops_;
  bool stores_face_properties_;
  const int32_t F_, E_, V_;
  const std::vector<dvec3>& pos_;
  const std::vector<VertexId>& pev_;
  const OverwriteVector<FaceId>& puf_;
  const OverwriteVector<EdgeUse>& pnext_;
  const std::vector<uint8_t>& pflags_;
  const std::vector<float>& psharp_;
  const std::vector<float>& pvsharp_;
  const std::vector<EdgeUse>& pface_uses_;
  const uint8_t mobius_flag_;
  const bool has_creases_;
  const bool has_corners_;
  SubdivisionLevel level_;
  std::vector<dvec3>& cpos_;
  int32_t corner_total_ = 0;
  bool has_child_creases_ = false;
  std::vector<int32_t> valence_;    // per parent vertex, its number of edges
  std::vector<SharpSums> sharp_;    // per parent vertex, once some edge is sharp
  std::vector<EdgeUse> face_loop_;  // the uses of the face being split, reused
};

}  // namespace

namespace {

std::optional<KernelError> check_level_count(const SubdivisionOptions& options) {
  if (options.levels >= 0 && options.levels <= 12) return std::nullopt;
  return KernelError{KernelError::Kind::InvalidArgument, "subdivision level count must be between 0 and 12", {}, {}, {}};
}

// Refuses level `level` (1-based) of `from` when it would exceed `max_vertices`.
std::optional<KernelError> check_vertex_limit(const Mesh& from, int32_t level, const SubdivisionOptions& options) {
  const int64_t next_vertices = int64_t{from.vertex_count()} + from.edge_count() + from.face_count();
  if (options.max_vertices <= 0 || next_vertices <= options.max_vertices) return std::nullopt;
  return KernelError{KernelError::Kind::InvalidArgument,
                     fmt::format("subdivision level {} would have {} vertices, more than the {} allowed", level,
                                 next_vertices, options.max_vertices),
                     {},
                     {},
                     {}};
}

}  // namespace

SubdivisionLevel subdivide_once(const Mesh& parent, const SubdivisionOptions& options) {
  const FaceInheritance own{MeshAccess::face_sources(parent), MeshAccess::face_colors(parent), 0};
  return Refiner(parent, options, own, /*is_intermediate=*/false, !parent.border_loops().empty()).run();
}

Result<std::vector<SubdivisionLevel>> subdivide(const Mesh& mesh,
                                                const SubdivisionOptions& options) {
  if (auto error = check_level_count(options)) return *error;
  std::vector<SubdivisionLevel> levels;
  levels.reserve(options.levels);
  for (int32_t i = 0; i < options.levels; ++i) {
    const Mesh& from = i == 0 ? mesh : levels.back().mesh;
    if (auto error = check_vertex_limit(from, i + 1, options)) return *error;
    levels.push_back(subdivide_once(from, options));
  }
  return levels;
}

Result<Mesh> subdivide_last_level(Mesh mesh, const SubdivisionOptions& options) {
  if (auto error = check_level_count(options)) return *error;
  if (options.levels == 0) return mesh;
  SubdivisionOptions without_maps = options;
  without_maps.has_parent_maps = false;
  const bool has_border_loops = !mesh.border_loops().empty();
  // The faces' sources and colours leave the meshes: every level reads them from here.
  std::vector<FaceSource> sources = std::move(MeshAccess::face_sources(mesh));
  std::vector<glm::vec3> colors = std::move(MeshAccess::face_colors(mesh));
  FaceInheritance inheritance{sources, colors, 0};
  for (int32_t i = 0; i < options.levels; ++i) {
    if (auto error = check_vertex_limit(mesh, i + 1, options)) return *error;
    const bool is_last = i + 1 == options.levels;
    SubdivisionLevel child = Refiner(mesh, without_maps, inheritance, !is_last, has_border_loops).run();
    mesh = std::move(child.mesh);  // frees the parent
    if (is_last) break;
    if (child.are_parent_faces_quads) {
      inheritance.shift += 2;
    } else {  // the child stores its own (see `Refiner`)
      sources = std::move(MeshAccess::face_sources(mesh));
      colors = std::move(MeshAccess::face_colors(mesh));
      inheritance = FaceInheritance{sources, colors, 0};
    }
  }
  return mesh;
}

}  // namespace nomec::kernel
