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
#include <array>
#include <atomic>
#include <cmath>
#include <optional>
#include <span>
#include <glm/geometric.hpp>

#include "kernel/large_arrays.h"
#include "base/two_threads.h"

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

// The parent elements one part of a level's passes handles, and what it found. With one
// part it is every element; with two, part 0 has the faces below the middle face (and the
// edges whose first face is one of them), part 1 the others, and each has half of the
// edges for the child edge halves and half of the vertices.
struct Part {
  int32_t face_begin = 0, face_end = 0;
  int32_t edge_begin = 0, edge_end = 0;  // for the child edge halves and `scan_edges`
  int32_t vertex_begin = 0, vertex_end = 0;
  int index = 0;                 // in `Refiner::parts_`
  int32_t first_child_face = 0;  // the first child of face `face_begin`
  // Counted by `scan_edges` over its edges.
  int64_t border_edges = 0;
  int64_t first_part_uses = 0;  // uses whose face belongs to part 0
  bool has_sharp_edges = false;
  // Found by the passes.
  bool are_quads = true;
  bool has_child_creases = false;
  std::vector<EdgeUse> face_loop;   // the uses of a face that is not a quad, reused
  std::vector<int32_t> face_tails;  // and their tail vertices
  // Contributions to the sums of vertices that both parts touch, which are added after
  // both parts, in the order one pass would add them: (vertex, face) of face points, and
  // 2 * edge + end of edge ends.
  std::vector<std::pair<int32_t, int32_t>> deferred_face_points;
  std::vector<int32_t> deferred_edge_ends;
};

// One level of refinement as named passes over the parent's flat arrays (see the top of
// the file); the passes share the parent's arrays and the child being built. Every child
// array is allocated once at its exact size, and the only scratch memory is a valence per
// parent vertex (plus `SharpSums` when there are sharp edges, and with two threads two
// bytes per parent vertex).
//
// Two threads (`Part`): every child element is written by one part, at an index known in
// advance, so the parts never write the same memory — except the vertex points' slots,
// which accumulate sums whose rounding depends on the order of the terms. A vertex that
// the faces of only one part touch gets its terms from that part alone, in one pass's
// order; for a vertex that faces of both parts touch (the seam between the two face
// ranges: a few per cent of the vertices of a mesh whose faces are numbered with some
// locality) both parts set the terms aside and they are added afterwards in one pass's
// order. So the child is the same bit for bit as with one thread.
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
        is_derose_(options.vertex_rule == VertexRule::DeRose),
        cpos_(MeshAccess::positions(level_.mesh)) {}

  SubdivisionLevel run() {
    const bool is_split = options_.threading == Threading::TwoThreads ||
                          (options_.threading == Threading::Automatic && E_ >= kTwoThreadEdges &&
                           has_two_hardware_threads());
    if (is_split) {
      run_split();
    } else {
      run_whole();
    }
    inherit_corners_and_creases();
    level_.parent_face_count = F_;
    level_.parent_edge_count = E_;
    return std::move(level_);
  }

 private:
  // The passes on one thread: one part with every element.
  void run_whole() {
    parts_.resize(1);
    Part& p = parts_[0];
    p.face_end = F_;
    p.edge_end = E_;
    p.vertex_end = V_;
    allocate_positions();
    scan_edges(p);
    allocate_child();
    child_edge_halves(p);
    faces(p);
    after_faces();
    edge_points(p);
    vertex_points(p);
    child_vertex_edges(p);
    after_vertices();
  }

  // The passes on two threads, joined between passes; what remains in between (adding the
  // terms set aside, allocating) runs on the calling thread.
  void run_split() {
    parts_.resize(2);
    parts_[1].index = 1;
    middle_face_ = F_ / 2;
    parts_[0].face_end = parts_[1].face_begin = middle_face_;
    parts_[1].face_end = F_;
    parts_[0].edge_end = parts_[1].edge_begin = E_ / 2;
    parts_[1].edge_end = E_;
    parts_[0].vertex_end = parts_[1].vertex_begin = V_ / 2;
    parts_[1].vertex_end = V_;
    touched_.assign(V_, {0, 0});
    allocate_positions();
    run_two_parts([&](int k) { scan_edges(parts_[k]); });
    parts_[1].first_child_face = static_cast<int32_t>(parts_[0].first_part_uses + parts_[1].first_part_uses);
    allocate_child();
    run_two_parts([&](int k) {
      child_edge_halves(parts_[k]);
      faces(parts_[k]);
    });
    after_faces();
    run_two_parts([&](int k) { edge_points(parts_[k]); });
    add_deferred_edge_ends();
    run_two_parts([&](int k) {
      vertex_points(parts_[k]);
      child_vertex_edges(parts_[k]);
    });
    after_vertices();
  }

  // The vertex whose position starts use `u` (Möbius edges are read forwards on both sides).
  int32_t tail_of(EdgeUse u) const {
    const int32_t e = u.index >> 1;
    const bool is_forward = (u.index & 1) == 0 || (pflags_[e] & mobius_flag_);
    return pev_[2 * e + (is_forward ? 0 : 1)].index;
  }

  // The part whose faces include `f` (two parts: below the middle face or not).
  int part_of(FaceId f) const { return f.index < middle_face_ ? 0 : 1; }

  // True if faces of both parts touch vertex `v` (never with one part).
  bool is_shared(int32_t v) const {
    if (touched_.empty()) return false;
    const std::array<uint8_t, 2>& t = touched_[v];
    return (t[0] & t[1]) != 0;
  }

  // Marks vertex `v` as touched by part `k` (both threads may mark the same vertex).
  void touch(int32_t v, int k) { std::atomic_ref<uint8_t>(touched_[v][k]).store(1, std::memory_order_relaxed); }

  // (a) Zeros in the slots of the part's vertex points. Every use of an edge belongs to a
  // face except the second side of a border edge, so the parent has 2E minus its border
  // edges corners (= child faces); whether some edge is sharp (then every vertex gets
  // `SharpSums`). With two parts also which part's faces touch each vertex (both ends of
  // each of their edges) and how many corners part 0 has.
  void scan_edges(Part& p) {
    dvec3* vertex_points = cpos_.data() + F_ + E_;
    std::fill(vertex_points + p.vertex_begin, vertex_points + p.vertex_end, dvec3(0.0));
    const bool is_split = !touched_.empty();
    for (int32_t e = p.edge_begin; e < p.edge_end; ++e) {
      const FaceId fb = puf_[2 * e + 1];
      const bool is_border = !fb.is_valid();
      p.border_edges += is_border ? 1 : 0;
      p.has_sharp_edges = p.has_sharp_edges || is_border || (has_creases_ && psharp_[e] > 0.0f);
      if (!is_split) continue;
      const int32_t a = pev_[2 * e].index;
      const int32_t b = pev_[2 * e + 1].index;
      for (const FaceId f : {puf_[2 * e], fb}) {
        if (!f.is_valid()) continue;
        const int k = part_of(f);
        touch(a, k);
        touch(b, k);
        p.first_part_uses += k == 0 ? 1 : 0;
      }
    }
  }

  // The child's positions: face points, edge points, then vertex points. Only the vertex
  // points' slots, which accumulate sums, need zeros: each part writes them for its
  // vertices in `scan_edges` (the other positions are written once each by the passes).
  void allocate_positions() { resize_for_overwrite(cpos_, static_cast<size_t>(F_) + E_ + V_); }

  // Every other child array at its exact size, before the passes write them by index:
  // without a fill where every element is then written (`OverwriteVector`), zeroed where
  // the passes write only some elements (creases).
  void allocate_child() {
    int64_t border_edges = 0;
    bool has_sharp_edges = false;
    for (const Part& p : parts_) {
      border_edges += p.border_edges;
      has_sharp_edges = has_sharp_edges || p.has_sharp_edges;
    }
    corner_total_ = static_cast<int32_t>(2 * int64_t{E_} - border_edges);
    Mesh& child = level_.mesh;
    const size_t cE = 2 * static_cast<size_t>(E_) + corner_total_;
    resize_for_overwrite(MeshAccess::edge_vertices(child), 2 * cE);
    // Every element of these is written by `faces` (the uses of the faces) or by
    // `child_edge_halves` (the unused side of a border edge); vertex anchors by `faces`
    // (face points), `child_edge_halves` (edge points) and `child_vertex_edges`.
    resize_for_overwrite(MeshAccess::use_faces(child), 2 * cE);
    resize_for_overwrite(MeshAccess::next(child), 2 * cE);
    if (!is_intermediate_) resize_for_overwrite(MeshAccess::prev(child), 2 * cE);
    resize_for_overwrite(MeshAccess::edge_flags(child), cE);
    if (has_creases_) resize_large(MeshAccess::sharpness(child), cE);  // the faces' edges are smooth
    resize_for_overwrite(MeshAccess::vertex_edges(child), static_cast<size_t>(F_) + E_ + V_);
    resize_for_overwrite(MeshAccess::face_uses(child), corner_total_);
    if (stores_face_properties_) allocate_face_properties();
    valence_.assign(V_, 0);
    if (has_sharp_edges) sharp_.resize(V_);
  }

  void allocate_face_properties() {
    resize_for_overwrite(MeshAccess::face_sources(level_.mesh), corner_total_);  // all written
    if (!inheritance_.colors.empty()) resize_large(MeshAccess::face_colors(level_.mesh), corner_total_);
  }

  // (b) The two child edges of every parent edge (edge 2e from its tail's vertex point to
  // the edge point, 2e+1 on to its head's), which depend on the parent's edges alone.
  void child_edge_halves(Part& p) {
    Mesh& child = level_.mesh;
    VertexId* cev = MeshAccess::edge_vertices(child).data();
    FaceId* cuf = MeshAccess::use_faces(child).data();
    EdgeUse* cnext = MeshAccess::next(child).data();
    EdgeUse* cprev = is_intermediate_ ? nullptr : MeshAccess::prev(child).data();
    uint8_t* cflags = MeshAccess::edge_flags(child).data();
    float* csharp = MeshAccess::sharpness(child).data();
    EdgeId* cvertex_edges = MeshAccess::vertex_edges(child).data();
    const int32_t vp_base = F_ + E_;
    for (int32_t e = p.edge_begin; e < p.edge_end; ++e) {
      cev[4 * e] = VertexId(vp_base + pev_[2 * e].index);
      cev[4 * e + 1] = VertexId(F_ + e);
      cev[4 * e + 2] = VertexId(F_ + e);
      cev[4 * e + 3] = VertexId(vp_base + pev_[2 * e + 1].index);
      cflags[2 * e] = cflags[2 * e + 1] = pflags_[e];
      if (has_creases_) {
        const float cs = child_sharpness(psharp_[e]);
        csharp[2 * e] = csharp[2 * e + 1] = cs;
        p.has_child_creases = p.has_child_creases || cs > 0.0f;
      }
      if (!puf_[2 * e + 1].is_valid()) {  // no wings yet; `link_borders` may add some
        for (const int32_t u : {4 * e + 1, 4 * e + 3}) {
          cuf[u] = FaceId::None();
          cnext[u] = EdgeUse::None();
          if (cprev != nullptr) cprev[u] = EdgeUse::None();
        }
      }
      cvertex_edges[F_ + e] = EdgeId(2 * e);
    }
  }

  // (c) One walk around every parent face: its face point, added to the slots of its
  // vertices' points (each slot starts as the sum of the face points around the vertex),
  // and its child quads with their interior edges (from the edge point to the face point),
  // whose wings are known arithmetically, so no hashing.
  //
  // The walk is a chain of dependent loads (each use's successor, then its tail vertex),
  // which the processor cannot overlap with the next face's while the long work of a face
  // stands in between. So the faces go in blocks: first the uses and tail vertices of every
  // quad of the block, a short loop whose faces' chains the processor runs side by side
  // (asking on the way for the edges' vertices and flags, then for the tails' positions
  // and vertex-point slots and for the child's wings at the edges' halves, which the work
  // writes in scattered places), then the work of each face from those. A face that is not
  // a quad is walked on its own.
  void faces(Part& p) {
    constexpr int32_t kBlock = 64;
    std::array<EdgeUse, 4 * kBlock> uses;
    std::array<int32_t, 4 * kBlock> tails;
    std::array<bool, kBlock> is_quad;
    std::vector<EdgeUse>& loop = p.face_loop;
    int32_t o = p.first_child_face;
    const Mesh& child = level_.mesh;
    const FaceId* cuf = MeshAccess::use_faces(child).data();
    const EdgeUse* cnext = MeshAccess::next(child).data();
    const EdgeUse* cprev = is_intermediate_ ? nullptr : MeshAccess::prev(child).data();
    for (int32_t begin = p.face_begin; begin < p.face_end; begin += kBlock) {
      const int32_t count = std::min(kBlock, p.face_end - begin);
      for (int32_t i = 0; i < count; ++i) {
        const EdgeUse u0 = pface_uses_[begin + i];
        const EdgeUse u1 = pnext_[u0.index];
        const EdgeUse u2 = pnext_[u1.index];
        const EdgeUse u3 = pnext_[u2.index];
        is_quad[i] = pnext_[u3.index] == u0 && u2 != u0 && u3 != u1;
        uses[4 * i] = u0;
        uses[4 * i + 1] = u1;
        uses[4 * i + 2] = u2;
        uses[4 * i + 3] = u3;
        for (const EdgeUse u : {u0, u1, u2, u3}) {
          __builtin_prefetch(&pev_[2 * (u.index >> 1)]);
          __builtin_prefetch(&pflags_[u.index >> 1]);
        }
        // The next block's first successors, so that its chains start from the cache.
        if (const int32_t x = begin + kBlock + i; x < p.face_end) __builtin_prefetch(&pnext_[pface_uses_[x].index]);
      }
      dvec3* vertex_points = cpos_.data() + F_ + E_;
      for (int32_t i = 0; i < 4 * count; ++i) {
        const int32_t v = tail_of(uses[i]);
        tails[i] = v;
        __builtin_prefetch(&pos_[v]);
        __builtin_prefetch(&vertex_points[v], 1);
        // The child's wings at the halves of the use's parent edge, written by `split_face`.
        const int32_t halves = 4 * (uses[i].index >> 1);
        __builtin_prefetch(&cuf[halves], 1);
        __builtin_prefetch(&cnext[halves], 1);
        if (cprev != nullptr) __builtin_prefetch(&cprev[halves], 1);
      }
      for (int32_t i = 0; i < count; ++i) {
        const int32_t f = begin + i;
        if (is_quad[i]) {
          o += split_face<4>(p, f, o, std::span<const EdgeUse, 4>(&uses[4 * i], 4),
                             std::span<const int32_t, 4>(&tails[4 * i], 4));
          continue;
        }
        loop.clear();
        std::vector<int32_t>& loop_tails = p.face_tails;
        loop_tails.clear();
        const EdgeUse start = pface_uses_[f];
        EdgeUse u = start;
        do {
          loop.push_back(u);
          loop_tails.push_back(tail_of(u));
          u = pnext_[u.index];
        } while (u != start);
        p.are_quads = false;
        o += split_face<std::dynamic_extent>(p, f, o, std::span<const EdgeUse>(loop),
                                             std::span<const int32_t>(loop_tails));
      }
    }
  }

  // Face `f` of the parent, whose uses are `loop` and their tail vertices `tails`: its face
  // point, its terms in its vertices' slots, and its child faces from `o` with their
  // interior edges; returns how many child faces it has.
  // `N` is 4 for a quad (the loops are then unrolled), otherwise `std::dynamic_extent`.
  template <size_t N>
  int32_t split_face(Part& p, int32_t f, int32_t o, std::span<const EdgeUse, N> loop,
                     std::span<const int32_t, N> tails) {
    Mesh& child = level_.mesh;
    VertexId* cev = MeshAccess::edge_vertices(child).data();
    uint8_t* cflags = MeshAccess::edge_flags(child).data();
    dvec3* vertex_points = cpos_.data() + F_ + E_;
    const int32_t n = static_cast<int32_t>(loop.size());
    dvec3 sum(0.0);
    for (const int32_t v : tails) sum += pos_[v];
    const dvec3 fp = sum / double(n);
    cpos_[f] = fp;
    for (const int32_t v : tails) {
      if (is_shared(v)) {
        p.deferred_face_points.emplace_back(v, f);
      } else {
        vertex_points[v] += fp;
      }
    }
    MeshAccess::vertex_edges(child)[f] = EdgeId(2 * E_ + o);
    link_face_children(o, loop);
    for (int32_t i = 0; i < n; ++i) {
      const int32_t ce = 2 * E_ + o + i;
      cev[2 * ce] = VertexId(F_ + (loop[i].index >> 1));
      cev[2 * ce + 1] = VertexId(f);
      cflags[ce] = 0;
    }
    if (stores_face_properties_) {
      const size_t from = static_cast<size_t>(f) >> inheritance_.shift;
      std::fill_n(MeshAccess::face_sources(child).data() + o, n, inheritance_.sources[from]);
      if (!inheritance_.colors.empty()) {
        std::fill_n(MeshAccess::face_colors(child).data() + o, n, inheritance_.colors[from]);
      }
    }
    return n;
  }

  // The wings of the child quads of the face whose uses are `loop`, numbered from `o`:
  // quad i runs tail half of use i, interior edge i (edge point to face point), interior
  // edge i-1 backwards, head half of use i-1.
  template <size_t N>
  void link_face_children(int32_t o, std::span<const EdgeUse, N> loop) {
    Mesh& child = level_.mesh;
    FaceId* cuf = MeshAccess::use_faces(child).data();
    EdgeUse* cnext = MeshAccess::next(child).data();
    EdgeUse* cprev = is_intermediate_ ? nullptr : MeshAccess::prev(child).data();
    EdgeUse* cface_uses = MeshAccess::face_uses(child).data();
    const int32_t n = static_cast<int32_t>(loop.size());
    // Half near the head of the previous use, and that use's side.
    const EdgeUse last = loop[n - 1];
    const bool last_forward = (last.index & 1) == 0 || (pflags_[last.index >> 1] & mobius_flag_);
    int32_t prev_head_half = 2 * (last.index >> 1) + (last_forward ? 1 : 0);
    int32_t prev_side = last.index & 1;
    for (int32_t i = 0; i < n; ++i) {
      const EdgeUse u = loop[i];
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
      cface_uses[q] = EdgeUse(u0);
      prev_head_half = head_half;
      prev_side = s;
    }
  }

  // The face point terms set aside by the parts (all of part 0's faces come before part
  // 1's), then, if some parent face is not a quad, the face map and an intermediate
  // child's face sources and colours.
  void after_faces() {
    dvec3* vertex_points = cpos_.data() + F_ + E_;
    bool are_quads = true;
    for (Part& p : parts_) {
      for (const auto& [v, f] : p.deferred_face_points) vertex_points[v] += cpos_[f];
      std::vector<std::pair<int32_t, int32_t>>().swap(p.deferred_face_points);
      are_quads = are_quads && p.are_quads;
    }
    level_.are_parent_faces_quads = are_quads;
    if (are_quads) return;
    if (options_.has_parent_maps) {
      reserve_large(level_.face_parents, corner_total_);
      for (int32_t q = 0; q < corner_total_; ++q) level_.face_parents.push_back(FaceId(parent_face_of(q)));
    }
    if (!stores_face_properties_) {
      stores_face_properties_ = true;
      allocate_face_properties();
      auto& sources = MeshAccess::face_sources(level_.mesh);
      auto& colors = MeshAccess::face_colors(level_.mesh);
      for (int32_t q = 0; q < corner_total_; ++q) {
        const size_t from = static_cast<size_t>(parent_face_of(q)) >> inheritance_.shift;
        sources[q] = inheritance_.sources[from];
        if (!inheritance_.colors.empty()) colors[q] = inheritance_.colors[from];
      }
    }
  }

  // The parent face of child face `q`: the face of the parent use whose tail half starts
  // the child's loop (`link_face_children`: use 2 * tail_half + side, tail_half = 2e or
  // 2e + 1).
  int32_t parent_face_of(int32_t q) const {
    const int32_t u0 = MeshAccess::face_uses(level_.mesh)[q].index;
    return puf_[2 * (u0 >> 2) + (u0 & 1)].index;
  }

  // (d) Edge points, and per-vertex sums over edges: the other ends of a vertex's edges (or
  // its edge points, DeRose) are added to its vertex-point slot, and its valence is counted.
  // With two parts, each takes the edges whose first face is its own.
  void edge_points(Part& p) {
    const bool is_split = parts_.size() > 1;
    dvec3* edge_points = cpos_.data() + F_;
    const dvec3* vertex_points = cpos_.data() + F_ + E_;
    // The positions an edge reads and the slots it adds to are scattered: they are asked
    // for this many edges ahead, so that they arrive while the edges before are done.
    constexpr int32_t kAhead = 16;
    for (int32_t e = 0; e < E_; ++e) {
      if (const int32_t x = e + kAhead; x < E_ && (!is_split || part_of(puf_[2 * x]) == p.index)) {
        const int32_t a = pev_[2 * x].index;
        const int32_t b = pev_[2 * x + 1].index;
        __builtin_prefetch(&pos_[a]);
        __builtin_prefetch(&pos_[b]);
        __builtin_prefetch(&cpos_[puf_[2 * x].index]);
        if (puf_[2 * x + 1].is_valid()) __builtin_prefetch(&cpos_[puf_[2 * x + 1].index]);
        __builtin_prefetch(&vertex_points[a], 1);
        __builtin_prefetch(&vertex_points[b], 1);
        __builtin_prefetch(&valence_[a], 1);
        __builtin_prefetch(&valence_[b], 1);
      }
      if (is_split && part_of(puf_[2 * e]) != p.index) continue;
      const int32_t a = pev_[2 * e].index;
      const int32_t b = pev_[2 * e + 1].index;
      const dvec3& pa = pos_[a];
      const dvec3& pb = pos_[b];
      const float s = edge_sharpness(e);
      dvec3 point;
      if (s >= 1.0f) {
        point = 0.5 * (pa + pb);
      } else {
        const dvec3 smooth = 0.25 * (pa + pb + cpos_[puf_[2 * e].index] + cpos_[puf_[2 * e + 1].index]);
        point = s <= 0.0f ? smooth : double(s) * (0.5 * (pa + pb)) + (1.0 - double(s)) * smooth;
      }
      edge_points[e] = point;
      if (is_shared(a)) {
        p.deferred_edge_ends.push_back(2 * e);
      } else {
        add_edge_end(a, b, point, s);
      }
      if (is_shared(b)) {
        p.deferred_edge_ends.push_back(2 * e + 1);
      } else {
        add_edge_end(b, a, point, s);
      }
    }
  }

  float edge_sharpness(int32_t e) const {
    if (!puf_[2 * e + 1].is_valid()) return kInfiniteSharpness;
    return has_creases_ ? psharp_[e] : 0.0f;
  }

  // Edge (v, other) with edge point `point` and sharpness `s`, counted at its end `v`.
  void add_edge_end(int32_t v, int32_t other, const dvec3& point, float s) {
    ++valence_[v];
    cpos_[F_ + E_ + v] += is_derose_ ? point : pos_[other];
    if (s <= 0.0f) return;
    SharpSums& ss = sharp_[v];
    const dvec3& other_position = pos_[other];
    ss.parent_neighbours += other_position;
    ++ss.parent_count;
    if (child_sharpness(s) > 0.0f) {
      ss.child_neighbours += other_position;
      ++ss.child_count;
    } else {
      ss.transition_sum += s;
      ++ss.transition_count;
    }
  }

  // The edge ends set aside by the parts, in edge order (each part's are in edge order).
  void add_deferred_edge_ends() {
    const std::vector<int32_t>& x = parts_[0].deferred_edge_ends;
    const std::vector<int32_t>& y = parts_[1].deferred_edge_ends;
    std::vector<int32_t> merged(x.size() + y.size());
    std::merge(x.begin(), x.end(), y.begin(), y.end(), merged.begin());
    for (const int32_t end : merged) {
      const int32_t e = end >> 1;
      const int32_t v = pev_[end].index;
      const int32_t other = pev_[end ^ 1].index;
      add_edge_end(v, other, cpos_[F_ + e], edge_sharpness(e));
    }
    for (Part& p : parts_) std::vector<int32_t>().swap(p.deferred_edge_ends);
  }

  // (e) Vertex points, overwriting each vertex's sum of face points and neighbours once it
  // is read.
  void vertex_points(const Part& p) {
    dvec3* vertex_points = cpos_.data() + F_ + E_;
    for (int32_t v = p.vertex_begin; v < p.vertex_end; ++v) vertex_points[v] = vertex_point(v, vertex_points[v]);
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

  // (f) Each vertex point's first edge.
  void child_vertex_edges(const Part& p) {
    EdgeId* cvertex_edges = MeshAccess::vertex_edges(level_.mesh).data();
    for (int32_t v = p.vertex_begin; v < p.vertex_end; ++v) {
      const EdgeId a = p_.vertex_edge(VertexId(v));
      cvertex_edges[F_ + E_ + v] =
          a.is_valid() ? EdgeId(2 * a.index + (pev_[2 * a.index].index == v ? 0 : 1)) : EdgeId::None();
    }
  }

  // The scratch memory freed, and the child's border loops (not for an intermediate child,
  // which has no `prev` wings to link them in).
  void after_vertices() {
    std::vector<int32_t>().swap(valence_);
    std::vector<SharpSums>().swap(sharp_);
    std::vector<std::array<uint8_t, 2>>().swap(touched_);
    for (const Part& p : parts_) has_child_creases_ = has_child_creases_ || p.has_child_creases;
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
  const OverwriteVector<dvec3>& pos_;
  const OverwriteVector<VertexId>& pev_;
  const OverwriteVector<FaceId>& puf_;
  const OverwriteVector<EdgeUse>& pnext_;
  const OverwriteVector<uint8_t>& pflags_;
  const std::vector<float>& psharp_;
  const std::vector<float>& pvsharp_;
  const OverwriteVector<EdgeUse>& pface_uses_;
  const uint8_t mobius_flag_;
  const bool has_creases_;
  const bool has_corners_;
  const bool is_derose_;
  SubdivisionLevel level_;
  OverwriteVector<dvec3>& cpos_;
  int32_t corner_total_ = 0;
  bool has_child_creases_ = false;
  std::vector<Part> parts_;
  int32_t middle_face_ = 0;               // two parts: part 1's first face
  std::vector<int32_t> valence_;          // per parent vertex, its number of edges
  std::vector<SharpSums> sharp_;          // per parent vertex, if some edge is sharp
  std::vector<std::array<uint8_t, 2>> touched_;  // two parts: per parent vertex, by whose faces
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
  OverwriteVector<FaceSource> sources = std::move(MeshAccess::face_sources(mesh));
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
