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

}  // namespace

SubdivisionLevel subdivide_once(const Mesh& parent, const SubdivisionOptions& options) {
  const int32_t F = parent.face_count();
  const int32_t E = parent.edge_count();
  const int32_t V = parent.vertex_count();
  const std::vector<dvec3>& pos = parent.positions();
  const uint8_t mobius_flag = MeshAccess::mobius_flag();
  const Mesh& p = parent;
  const std::vector<VertexId>& pev = MeshAccess::edge_vertices(p);
  const std::vector<FaceId>& puf = MeshAccess::use_faces(p);
  const std::vector<EdgeUse>& pnext = MeshAccess::next(p);
  const std::vector<uint8_t>& pflags = MeshAccess::edge_flags(p);
  const std::vector<float>& psharp = MeshAccess::sharpness(p);
  const std::vector<EdgeUse>& pface_uses = MeshAccess::face_uses(p);

  // (1) Face loops and face points.
  std::vector<int32_t> face_offsets(static_cast<size_t>(F) + 1);
  std::vector<EdgeUse> uses;
  uses.reserve(2 * static_cast<size_t>(E));
  SubdivisionLevel level;
  Mesh& child = level.mesh;
  std::vector<dvec3>& cpos = MeshAccess::positions(child);
  cpos.resize(static_cast<size_t>(F) + E + V);  // zero-initialised
  // The vertex-point slots first accumulate the face points around each vertex (3b),
  // done here while the face's uses are still in cache.
  dvec3* vertex_points = cpos.data() + F + E;
  for (int32_t f = 0; f < F; ++f) {
    const int32_t o = static_cast<int32_t>(uses.size());
    face_offsets[f] = o;
    dvec3 sum(0.0);
    const EdgeUse start = pface_uses[f];
    EdgeUse u = start;
    do {
      uses.push_back(u);
      const int32_t e = u.index >> 1;
      const bool is_forward = (u.index & 1) == 0 || (pflags[e] & mobius_flag);
      sum += pos[pev[2 * e + (is_forward ? 0 : 1)].index];
      u = pnext[u.index];
    } while (u != start);
    const int32_t n = static_cast<int32_t>(uses.size()) - o;
    const dvec3 fp = sum / double(n);
    cpos[f] = fp;
    for (int32_t i = o; i < o + n; ++i) {
      const int32_t e = uses[i].index >> 1;
      const bool is_forward = (uses[i].index & 1) == 0 || (pflags[e] & mobius_flag);
      vertex_points[pev[2 * e + (is_forward ? 0 : 1)].index] += fp;
    }
  }
  const int32_t corner_total = static_cast<int32_t>(uses.size());
  face_offsets[F] = corner_total;

  // Does any edge need the sharp rules? Plain Catmull-Clark ignores creases and corners
  // (boundaries stay sharp).
  const bool has_creases = options.is_sharpness_honoured && !psharp.empty();
  const std::vector<float>& pvsharp = MeshAccess::vertex_sharpness(p);
  const bool has_corners = options.is_sharpness_honoured && !pvsharp.empty();
  bool has_sharp = false;
  for (int32_t e = 0; e < E && !has_sharp; ++e) {
    has_sharp = !puf[2 * e + 1].is_valid() || (has_creases && psharp[e] > 0.0f);
  }

  // (2) Edge points, and (3a) per-vertex sums over edges.
  const bool is_derose = options.vertex_rule == VertexRule::DeRose;
  // Per vertex: sum of the other ends of its edges (or of its edge points, DeRose) and its
  // valence, side by side so each scatter touches one cache line.
  struct EdgeSums {
    dvec3 neighbours{0.0};
    double valence = 0.0;
  };
  std::vector<EdgeSums> edge_sums(V);
  std::vector<SharpSums> sharp;
  if (has_sharp) {
    sharp.resize(V);
  }
  dvec3* edge_points = cpos.data() + F;
  for (int32_t e = 0; e < E; ++e) {
    const int32_t a = pev[2 * e].index;
    const int32_t b = pev[2 * e + 1].index;
    const dvec3& pa = pos[a];
    const dvec3& pb = pos[b];
    const bool is_boundary = !puf[2 * e + 1].is_valid();
    const float s = is_boundary ? kInfiniteSharpness : (has_creases ? psharp[e] : 0.0f);
    dvec3 point;
    if (s >= 1.0f) {
      point = 0.5 * (pa + pb);
    } else {
      const dvec3 smooth = 0.25 * (pa + pb + cpos[puf[2 * e].index] + cpos[puf[2 * e + 1].index]);
      point = s <= 0.0f ? smooth : double(s) * (0.5 * (pa + pb)) + (1.0 - double(s)) * smooth;
    }
    edge_points[e] = point;
    EdgeSums& sa = edge_sums[a];
    EdgeSums& sb = edge_sums[b];
    sa.valence += 1.0;
    sb.valence += 1.0;
    if (is_derose) {
      sa.neighbours += point;
      sb.neighbours += point;
    } else {
      sa.neighbours += pb;
      sb.neighbours += pa;
    }
    if (s > 0.0f) {
      const float cs = child_sharpness(s);
      for (int end = 0; end < 2; ++end) {
        SharpSums& ss = sharp[end == 0 ? a : b];
        const dvec3& other = end == 0 ? pb : pa;
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
  }

  const dvec3* face_sum = vertex_points;

  // (3c) Vertex points (overwriting each vertex's face-point sum once it is read).
  for (int32_t v = 0; v < V; ++v) {
    const dvec3& p0 = pos[v];
    const int32_t n = static_cast<int32_t>(edge_sums[v].valence);
    auto smooth_point = [&]() {
      if (n == 0) {
        return p0;
      }
      const double inv_n = 1.0 / n;
      return (double(n - 2) * inv_n) * p0 +
             (inv_n * inv_n) * (edge_sums[v].neighbours + face_sum[v]);
    };
    const float corner = has_corners ? pvsharp[v] : 0.0f;
    if (corner <= 0.0f && (!has_sharp || sharp[v].parent_count < 2)) {
      vertex_points[v] = smooth_point();
      continue;
    }
    const SharpSums ss = has_sharp ? sharp[v] : SharpSums{};
    // A sharp vertex is a corner while its sharpness lasts.
    const float child_corner = child_sharpness(corner);
    const int parent_rule = corner > 0.0f ? 3 : rule_of(ss.parent_count);
    const int child_rule = child_corner > 0.0f ? 3 : rule_of(ss.child_count);
    auto point_for = [&](int rule, const dvec3& sharp_neighbours) {
      if (rule == 3) {
        return p0;
      }
      if (rule == 2) {
        return 0.75 * p0 + 0.125 * sharp_neighbours;
      }
      return smooth_point();
    };
    const dvec3 parent_point = point_for(parent_rule, ss.parent_neighbours);
    if (child_rule == parent_rule) {
      vertex_points[v] = parent_point;
      continue;
    }
    // A semi-sharp feature relaxes in this level: blend by the average sharpness of the
    // edges that become smooth (OpenSubdiv's fractional weight, uniform creasing).
    double transition_sum = ss.transition_sum;
    int transition_count = ss.transition_count;
    if (corner > 0.0f && child_corner <= 0.0f) {
      transition_sum += corner;
      ++transition_count;
    }
    double w = transition_count > 0 ? transition_sum / transition_count : 0.0;
    w = std::min(w, 1.0);
    vertex_points[v] = w * parent_point + (1.0 - w) * point_for(child_rule, ss.child_neighbours);
  }

  // (4) Child topology.
  const int32_t cE = 2 * E + corner_total;
  const int32_t cF = corner_total;
  auto& cev = MeshAccess::edge_vertices(child);
  auto& cuf = MeshAccess::use_faces(child);
  auto& cnext = MeshAccess::next(child);
  auto& cprev = MeshAccess::prev(child);
  auto& cflags = MeshAccess::edge_flags(child);
  auto& csharp = MeshAccess::sharpness(child);
  auto& cface_uses = MeshAccess::face_uses(child);
  auto& csources = MeshAccess::face_sources(child);
  auto& cvertex_edges = MeshAccess::vertex_edges(child);
  // Arrays written in index order are filled by push_back (one pass over the memory);
  // the per-use arrays are written out of order and are sized up front.
  cev.reserve(2 * static_cast<size_t>(cE));
  cuf.resize(2 * static_cast<size_t>(cE));
  cnext.resize(2 * static_cast<size_t>(cE));
  cprev.resize(2 * static_cast<size_t>(cE));
  cflags.reserve(cE);
  bool has_child_creases = false;
  if (has_creases) {
    csharp.reserve(cE);
  }
  cface_uses.reserve(cF);
  csources.reserve(cF);
  cvertex_edges.resize(static_cast<size_t>(F) + E + V);
  const bool has_colors = parent.has_face_colors();
  if (has_colors) {
    MeshAccess::face_colors(child).resize(cF);
  }
  const int32_t vp_base = F + E;

  for (int32_t e = 0; e < E; ++e) {
    const int32_t h0 = 2 * e;
    const int32_t h1 = 2 * e + 1;
    cev.push_back(VertexId(vp_base + pev[2 * e].index));
    cev.push_back(VertexId(F + e));
    cev.push_back(VertexId(F + e));
    cev.push_back(VertexId(vp_base + pev[2 * e + 1].index));
    cflags.push_back(pflags[e]);
    cflags.push_back(pflags[e]);
    if (has_creases) {
      const float cs = child_sharpness(psharp[e]);
      csharp.push_back(cs);
      csharp.push_back(cs);
      has_child_creases = has_child_creases || cs > 0.0f;
    }
    if (!puf[2 * e + 1].is_valid()) {
      cuf[2 * h0 + 1] = FaceId::None();
      cuf[2 * h1 + 1] = FaceId::None();
    }
    cvertex_edges[F + e] = EdgeId(h0);
  }

  for (int32_t f = 0; f < F; ++f) {
    const int32_t o = face_offsets[f];
    const int32_t n = face_offsets[f + 1] - o;
    const FaceSource source = parent.face_source(FaceId(f));
    cvertex_edges[f] = EdgeId(2 * E + o);
    // Half near the head of the previous use, and that use's side.
    EdgeUse last = uses[o + n - 1];
    bool last_forward = (last.index & 1) == 0 || (pflags[last.index >> 1] & mobius_flag);
    int32_t prev_head_half = 2 * (last.index >> 1) + (last_forward ? 1 : 0);
    int32_t prev_side = last.index & 1;
    for (int32_t i = 0; i < n; ++i) {
      const EdgeUse u = uses[o + i];
      const int32_t e = u.index >> 1;
      const int32_t s = u.index & 1;
      const bool is_forward = s == 0 || (pflags[e] & mobius_flag);
      const int32_t tail_half = 2 * e + (is_forward ? 0 : 1);
      const int32_t head_half = 2 * e + (is_forward ? 1 : 0);
      const int32_t q = o + i;
      const int32_t interior = 2 * E + o + i;
      const int32_t interior_prev = 2 * E + o + (i == 0 ? n - 1 : i - 1);
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
      cev.push_back(VertexId(F + e));
      cev.push_back(VertexId(f));
      cflags.push_back(0);
      if (has_creases) {
        csharp.push_back(0.0f);
      }
      csources.push_back(source);
      prev_head_half = head_half;
      prev_side = s;
    }
    if (has_colors) {
      std::fill_n(MeshAccess::face_colors(child).begin() + o, n, parent.face_color(FaceId(f)));
    }
  }

  for (int32_t v = 0; v < V; ++v) {
    const EdgeId a = parent.vertex_edge(VertexId(v));
    cvertex_edges[vp_base + v] =
        a.is_valid() ? EdgeId(2 * a.index + (pev[2 * a.index].index == v ? 0 : 1)) : EdgeId::None();
  }

  if (!parent.border_loops().empty()) {
    MeshAccess::link_borders(child);
  }

  if (has_corners) {
    // Corner sharpness decays like crease sharpness; only vertex points inherit it.
    bool has_child_corners = false;
    for (int32_t v = 0; v < V && !has_child_corners; ++v) {
      has_child_corners = child_sharpness(pvsharp[v]) > 0.0f;
    }
    if (has_child_corners) {
      auto& cvsharp = MeshAccess::vertex_sharpness(child);
      cvsharp.assign(static_cast<size_t>(F) + E + V, 0.0f);
      for (int32_t v = 0; v < V; ++v) {
        cvsharp[vp_base + v] = child_sharpness(pvsharp[v]);
      }
    }
  }
  if (has_creases && !has_child_creases) {
    csharp.clear();  // every crease has relaxed; drop the property
  }

  level.parent_face_count = F;
  level.parent_edge_count = E;
  if (options.has_parent_maps) {
    level.face_parents.resize(cF);
    for (int32_t f = 0; f < F; ++f) {
      std::fill(level.face_parents.begin() + face_offsets[f],
                level.face_parents.begin() + face_offsets[f + 1], FaceId(f));
    }
  }
  return level;
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
