// Catmull-Clark refinement of one level, written as a few linear passes over flat
// arrays: (1) walk every face once to record its uses and face point, (2) edge points,
// (3) scatter per-vertex sums (neighbours, face points, sharp neighbours) from edges and
// face corners, then apply the corner / crease / smooth rule, (4) build the child
// winged-edge topology arithmetically (the child IDs of every parent element are known
// in advance, see `SubdivisionLevel`), so no hashing is needed.
//
// Vertex rules follow the seed (§4.1.3) and coincide with OpenSubdiv's Catmark scheme
// with edge-only boundary interpolation and uniform creasing, including the blend used
// when a semi-sharp crease becomes smooth in the child level.
#include "kernel/subdivide.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

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

// One level of refinement as named passes over the parent's flat arrays (see the top of
// the file); the passes share the parent's arrays and the child being built.
class Refiner {
 public:
  Refiner(const Mesh& parent, const SubdivisionOptions& options)
      : p_(parent),
        options_(options),
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
        cpos_(MeshAccess::positions(level_.mesh)) {
    cpos_.resize(static_cast<size_t>(F_) + E_ + V_);  // zero-initialised
  }

  SubdivisionLevel run() {
    face_points();
    find_sharp_edges();
    edge_points();
    vertex_points();
    child_edges_of_parent_edges();
    child_faces();
    child_vertex_edges();
    inherit_corners_and_creases();
    parent_maps();
    return std::move(level_);
  }

 private:
  struct EdgeSums {
    dvec3 neighbours{0.0};
    double valence = 0.0;
  };

  // The vertex whose position starts use `u` (Möbius edges are read forwards on both sides).
  int32_t tail_of(EdgeUse u) const {
    const int32_t e = u.index >> 1;
    const bool is_forward = (u.index & 1) == 0 || (pflags_[e] & mobius_flag_);
    return pev_[2 * e + (is_forward ? 0 : 1)].index;
  }

  // (1) Face loops and face points. The vertex-point slots first accumulate the face points
  // around each vertex (3b), done here while the face's uses are still in cache.
  void face_points() {
    face_offsets_.resize(static_cast<size_t>(F_) + 1);
    uses_.reserve(2 * static_cast<size_t>(E_));
    dvec3* vertex_points = cpos_.data() + F_ + E_;
    for (int32_t f = 0; f < F_; ++f) {
      const int32_t o = static_cast<int32_t>(uses_.size());
      face_offsets_[f] = o;
      dvec3 sum(0.0);
      const EdgeUse start = pface_uses_[f];
      EdgeUse u = start;
      do {
        uses_.push_back(u);
        sum += pos_[tail_of(u)];
        u = pnext_[u.index];
      } while (u != start);
      const int32_t n = static_cast<int32_t>(uses_.size()) - o;
      const dvec3 fp = sum / double(n);
      cpos_[f] = fp;
      for (int32_t i = o; i < o + n; ++i) vertex_points[tail_of(uses_[i])] += fp;
    }
    corner_total_ = static_cast<int32_t>(uses_.size());
    face_offsets_[F_] = corner_total_;
  }

  // Does any edge need the sharp rules? Plain Catmull-Clark ignores creases and corners
  // (boundaries stay sharp).
  void find_sharp_edges() {
    for (int32_t e = 0; e < E_ && !has_sharp_; ++e) {
      has_sharp_ = !puf_[2 * e + 1].is_valid() || (has_creases_ && psharp_[e] > 0.0f);
    }
    if (has_sharp_) sharp_.resize(V_);
  }

  // (2) Edge points, and (3a) per-vertex sums over edges: the other ends of a vertex's
  // edges (or its edge points, DeRose) and its valence, side by side so each scatter
  // touches one cache line.
  void edge_points() {
    const bool is_derose = options_.vertex_rule == VertexRule::DeRose;
    edge_sums_.resize(V_);
    dvec3* edge_points = cpos_.data() + F_;
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
      EdgeSums& sa = edge_sums_[a];
      EdgeSums& sb = edge_sums_[b];
      sa.valence += 1.0;
      sb.valence += 1.0;
      if (is_derose) {
        sa.neighbours += point;
        sb.neighbours += point;
      } else {
        sa.neighbours += pb;
        sb.neighbours += pa;
      }
      if (s > 0.0f) add_sharp_edge(a, b, s);
    }
  }

  void add_sharp_edge(int32_t a, int32_t b, float s) {
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

  // (3c) Vertex points, overwriting each vertex's face-point sum once it is read.
  void vertex_points() {
    dvec3* vertex_points = cpos_.data() + F_ + E_;
    for (int32_t v = 0; v < V_; ++v) vertex_points[v] = vertex_point(v, vertex_points[v]);
  }

  dvec3 vertex_point(int32_t v, const dvec3& face_sum) const {
    const dvec3& p0 = pos_[v];
    const int32_t n = static_cast<int32_t>(edge_sums_[v].valence);
    auto smooth_point = [&]() {
      if (n == 0) return p0;
      const double inv_n = 1.0 / n;
      return (double(n - 2) * inv_n) * p0 + (inv_n * inv_n) * (edge_sums_[v].neighbours + face_sum);
    };
    const float corner = has_corners_ ? pvsharp_[v] : 0.0f;
    if (corner <= 0.0f && (!has_sharp_ || sharp_[v].parent_count < 2)) return smooth_point();
    const SharpSums ss = has_sharp_ ? sharp_[v] : SharpSums{};
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

  // (4a) The two child edges of every parent edge (edge 2e from its tail's vertex point to
  // the edge point, 2e+1 on to its head's). Arrays written in index order are filled by
  // push_back (one pass over the memory); the per-use arrays are written out of order and
  // are sized up front.
  void child_edges_of_parent_edges() {
    Mesh& child = level_.mesh;
    const int32_t cE = 2 * E_ + corner_total_;
    auto& cev = MeshAccess::edge_vertices(child);
    auto& cuf = MeshAccess::use_faces(child);
    auto& cflags = MeshAccess::edge_flags(child);
    auto& csharp = MeshAccess::sharpness(child);
    cev.reserve(2 * static_cast<size_t>(cE));
    cuf.resize(2 * static_cast<size_t>(cE));
    MeshAccess::next(child).resize(2 * static_cast<size_t>(cE));
    MeshAccess::prev(child).resize(2 * static_cast<size_t>(cE));
    cflags.reserve(cE);
    if (has_creases_) csharp.reserve(cE);
    MeshAccess::vertex_edges(child).resize(static_cast<size_t>(F_) + E_ + V_);
    const int32_t vp_base = F_ + E_;
    for (int32_t e = 0; e < E_; ++e) {
      const int32_t h0 = 2 * e;
      const int32_t h1 = 2 * e + 1;
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
      if (!puf_[2 * e + 1].is_valid()) {
        cuf[2 * h0 + 1] = FaceId::None();
        cuf[2 * h1 + 1] = FaceId::None();
      }
      MeshAccess::vertex_edges(child)[F_ + e] = EdgeId(h0);
    }
  }

  // (4b) One child quad per face corner, with its interior edge from the edge point to the
  // face point; wings are known arithmetically, so no hashing.
  void child_faces() {
    Mesh& child = level_.mesh;
    auto& cev = MeshAccess::edge_vertices(child);
    auto& cuf = MeshAccess::use_faces(child);
    auto& cnext = MeshAccess::next(child);
    auto& cprev = MeshAccess::prev(child);
    auto& cflags = MeshAccess::edge_flags(child);
    auto& csharp = MeshAccess::sharpness(child);
    auto& cface_uses = MeshAccess::face_uses(child);
    auto& csources = MeshAccess::face_sources(child);
    cface_uses.reserve(corner_total_);
    csources.reserve(corner_total_);
    const bool has_colors = p_.has_face_colors();
    if (has_colors) MeshAccess::face_colors(child).resize(corner_total_);
    for (int32_t f = 0; f < F_; ++f) {
      const int32_t o = face_offsets_[f];
      const int32_t n = face_offsets_[f + 1] - o;
      const FaceSource source = p_.face_source(FaceId(f));
      MeshAccess::vertex_edges(child)[f] = EdgeId(2 * E_ + o);
      // Half near the head of the previous use, and that use's side.
      const EdgeUse last = uses_[o + n - 1];
      const bool last_forward = (last.index & 1) == 0 || (pflags_[last.index >> 1] & mobius_flag_);
      int32_t prev_head_half = 2 * (last.index >> 1) + (last_forward ? 1 : 0);
      int32_t prev_side = last.index & 1;
      for (int32_t i = 0; i < n; ++i) {
        const EdgeUse u = uses_[o + i];
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
        cprev[u0] = EdgeUse(u3);
        cprev[u1] = EdgeUse(u0);
        cprev[u2] = EdgeUse(u1);
        cprev[u3] = EdgeUse(u2);
        cface_uses.push_back(EdgeUse(u0));
        cev.push_back(VertexId(F_ + e));
        cev.push_back(VertexId(f));
        cflags.push_back(0);
        if (has_creases_) csharp.push_back(0.0f);
        csources.push_back(source);
        prev_head_half = head_half;
        prev_side = s;
      }
      if (has_colors) std::fill_n(MeshAccess::face_colors(child).begin() + o, n, p_.face_color(FaceId(f)));
    }
  }

  // (4c) Each vertex point's first edge, and the child's border loops.
  void child_vertex_edges() {
    auto& cvertex_edges = MeshAccess::vertex_edges(level_.mesh);
    for (int32_t v = 0; v < V_; ++v) {
      const EdgeId a = p_.vertex_edge(VertexId(v));
      cvertex_edges[F_ + E_ + v] =
          a.is_valid() ? EdgeId(2 * a.index + (pev_[2 * a.index].index == v ? 0 : 1)) : EdgeId::None();
    }
    if (!p_.border_loops().empty()) MeshAccess::link_borders(level_.mesh);
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

  void parent_maps() {
    level_.parent_face_count = F_;
    level_.parent_edge_count = E_;
    if (!options_.has_parent_maps) return;
    level_.face_parents.resize(corner_total_);
    for (int32_t f = 0; f < F_; ++f) {
      std::fill(level_.face_parents.begin() + face_offsets_[f], level_.face_parents.begin() + face_offsets_[f + 1],
                FaceId(f));
    }
  }

  const Mesh& p_;
  const SubdivisionOptions& options_;
  const int32_t F_, E_, V_;
  const std::vector<dvec3>& pos_;
  const std::vector<VertexId>& pev_;
  const std::vector<FaceId>& puf_;
  const std::vector<EdgeUse>& pnext_;
  const std::vector<uint8_t>& pflags_;
  const std::vector<float>& psharp_;
  const std::vector<float>& pvsharp_;
  const std::vector<EdgeUse>& pface_uses_;
  const uint8_t mobius_flag_;
  const bool has_creases_;
  const bool has_corners_;
  SubdivisionLevel level_;
  std::vector<dvec3>& cpos_;
  std::vector<int32_t> face_offsets_;  // per face, its first corner in `uses_`
  std::vector<EdgeUse> uses_;          // every face's uses, face by face
  int32_t corner_total_ = 0;
  bool has_sharp_ = false;
  bool has_child_creases_ = false;
  std::vector<EdgeSums> edge_sums_;
  std::vector<SharpSums> sharp_;
};

}  // namespace

SubdivisionLevel subdivide_once(const Mesh& parent, const SubdivisionOptions& options) {
  return Refiner(parent, options).run();
}

Result<std::vector<SubdivisionLevel>> subdivide(const Mesh& mesh,
                                                const SubdivisionOptions& options) {
  if (options.levels < 0 || options.levels > 12) {
    return KernelError{KernelError::Kind::InvalidArgument,
                       "subdivision level count must be between 0 and 12",
                       {},
                       {},
                       {}};
  }
  std::vector<SubdivisionLevel> levels;
  levels.reserve(options.levels);
  for (int32_t i = 0; i < options.levels; ++i) {
    const Mesh& from = i == 0 ? mesh : levels.back().mesh;
    const int64_t next_vertices = int64_t{from.vertex_count()} + from.edge_count() + from.face_count();
    if (options.max_vertices > 0 && next_vertices > options.max_vertices) {
      return KernelError{KernelError::Kind::InvalidArgument,
                         fmt::format("subdivision level {} would have {} vertices, more than the {} allowed", i + 1,
                                     next_vertices, options.max_vertices),
                         {},
                         {},
                         {}};
    }
    levels.push_back(subdivide_once(from, options));
  }
  return levels;
}

}  // namespace nomec::kernel
