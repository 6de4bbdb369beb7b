// Offset construction. Each used input vertex v gets two output vertices, v+ and v-,
// at v ± d·n_v. The Möbius counter of the vertex ring gives every face corner a sign σ:
// the positive copy of face f uses v+ at corners with σ = +1 and v- otherwise, so across
// a Möbius edge the positive copy of one face continues into the negative copy of its
// neighbour. The negative copies are reversed and border edges get ribbons; the soup is
// rebuilt with the builder, which confirms the result is a manifold.
#include "kernel/offset.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/geometric.hpp>
#include <memory>
#include <optional>
#include <utility>

#include "kernel/large_arrays.h"
#include "base/two_threads.h"

namespace nomec::kernel {

using glm::dvec3;

dvec3 newell_normal(const std::vector<dvec3>& points) {
  dvec3 n(0.0);
  for (size_t i = 0; i < points.size(); ++i) n += newell_term(points[i], points[(i + 1) % points.size()]);
  const double len = glm::length(n);
  return len > 0.0 ? n / len : dvec3(0.0);
}

namespace {

// Runs `fn(begin, end)` over [0, n): for large n the upper half on a second thread, which
// on two cores halves the time of an independent per-element pass (the elements are
// computed exactly as in one pass, so the results are the same).
constexpr int32_t kThreadedFrom = 1 << 15;

template <typename Fn>
void for_halves(int32_t n, Fn&& fn) {
  if (n < kThreadedFrom || !has_two_hardware_threads()) {
    fn(0, n);
    return;
  }
  const int32_t mid = n / 2;
  run_two_parts([&](int part) { part == 0 ? fn(0, mid) : fn(mid, n); });
}

// A border edge and its ribbon (the offset's two-thread ribbons): the edge, its tail and
// head, and which side edges the ribbon makes (bit 0 at the tail, bit 1 at the head) above
// the number its half of the ribbons made before it (`made >> 2`).
struct BorderRibbon {
  int32_t edge;
  int32_t tail;
  int32_t head;
  uint32_t made;
};

}  // namespace

namespace {

// Face f's unit normal (the one computation `face_normals` and the offset share, so both
// give the same bits).
dvec3 unit_face_normal(const Mesh& mesh, int32_t f) {
  // Newell: sum over edges (a, b) of (a - b) x (a + b) / 2 equals the sum of cross
  // products of consecutive edge vectors up to a factor; both give the area vector.
  dvec3 n(0.0);
  mesh.for_each_face_use(FaceId(f), [&](EdgeUse u) {
    n += newell_term(mesh.position(mesh.use_tail(u)), mesh.position(mesh.use_head(u)));
  });
  const double len = glm::length(n);
  return len > 0.0 ? n / len : dvec3(0.0);
}

}  // namespace

std::vector<dvec3> face_normals(const Mesh& mesh) {
  std::vector<dvec3> normals;
  resize_large(normals, mesh.face_count());
  for_halves(mesh.face_count(), [&](int32_t begin, int32_t end) {
    for (int32_t f = begin; f < end; ++f) normals[f] = unit_face_normal(mesh, f);
  });
  return normals;
}

VertexNormals vertex_normals(const Mesh& mesh, const std::vector<dvec3>& fnormals) {
  VertexNormals result;
  resize_large(result.normals, mesh.vertex_count());  // zero vectors
  resize_large(result.corner_signs, 2 * static_cast<size_t>(mesh.edge_count()));  // zeros
  result.is_mobius_vertex.assign(mesh.vertex_count(), 0);
  for (int32_t e = 0; e < mesh.edge_count(); ++e) {
    if (mesh.is_mobius(EdgeId(e))) {
      result.is_mobius_vertex[mesh.edge_vertex(EdgeId(e), 0).index] = 1;
      result.is_mobius_vertex[mesh.edge_vertex(EdgeId(e), 1).index] = 1;
    }
  }
  // Each vertex writes its own normal and the signs of the uses starting at it.
  for_halves(mesh.vertex_count(), [&](int32_t begin, int32_t end) {
    for (int32_t v = begin; v < end; ++v) {
      dvec3 sum(0.0);
      dvec3 first(0.0);
      bool is_first = true;
      mesh.for_each_vertex_corner(VertexId(v), [&](const VertexCorner& c) {
        const int8_t sign = c.is_flipped ? -1 : 1;
        result.corner_signs[c.use.index] = sign;
        sum += double(sign) * fnormals[c.face.index];
        if (is_first) {
          first = fnormals[c.face.index];
          is_first = false;
        }
      });
      const double len = glm::length(sum);
      // A vanishing average (e.g. a needle vertex) falls back to the first face normal.
      result.normals[v] = len > 1e-12 ? sum / len : first;
    }
  });
  return result;
}

void assign_vertex_normals(Mesh& mesh) {
  VertexNormals vn = vertex_normals(mesh, face_normals(mesh));
  (void)mesh.set_vertex_normals(std::move(vn.normals));
}

namespace {

// The edges of the offset soup follow from the input's, so they need not be searched for
// (the search is most of the builder's cost). Soup corner k runs from the k-th face vertex
// to the next. The positive copy of input use u (corner p = `corner_of_use[u]`, joining
// P(u) to P(next u)) and its negative copy (the same use in the reversed loop, joining the
// partners N = P ^ 1) pair with the two copies of u's twin: positive with positive if the
// twin joins the same two output vertices, else positive with negative. On a border they
// pair with the ribbon of u's edge, and each ribbon's two sides (v+ to v-) with the
// neighbouring ribbons' sides at the same vertex. Returns the pairing for
// `MeshAccess::build_paired`, or nothing if some corner finds no single partner (the
// builder then searches and reports what is wrong).
std::vector<int32_t> offset_twins(const Mesh& mesh, const PolygonSoup& soup, const std::vector<int32_t>& corner_of_use) {
  const int32_t F = mesh.face_count();
  const int32_t total = static_cast<int32_t>(soup.face_vertices.size());
  const int32_t* fv = soup.face_vertices.data();
  std::vector<int32_t> face_start(static_cast<size_t>(F) + 1, 0);
  for (int32_t f = 0; f < F; ++f) face_start[f + 1] = face_start[f] + soup.face_sizes[f];
  const int32_t corners = face_start[F];  // corners of the positive copy (= the input's)
  // The negative copy's corner of positive corner p of face f (loop reversed).
  auto negative_corner = [&](int32_t p, int32_t f) {
    const int32_t o = face_start[f], n = face_start[f + 1] - o;
    const int32_t j = n - 2 - (p - o);
    return corners + o + (j < 0 ? j + n : j);
  };
  auto same = [](int32_t a0, int32_t a1, int32_t b0, int32_t b1) {
    return (a0 == b0 && a1 == b1) || (a0 == b1 && a1 == b0);
  };
  const std::vector<int32_t> none;
  std::vector<int32_t> twin;
  reserve_large(twin, total);
  twin.assign(total, -1);
  int32_t ribbon = 2 * corners;
  for (int32_t e = 0; e < mesh.edge_count(); ++e) {
    const EdgeUse u(EdgeId(e), 0);
    const int32_t p = corner_of_use[u.index];
    if (p < 0) return none;
    const int32_t q = negative_corner(p, mesh.use_face(u).index);
    if (mesh.is_boundary(EdgeId(e))) {
      twin[p] = ribbon;
      twin[ribbon] = p;
      twin[q] = ribbon + 2;
      twin[ribbon + 2] = q;
      ribbon += 4;
      continue;
    }
    const EdgeUse t = u.twin();
    const int32_t pt = corner_of_use[t.index];
    if (pt < 0) return none;
    const int32_t qt = negative_corner(pt, mesh.use_face(t).index);
    const int32_t a0 = fv[p], a1 = fv[corner_of_use[mesh.next(u).index]];
    const int32_t b0 = fv[pt], b1 = fv[corner_of_use[mesh.next(t).index]];
    if (same(a0, a1, b0, b1)) {
      twin[p] = pt, twin[pt] = p, twin[q] = qt, twin[qt] = q;
    } else if (same(a0, a1, b0 ^ 1, b1 ^ 1)) {
      twin[p] = qt, twin[qt] = p, twin[q] = pt, twin[pt] = q;
    } else {
      return none;
    }
  }
  // Ribbon sides: corners 1 (a+ to a-) and 3 (b- to b+) of each ribbon, met twice per vertex.
  std::vector<int32_t> side_at(soup.positions.size() / 2, -1);
  for (int32_t r = 2 * corners; r < total; r += 4) {
    for (int32_t c : {r + 1, r + 3}) {
      const int32_t k = fv[c] >> 1;
      const int32_t to = fv[c == r + 1 ? r + 2 : r];
      if ((to >> 1) != k || side_at[k] == -2) return none;
      if (side_at[k] < 0) {
        side_at[k] = c;
        continue;
      }
      twin[c] = side_at[k];
      twin[side_at[k]] = c;
      side_at[k] = -2;
    }
  }
  for (int32_t c = 0; c < total; ++c) {
    if (twin[c] < 0 || twin[twin[c]] != c) return none;
  }
  return twin;
}

// The reference construction: the slab as a polygon soup, rebuilt by the builder (with the
// edges paired from the input's when `offset_twins` finds them).
Result<OffsetResult> offset_through_soup(const Mesh& mesh, double distance, const std::vector<FaceId>* face_origin,
                                         const std::vector<dvec3>& fnormals, const VertexNormals& vn) {
  const int32_t V = mesh.vertex_count();
  const int32_t F = mesh.face_count();

  OffsetResult result;
  PolygonSoup soup;
  // Every array is reserved up front at its final size (no regrowth copies).
  int32_t border_edges = 0;
  for (int32_t e = 0; e < mesh.edge_count(); ++e) border_edges += mesh.is_boundary(EdgeId(e)) ? 1 : 0;
  const size_t in_corners = 2 * static_cast<size_t>(mesh.edge_count()) - border_edges;
  const size_t out_faces = 2 * static_cast<size_t>(F) + border_edges;
  reserve_large(soup.positions, 2 * static_cast<size_t>(V));
  reserve_large(result.vertex_parents, 2 * static_cast<size_t>(V));
  reserve_large(soup.face_sizes, out_faces);
  reserve_large(soup.face_vertices, 2 * in_corners + 4 * static_cast<size_t>(border_edges));
  reserve_large(result.face_parents, out_faces);
  // Output vertices 2k (v+) and 2k+1 (v-) for the k-th used input vertex.
  std::vector<int32_t> compact(V, -1);
  for (int32_t v = 0; v < V; ++v) {
    if (!mesh.vertex_edge(VertexId(v)).is_valid()) {
      continue;
    }
    compact[v] = soup.vertex_count() / 2;
    const dvec3& p = mesh.position(VertexId(v));
    soup.positions.push_back(p + distance * vn.normals[v]);
    soup.positions.push_back(p - distance * vn.normals[v]);
    result.vertex_parents.push_back(VertexId(v));
    result.vertex_parents.push_back(VertexId(v));
  }
  auto positive_vertex = [&](EdgeUse corner) {
    const int32_t k = compact[mesh.use_tail(corner).index];
    return vn.corner_signs[corner.index] > 0 ? 2 * k : 2 * k + 1;
  };
  auto negative_vertex = [&](EdgeUse corner) { return positive_vertex(corner) ^ 1; };
  auto origin = [&](FaceId f) { return face_origin ? (*face_origin)[f.index] : f; };

  std::vector<int32_t> loop;
  // Soup corner of each input use in the positive copy (see `offset_twins`).
  std::vector<int32_t> corner_of_use;
  resize_large(corner_of_use, 2 * static_cast<size_t>(mesh.edge_count()));
  std::fill(corner_of_use.begin(), corner_of_use.end(), -1);
  for (int32_t f = 0; f < F; ++f) {
    loop.clear();
    mesh.for_each_face_use(FaceId(f), [&](EdgeUse u) {
      corner_of_use[u.index] = static_cast<int32_t>(soup.face_vertices.size() + loop.size());
      loop.push_back(positive_vertex(u));
      const int32_t v = mesh.use_tail(u).index;
      if (vn.is_mobius_vertex[v] &&
          double(vn.corner_signs[u.index]) * glm::dot(vn.normals[v], fnormals[f]) <= 0.0) {
        ++result.inconsistent_normal_count;
      }
    });
    soup.add_face(loop);
    result.face_parents.push_back({OffsetParent::Kind::PositiveFace, origin(FaceId(f)), {}});
  }
  for (int32_t f = 0; f < F; ++f) {
    loop.clear();
    mesh.for_each_face_use(FaceId(f), [&](EdgeUse u) { loop.push_back(negative_vertex(u)); });
    std::reverse(loop.begin(), loop.end());
    soup.add_face(loop);
    result.face_parents.push_back({OffsetParent::Kind::NegativeFace, origin(FaceId(f)), {}});
  }
  // Ribbons: border edge a->b of face f gives [P(b), P(a), N(a), N(b)].
  for (int32_t e = 0; e < mesh.edge_count(); ++e) {
    if (!mesh.is_boundary(EdgeId(e))) {
      continue;
    }
    const EdgeUse at_a(EdgeId(e), 0);
    const EdgeUse at_b = mesh.next(at_a);
    soup.add_face({positive_vertex(at_b), positive_vertex(at_a), negative_vertex(at_a),
                   negative_vertex(at_b)});
    result.face_parents.push_back(
        {OffsetParent::Kind::Ribbon, origin(mesh.edge_face(EdgeId(e), 0)), EdgeId(e)});
  }
  // Sources and colours follow the input faces.
  reserve_large(soup.face_sources, out_faces);
  if (mesh.has_face_colors()) reserve_large(soup.face_colors, out_faces);
  for (size_t i = 0; i < out_faces; ++i) {
    const int32_t f =
        i < size_t(2 * F) ? int32_t(i % F) : mesh.edge_face(result.face_parents[i].edge, 0).index;
    soup.face_sources.push_back(mesh.face_source(FaceId(f)));
    if (mesh.has_face_colors()) {
      soup.face_colors.push_back(mesh.face_color(FaceId(f)));
    }
  }

  std::vector<int32_t> twins = offset_twins(mesh, soup, corner_of_use);
  auto built = twins.empty() ? build_mesh(soup) : MeshAccess::build_paired(std::move(soup), std::move(twins));
  if (!built.has_value()) {
    KernelError error = built.error();
    error.message = "offset surface is not a manifold: " + error.message;
    return error;
  }
  result.mesh = std::move(*built);
  return result;
}


// The input of `offset_consuming`, whose arrays the direct construction frees once it has
// read them (`is_done` then).
struct InputRelease {
  Mesh* mesh = nullptr;
  bool is_done = false;
};

// The slab's winged-edge arrays written directly, in the order the builder would number
// them for the soup `offset_through_soup` makes (positive copies, negative copies, ribbons;
// an edge is numbered at the first corner, in soup order, that uses it), without the soup,
// its corner pairing or the builder's per-corner arrays. Each corner's edge use is kept per
// input edge (`oedge`) for the corner that meets it later. Returns nothing
// where the soup path's pairing would fail (a corner whose twin joins other vertices, a
// ribbon side met other than twice), so that path runs and reports what is wrong.
// `kPFromTails`: whether P(u), the output vertex a corner of use u starts at, is read from
// the input's edge vertices (see `offset_direct` below), else kept in an array.
template <bool kPFromTails>
std::optional<OffsetResult> offset_direct_with(const Mesh& mesh, double distance, const std::vector<FaceId>* face_origin,
                                               bool has_parent_maps, InputRelease* release) {
  const int32_t V = mesh.vertex_count();
  const int32_t F = mesh.face_count();
  const int32_t E = mesh.edge_count();
  const FaceId* iuf = MeshAccess::use_faces(mesh).data();
  const EdgeUse* inext = MeshAccess::next(mesh).data();
  const uint8_t mobius = MeshAccess::mobius_flag();
  // Border edges, by halves of the edges (as `for_halves(E, …)` splits them).
  int32_t borders_in[2] = {0, 0};
  for_halves(E, [&](int32_t begin, int32_t end) {
    int32_t count = 0;
    for (int32_t e = begin; e < end; ++e) count += iuf[2 * e + 1].is_valid() ? 0 : 1;
    borders_in[begin == 0 ? 0 : 1] = count;
  });
  const int64_t border_edges = int64_t{borders_in[0]} + borders_in[1];
  const int64_t in_corners = 2 * int64_t{E} - border_edges;
  const int64_t out_faces = 2 * int64_t{F} + border_edges;
  const int64_t out_edges = in_corners + 2 * border_edges;  // 2C + 4B corners, two per edge
  if (2 * out_edges > int64_t{INT32_MAX} - 2) return std::nullopt;

  // Scratch that is written before it is read is not initialised (a fresh page costs a
  // fault, zeroing it costs a pass); large arrays get the huge-page advice.
  auto scratch = [&]<typename T>(T*, size_t n) {
    std::unique_ptr<T[]> a = std::make_unique_for_overwrite<T[]>(n);
    advise_huge_pages(a.get(), n * sizeof(T));
    return a;
  };
  const size_t use_count = 2 * static_cast<size_t>(E);
  // The face normals, as `face_normals` computes them.
  std::unique_ptr<dvec3[]> fnormals = scratch(static_cast<dvec3*>(nullptr), static_cast<size_t>(F));
  for_halves(F, [&](int32_t begin, int32_t end) {
    for (int32_t f = begin; f < end; ++f) fnormals[f] = unit_face_normal(mesh, f);
  });
  // With P from the tails, `offset_direct` has found no Möbius edge and no unused vertex.
  std::vector<uint8_t> is_mobius_vertex;
  bool has_mobius = false;
  if constexpr (!kPFromTails) {
    is_mobius_vertex.assign(V, 0);
    for (int32_t e = 0; e < E; ++e) {
      if (mesh.is_mobius(EdgeId(e))) {
        has_mobius = true;
        is_mobius_vertex[mesh.edge_vertex(EdgeId(e), 0).index] = 1;
        is_mobius_vertex[mesh.edge_vertex(EdgeId(e), 1).index] = 1;
      }
    }
  }

  OffsetResult result;
  Mesh& m = result.mesh;
  // Output vertices 2k (v+) and 2k+1 (v-) for the k-th used input vertex (k = v when every
  // vertex is used).
  std::unique_ptr<int32_t[]> compact;
  int32_t used = V;
  if (has_parent_maps) reserve_large(result.vertex_parents, 2 * static_cast<size_t>(V));
  if constexpr (!kPFromTails) {
    compact = scratch(static_cast<int32_t*>(nullptr), static_cast<size_t>(V));
    used = 0;
    for (int32_t v = 0; v < V; ++v) compact[v] = mesh.vertex_edge(VertexId(v)).is_valid() ? used++ : -1;
  }
  if (has_parent_maps) {
    for (int32_t v = 0; v < V; ++v) {
      if (!mesh.vertex_edge(VertexId(v)).is_valid()) continue;
      result.vertex_parents.push_back(VertexId(v));
      result.vertex_parents.push_back(VertexId(v));
    }
  }
  const int32_t out_vertices = 2 * used;
  const VertexId* itail = MeshAccess::edge_vertices(mesh).data();
  auto& positions = MeshAccess::positions(m);
  // Every position is written by the walk below (on two threads, which then share the
  // cost of faulting in the fresh pages; a fill here would pay it on one).
  resize_for_overwrite(positions, static_cast<size_t>(out_vertices));
  // One walk around every vertex (§5.1, as `vertex_normals`): its normal, straight into
  // its two offset positions, and (unless it comes from the tails) P(u) for every use u
  // starting at it: v+ where the Möbius counter agrees with the ring's first face, else
  // v-. Corners at Möbius vertices are then checked against the face normals (the seed's
  // dot-product test).
  const std::unique_ptr<int32_t[]> pvert =
      kPFromTails ? nullptr : scratch(static_cast<int32_t*>(nullptr), use_count);
  auto P = [&](int32_t u) {
    if constexpr (kPFromTails) {
      return 2 * itail[u].index;
    } else {
      return pvert[u];
    }
  };
  int32_t inconsistent[2] = {0, 0};
  int64_t walked_corners[2] = {0, 0};
  for_halves(V, [&](int32_t begin, int32_t end) {
    int32_t count = 0;
    int64_t corners = 0;
    for (int32_t v = begin; v < end; ++v) {
      const int32_t k = kPFromTails ? v : compact[v];
      if (k < 0) continue;
      dvec3 sum(0.0);
      dvec3 first(0.0);
      bool is_first = true;
      mesh.for_each_vertex_corner(VertexId(v), [&](const VertexCorner& c) {
        if constexpr (!kPFromTails) pvert[c.use.index] = 2 * k + (c.is_flipped ? 1 : 0);
        ++corners;
        sum += double(c.is_flipped ? -1 : 1) * fnormals[c.face.index];
        if (is_first) {
          first = fnormals[c.face.index];
          is_first = false;
        }
      });
      const double len = glm::length(sum);
      const dvec3 n = len > 1e-12 ? sum / len : first;
      const dvec3& p = mesh.position(VertexId(v));
      positions[2 * k] = p + distance * n;
      positions[2 * k + 1] = p - distance * n;
      if (!kPFromTails && is_mobius_vertex[v]) {
        mesh.for_each_vertex_corner(VertexId(v), [&](const VertexCorner& c) {
          if (double(c.is_flipped ? -1 : 1) * glm::dot(n, fnormals[c.face.index]) <= 0.0) ++count;
        });
      }
    }
    inconsistent[begin == 0 ? 0 : 1] += count;
    walked_corners[begin == 0 ? 0 : 1] += corners;
  });
  result.inconsistent_normal_count = inconsistent[0] + inconsistent[1];
  // The walks met every corner: every vertex has one fan, so a border vertex has two
  // border edges, one ending and (without Möbius edges) one starting there.
  const bool one_fan_each = walked_corners[0] + walked_corners[1] == in_corners;
  // Freed before the output's arrays are made, which can then reuse their pages.
  fnormals.reset();
  compact.reset();
  std::vector<uint8_t>().swap(is_mobius_vertex);
  // A caller done with the input (`offset_consuming`) has its positions, `prev` wings and
  // vertex anchors freed here too: nothing below reads them. Only where nothing below can
  // fail (so the fallback, which reads the whole input, cannot be needed): no Möbius edge
  // (every corner pairs positive with positive) and the walks met every corner, so every
  // vertex has one fan and a border vertex two border edges (each ribbon side is met
  // twice).
  if (kPFromTails && release != nullptr && one_fan_each) {
    Mesh& input = *release->mesh;
    OverwriteVector<dvec3>().swap(MeshAccess::positions(input));
    OverwriteVector<EdgeUse>().swap(MeshAccess::prev(input));
    OverwriteVector<EdgeId>().swap(MeshAccess::vertex_edges(input));
    release->is_done = true;
  }

  auto& oev = MeshAccess::edge_vertices(m);
  auto& ouf = MeshAccess::use_faces(m);
  auto& oflags = MeshAccess::edge_flags(m);
  auto& onext = MeshAccess::next(m);
  auto& oprev = MeshAccess::prev(m);
  auto& oface_uses = MeshAccess::face_uses(m);
  auto& overtex_edges = MeshAccess::vertex_edges(m);
  auto& osources = MeshAccess::face_sources(m);
  auto& ocolors = MeshAccess::face_colors(m);
  // The arrays are written by index (the two copies may be made on two threads). Every use
  // of every output edge lies in one face loop, every edge is made once (its vertices and
  // flags written then) and gets its second use, and every face is linked, so none of them
  // is filled first (the copies' threads fault their pages in as they write them); the
  // anchors start as None (all bits set).
  resize_for_overwrite(oev, 2 * static_cast<size_t>(out_edges));
  resize_for_overwrite(ouf, 2 * static_cast<size_t>(out_edges));
  resize_for_overwrite(oflags, static_cast<size_t>(out_edges));
  resize_for_overwrite(onext, 2 * static_cast<size_t>(out_edges));
  resize_for_overwrite(oprev, 2 * static_cast<size_t>(out_edges));
  resize_for_overwrite(oface_uses, static_cast<size_t>(out_faces));
  resize_for_overwrite(overtex_edges, static_cast<size_t>(out_vertices));
  static_assert(EdgeId::None().index == -1);
  std::memset(static_cast<void*>(overtex_edges.data()), 0xff, overtex_edges.size() * sizeof(EdgeId));
  resize_for_overwrite(osources, static_cast<size_t>(out_faces));
  const bool has_colors = mesh.has_face_colors();
  if (has_colors) reserve_large(ocolors, static_cast<size_t>(out_faces));
  if (has_parent_maps) reserve_large(result.face_parents, static_cast<size_t>(out_faces));
  // Each corner's use, per input use, for the corner of the same edge that comes later.
  // Each interior input edge gives two output edges, each met by two corners: the positive
  // copies of both uses and the negative copies of both (pairing 1), or the positive copy
  // of one use and the negative of the other (pairing 2); a border edge gives its two
  // copies, each met again by the ribbon. The first corner keeps its new edge in one of the
  // input edge's two slots for the second: slot 0 holds the positive copy of side 0, and
  // the positive copy of side 1 where it pairs with side 0's (`pos_slot`).
  // A slot holds -1 until its first corner is made (corners are made face by face, in loop
  // order), so a corner finds by its slot whether it comes second. Slot 0 of every edge
  // comes first, then slot 1 of every edge (`slot_at`): without Möbius edges the positive
  // copies use only slots 0 and the negative only slots 1, and the two threads that make
  // them walk the faces in the same order, so slots side by side would put both threads'
  // writes in the same cache lines at the same time.
  // The slots are kept two to a `FaceSource` (its two numbers), in the output's sources
  // while they are unwritten (they are written last, after the ribbons have read the
  // slots) when they have room, as they have for closed quad and triangle meshes and for
  // meshes with borders: the slots then take no fresh memory of their own (13 MB for the
  // pipeline benchmark's input, bench/kernel/README.md).
  std::unique_ptr<FaceSource[]> slot_scratch;
  FaceSource* slot_store = osources.data();
  if (static_cast<size_t>(E) > osources.size()) {
    slot_scratch = scratch(static_cast<FaceSource*>(nullptr), static_cast<size_t>(E));
    slot_store = slot_scratch.get();
  }
  auto slot_at = [&](int32_t e, int32_t slot) -> int32_t& {
    const size_t k = static_cast<size_t>(slot) * E + e;
    FaceSource& pair = slot_store[k >> 1];
    return (k & 1) == 0 ? pair.source_face : pair.instance;
  };
  static_assert(sizeof(FaceSource) == 2 * sizeof(int32_t));
  for_halves(E, [&](int32_t begin, int32_t end) {
    // Slots [2 begin, 2 end), in whole pairs.
    std::memset(static_cast<void*>(slot_store + begin), 0xff, static_cast<size_t>(end - begin) * sizeof(FaceSource));
  });
  auto pos_slot = [](int32_t u, int kind) { return (u & 1) == 0 || kind == 1 ? 0 : 1; };
  auto slot_edge = [&](int32_t u, int32_t slot) { return EdgeUse(EdgeId(slot_at(u >> 1, slot)), 0); };
  EdgeId* anchors = overtex_edges.data();

  // One sequence of corners (the positive copies, the negative copies, the ribbons): the
  // number its next new edge gets, the end of its numbers, and how many second uses it made.
  // Its anchors (the first edge at each vertex) are `anchors`, or, for the negative copies
  // made on their own thread, an array of their own by v- >> 1 (`is_halved`), copied in
  // once both threads are done: each copy's anchors then lie in cache lines the other
  // thread never writes, as do the runs themselves and their loops.
  struct alignas(64) Run {
    int32_t next_edge = 0;
    int32_t end = 0;
    int64_t second_uses = 0;
    EdgeId* anchors = nullptr;
    bool is_halved = false;
    std::vector<EdgeUse> loop;
    std::vector<EdgeUse> uses;
    EdgeId& anchor(int32_t v) { return anchors[is_halved ? v >> 1 : v]; }
  };
  // The first use of a new edge from a to b (in face `face`), or the second use of the
  // edge whose first use is `first` by the corner starting at `a`.
  // None once the run has used up its numbers (only for input that breaks the mesh's
  // invariants: then nothing is written out of bounds or into another run's edges).
  auto new_edge = [&](Run& run, int32_t a, int32_t b, int32_t face) {
    if (run.next_edge == run.end) return EdgeUse::None();
    const int32_t e = run.next_edge++;
    oev[2 * e] = VertexId(a);
    oev[2 * e + 1] = VertexId(b);
    oflags[e] = 0;
    ouf[2 * e] = FaceId(face);
    if (!run.anchor(a).is_valid()) run.anchor(a) = EdgeId(e);
    if (!run.anchor(b).is_valid()) run.anchor(b) = EdgeId(e);
    return EdgeUse(EdgeId(e), 0);
  };
  auto second_use = [&](Run& run, EdgeUse first, int32_t a, int32_t face) {
    ++run.second_uses;
    const int32_t e = first.index >> 1;
    ouf[2 * e + 1] = FaceId(face);
    if (oev[2 * e].index == a) oflags[e] |= mobius;  // both corners run the same way
    return EdgeUse(EdgeId(e), 1);
  };
  auto link = [&](const EdgeUse* loop, int32_t n, int32_t face) {
    oface_uses[face] = loop[0];
    for (int32_t i = 0; i < n; ++i) {
      const EdgeUse x = loop[i], y = loop[i + 1 == n ? 0 : i + 1];
      onext[x.index] = y;
      oprev[y.index] = x;
    }
  };
  auto origin = [&](int32_t f) { return face_origin ? (*face_origin)[f] : FaceId(f); };
  auto same = [](int32_t a0, int32_t a1, int32_t b0, int32_t b1) {
    return (a0 == b0 && a1 == b1) || (a0 == b1 && a1 == b0);
  };
  // How the copies of use u pair with those of its twin t: 1 positive with positive (the
  // twin's positive corner joins the same two vertices), 2 positive with negative, 0 neither.
  auto pairing = [&](int32_t u, int32_t a0, int32_t a1) {
    const int32_t t = u ^ 1;
    const int32_t b0 = P(t), b1 = P(inext[t].index);
    if (same(a0, a1, b0, b1)) return 1;
    return same(a0, a1, b0 ^ 1, b1 ^ 1) ? 2 : 0;
  };
  // The pairing of use u's copies: without Möbius edges no corner is flipped, so every
  // interior edge pairs positive with positive (and a border edge's copies meet its ribbon).
  auto kind_of = [&](int32_t u, int32_t a0, int32_t a1) {
    return has_mobius && iuf[u ^ 1].is_valid() ? pairing(u, a0, a1) : 1;
  };
  auto face_loop = [&](Run& run, int32_t f) {
    run.loop.clear();
    mesh.for_each_face_use(FaceId(f), [&](EdgeUse u) { run.loop.push_back(u); });
    const int32_t n = static_cast<int32_t>(run.loop.size());
    run.uses.resize(n);
    return n;
  };

  // Positive copies: corner i of face f runs from P(u_i) to P(u_i+1). False where a corner
  // pairs with neither copy of its twin.
  auto make_positive = [&](Run& run) {
    for (int32_t f = 0; f < F; ++f) {
      const int32_t n = face_loop(run, f);
      const EdgeUse* loop = run.loop.data();
      for (int32_t i = 0; i < n; ++i) {
        const int32_t u = loop[i].index;
        const int32_t a0 = P(u), a1 = P(loop[i + 1 == n ? 0 : i + 1].index);
        const int kind = kind_of(u, a0, a1);
        if (kind == 0) return false;
        // Under pairing 1 the corner that comes second finds the edge kept in the slot.
        int32_t& kept = slot_at(u >> 1, pos_slot(u, kind));
        EdgeUse x;
        if (kind == 1 && kept >= 0) {
          x = second_use(run, EdgeUse(EdgeId(kept), 0), a0, f);
        } else {
          x = new_edge(run, a0, a1, f);
          if (!x.is_valid()) return false;
          kept = x.index >> 1;
        }
        run.uses[i] = x;
      }
      link(run.uses.data(), n, f);
    }
    return true;
  };
  // Negative copies, loops reversed: corner j of face F + f runs from N(u_i+1) to N(u_i)
  // for i = n - 2 - j (mod n), with N = P ^ 1.
  auto make_negative = [&](Run& run) {
    for (int32_t f = 0; f < F; ++f) {
      const int32_t n = face_loop(run, f);
      const EdgeUse* loop = run.loop.data();
      const int32_t face = F + f;
      for (int32_t j = 0; j < n; ++j) {
        const int32_t i = j <= n - 2 ? n - 2 - j : n - 1;
        const int32_t w = loop[i].index;
        const int32_t p0 = P(w), p1 = P(loop[i + 1 == n ? 0 : i + 1].index);
        const int32_t a0 = p1 ^ 1, a1 = p0 ^ 1;
        const int kind = kind_of(w, p0, p1);
        if (kind == 0) return false;
        int32_t& kept = slot_at(w >> 1, 1 - pos_slot(w, kind));
        EdgeUse x;
        if (kept >= 0) {
          // Pairing 2: every positive corner came first; pairing 1: the twin's negative
          // corner came first, in an earlier face or earlier in this one.
          x = second_use(run, EdgeUse(EdgeId(kept), 0), a0, face);
        } else {
          x = new_edge(run, a0, a1, face);
          if (!x.is_valid()) return false;
          kept = x.index >> 1;
        }
        run.uses[j] = x;
      }
      link(run.uses.data(), n, face);
    }
    return true;
  };
  // Without Möbius edges the copies share no edge, slot or vertex (the positive copies use
  // only v+, the negative only v-), and the positive copies make exactly one new edge per
  // input edge, so the negative copies' edges are numbered from E on: the two copies are
  // made on two threads for large meshes, the same arrays as one after the other.
  Run positive, negative;
  positive.anchors = negative.anchors = anchors;
  if (!has_mobius && F >= kThreadedFrom && has_two_hardware_threads()) {
    positive.end = E;
    negative.next_edge = E;
    negative.end = static_cast<int32_t>(out_edges);
    // Without Möbius edges no corner is flipped: the negative copies meet only the odd
    // vertices (v- = v+ + 1), whose anchors are still None.
    const size_t halved_count = static_cast<size_t>(out_vertices) / 2;
    const std::unique_ptr<EdgeId[]> negative_anchors = scratch(static_cast<EdgeId*>(nullptr), halved_count);
    std::memset(static_cast<void*>(negative_anchors.get()), 0xff, halved_count * sizeof(EdgeId));
    negative.anchors = negative_anchors.get();
    negative.is_halved = true;
    // Loops of their own, allocated in whole cache lines: a face's few corners would
    // otherwise take a small block that may share a line with the other thread's.
    for (Run* r : {&positive, &negative}) {
      r->loop.reserve(64);
      r->uses.reserve(64);
    }
    bool made[2] = {false, false};  // positive, negative
    run_two_parts([&](int part) { made[part] = part == 0 ? make_positive(positive) : make_negative(negative); });
    if (!made[0] || !made[1] || positive.next_edge != E) return std::nullopt;
    for_halves(static_cast<int32_t>(halved_count), [&](int32_t begin, int32_t end) {
      for (int32_t k = begin; k < end; ++k) anchors[2 * k + 1] = negative_anchors[k];
    });
    negative.anchors = anchors;
    negative.is_halved = false;
  } else {
    positive.end = static_cast<int32_t>(out_edges);
    if (!make_positive(positive)) return std::nullopt;
    negative.next_edge = positive.next_edge;
    negative.end = static_cast<int32_t>(out_edges);
    if (!make_negative(negative)) return std::nullopt;
  }
  // Ribbons: border edge a->b gives [P(b), P(a), N(a), N(b)]; its sides (corners 1 and 3)
  // pair with the neighbouring ribbons' sides at the same vertex. The r-th border edge's
  // ribbon is face 2F + r; a side's edge is made by the first of its two corners (ribbons
  // in order, corner 1 before corner 3), so the side edges are numbered from
  // `negative.next_edge` on in the order of their first corners.
  int64_t ribbon_second_uses = 0;
  // The border edges in order, when the ribbons were made on two threads.
  std::unique_ptr<BorderRibbon[]> border_ribbons;
  if constexpr (kPFromTails) {
    if (one_fan_each && border_edges >= kThreadedFrom && has_two_hardware_threads()) {
      // Two threads, each making the ribbons of half the border edges, number the sides as
      // one thread would: they first find, for every border vertex k, the ribbon of the
      // border edge starting at k (its corner 1 meets side k) and of the one ending at k
      // (its corner 3 does; `meets`, 2k and 2k + 1), then count the side edges each ribbon
      // makes, and then make them. A side corner that comes second takes the number its
      // partner made. Its edge's Möbius flag stays clear: the two corners of a side are a
      // corner 1 and a corner 3, which run the side in opposite directions.
      const int32_t R = static_cast<int32_t>(border_edges);
      const int32_t mid = R / 2;
      // The ribbons of half `part`: [begin, end).
      auto half = [&](int part) { return part == 0 ? std::pair{0, mid} : std::pair{mid, R}; };
      border_ribbons = scratch(static_cast<BorderRibbon*>(nullptr), static_cast<size_t>(R));
      BorderRibbon* rib = border_ribbons.get();
      const std::unique_ptr<int32_t[]> meets = scratch(static_cast<int32_t*>(nullptr), 2 * static_cast<size_t>(V));
      for_halves(V, [&](int32_t begin, int32_t end) {
        std::memset(static_cast<void*>(meets.get() + 2 * static_cast<size_t>(begin)), 0xff,
                    2 * static_cast<size_t>(end - begin) * sizeof(int32_t));
      });
      // One fan at every vertex: each meet is written once (no two threads write one).
      for_halves(E, [&](int32_t begin, int32_t end) {
        int32_t r = begin == 0 ? 0 : borders_in[0];
        for (int32_t e = begin; e < end; ++e) {
          if (iuf[2 * e + 1].is_valid()) continue;
          const int32_t tail = itail[2 * e].index, head = itail[inext[2 * e].index].index;
          rib[r] = {e, tail, head, 0};
          meets[2 * static_cast<size_t>(tail)] = r;
          meets[2 * static_cast<size_t>(head) + 1] = r;
          ++r;
        }
      });
      // Which sides each ribbon makes, and how many its half made before it.
      int32_t made_in[2] = {0, 0};
      bool paired[2] = {true, true};
      run_two_parts([&](int part) {
        const auto [begin, end] = half(part);
        uint32_t made = 0;
        bool ok = true;
        for (int32_t r = begin; r < end; ++r) {
          BorderRibbon& x = rib[r];
          const int32_t ends_at_tail = meets[2 * static_cast<size_t>(x.tail) + 1];
          const int32_t starts_at_head = meets[2 * static_cast<size_t>(x.head)];
          ok &= meets[2 * static_cast<size_t>(x.tail)] == r && meets[2 * static_cast<size_t>(x.head) + 1] == r &&
                ends_at_tail >= 0 && starts_at_head >= 0;
          const uint32_t sides = (r <= ends_at_tail ? 1u : 0u) | (r < starts_at_head ? 2u : 0u);
          x.made = made << 2 | sides;
          made += (sides & 1) + (sides >> 1);
        }
        made_in[part] = static_cast<int32_t>(made);
        paired[part] = ok;
      });
      // One fan at every vertex and no Möbius edge make one border edge start and one end
      // at every border vertex; else the input breaks the mesh's invariants.
      if (!paired[0] || !paired[1]) return std::nullopt;
      const int32_t side_base = negative.next_edge;
      // The edge made by ribbon r's side corner 1, or 3.
      auto side_edge = [&](int32_t r, int corner) {
        const uint32_t made = rib[r].made;
        return side_base + (r < mid ? 0 : made_in[0]) + static_cast<int32_t>(made >> 2) +
               (corner == 3 && (made & 1) != 0 ? 1 : 0);
      };
      auto second_side = [&](Run& run, int32_t e, int32_t face) {
        ++run.second_uses;
        ouf[2 * e + 1] = FaceId(face);
        return EdgeUse(EdgeId(e), 1);
      };
      Run halves[2];
      bool made[2] = {false, false};
      run_two_parts([&](int part) {
        Run& run = halves[part];
        run.anchors = anchors;
        run.next_edge = side_base + (part == 0 ? 0 : made_in[0]);
        run.end = run.next_edge + made_in[part];
        const auto [begin, end] = half(part);
        for (int32_t r = begin; r < end; ++r) {
          const BorderRibbon x = rib[r];
          const int32_t face = 2 * F + r;
          const int32_t c0 = slot_at(x.edge, 0), c1 = slot_at(x.edge, 1);
          if (c0 < 0 || c1 < 0) return;  // a copy made no edge here
          const int32_t x1 = 2 * x.tail, x2 = x1 + 1, x0 = 2 * x.head, x3 = x0 + 1;
          EdgeUse ribbon[4];
          ribbon[0] = second_use(run, EdgeUse(EdgeId(c0), 0), x0, face);
          ribbon[1] = (x.made & 1) != 0 ? new_edge(run, x1, x2, face)
                                        : second_side(run, side_edge(meets[2 * static_cast<size_t>(x.tail) + 1], 3), face);
          ribbon[2] = second_use(run, EdgeUse(EdgeId(c1), 0), x2, face);
          ribbon[3] = (x.made & 2) != 0 ? new_edge(run, x3, x0, face)
                                        : second_side(run, side_edge(meets[2 * static_cast<size_t>(x.head)], 1), face);
          if (!ribbon[1].is_valid() || !ribbon[3].is_valid()) return;
          link(ribbon, 4, face);
        }
        made[part] = run.next_edge == run.end;
      });
      if (!made[0] || !made[1] || halves[1].end != out_edges) return std::nullopt;
      ribbon_second_uses = halves[0].second_uses + halves[1].second_uses;
    }
  }
  if (border_ribbons == nullptr) {
    // One thread: `side_use` per border vertex is None, the first side's use, or `kPaired`.
    constexpr int32_t kPaired = -2;
    std::vector<EdgeUse> side_use(static_cast<size_t>(out_vertices) / 2, EdgeUse::None());
    bool sides_ok = true;
    Run ribbons;
    ribbons.anchors = anchors;
    ribbons.next_edge = negative.next_edge;
    ribbons.end = static_cast<int32_t>(out_edges);
    auto side = [&](int32_t a, int32_t b, int32_t face) {
      EdgeUse& s = side_use[a >> 1];
      if (s.index == kPaired) {
        sides_ok = false;
        return EdgeUse::None();
      }
      if (!s.is_valid()) {
        s = new_edge(ribbons, a, b, face);
        if (!s.is_valid()) sides_ok = false;
        return s;
      }
      const EdgeUse x = second_use(ribbons, s, a, face);
      s = EdgeUse(kPaired);
      return x;
    };
    int32_t face = 2 * F;
    for (int32_t e = 0; e < E; ++e) {
      if (iuf[2 * e + 1].is_valid()) continue;
      const int32_t at_a = 2 * e, at_b = inext[at_a].index;
      const int32_t x0 = P(at_b), x1 = P(at_a), x2 = x1 ^ 1, x3 = x0 ^ 1;
      if (slot_at(e, 0) < 0 || slot_at(e, 1) < 0) return std::nullopt;  // a copy made no edge here
      EdgeUse ribbon[4];
      ribbon[0] = second_use(ribbons, slot_edge(at_a, 0), x0, face);
      ribbon[1] = side(x1, x2, face);
      ribbon[2] = second_use(ribbons, slot_edge(at_a, 1), x2, face);
      ribbon[3] = side(x3, x0, face);
      if (!sides_ok) return std::nullopt;
      link(ribbon, 4, face);
      ++face;
    }
    for (const EdgeUse s : side_use) {
      if (s.is_valid()) return std::nullopt;  // a side without a partner
    }
    if (ribbons.next_edge != out_edges) return std::nullopt;
    ribbon_second_uses = ribbons.second_uses;
  }
  // Every edge made and met twice: then every use is in a loop and every wing was written.
  if (positive.second_uses + negative.second_uses + ribbon_second_uses != out_edges) return std::nullopt;
  // Sources, colours and parents follow the input faces.
  const auto& isources = MeshAccess::face_sources(mesh);
  const auto& icolors = MeshAccess::face_colors(mesh);
  // The sources overwrite the slots (above), which nothing reads any more.
  slot_scratch.reset();
  for_halves(F, [&](int32_t begin, int32_t end) {
    for (int32_t copy = 0; copy < 2; ++copy) {
      std::copy(isources.begin() + begin, isources.begin() + end, osources.begin() + static_cast<size_t>(copy) * F + begin);
    }
  });
  if (border_ribbons != nullptr) {
    const BorderRibbon* rib = border_ribbons.get();
    for_halves(static_cast<int32_t>(border_edges), [&](int32_t begin, int32_t end) {
      for (int32_t r = begin; r < end; ++r) osources[2 * static_cast<size_t>(F) + r] = isources[iuf[2 * rib[r].edge].index];
    });
  } else {
    size_t ribbon_face = 2 * static_cast<size_t>(F);
    for (int32_t e = 0; e < E; ++e) {
      if (!iuf[2 * e + 1].is_valid()) osources[ribbon_face++] = isources[iuf[2 * e].index];
    }
  }
  if (has_colors || has_parent_maps) {
    for (int32_t copy = 0; copy < 2; ++copy) {
      if (has_colors) ocolors.insert(ocolors.end(), icolors.begin(), icolors.begin() + F);
      if (has_parent_maps) {
        for (int32_t f = 0; f < F; ++f) {
          result.face_parents.push_back(
              {copy == 0 ? OffsetParent::Kind::PositiveFace : OffsetParent::Kind::NegativeFace, origin(f), {}});
        }
      }
    }
    for (int32_t e = 0; e < E; ++e) {
      if (iuf[2 * e + 1].is_valid()) continue;
      const FaceId f = iuf[2 * e];
      if (has_colors) ocolors.push_back(mesh.face_color(f));
      if (has_parent_maps) result.face_parents.push_back({OffsetParent::Kind::Ribbon, origin(f.index), EdgeId(e)});
    }
  }
  return result;
}

// Without Möbius edges no corner is flipped, and when every vertex is used the k-th used
// vertex is vertex k: P(u) is then twice the tail of u, which the input's edge vertices give
// (a use's tail is its edge's vertex of the same side), so no array of it is made (a
// scattered write per corner, and 4 bytes per use of fresh memory). The two ways are two
// instantiations, so that neither pays for the other's test in its loops.
std::optional<OffsetResult> offset_direct(const Mesh& mesh, double distance, const std::vector<FaceId>* face_origin,
                                          bool has_parent_maps, InputRelease* release = nullptr) {
  const auto& anchors = MeshAccess::vertex_edges(mesh);
  const bool every_vertex_used =
      std::all_of(anchors.begin(), anchors.end(), [](EdgeId e) { return e.is_valid(); });
  if (every_vertex_used && !mesh.has_mobius_edges()) {
    return offset_direct_with<true>(mesh, distance, face_origin, has_parent_maps, release);
  }
  return offset_direct_with<false>(mesh, distance, face_origin, has_parent_maps, release);
}

Result<OffsetResult> offset_impl(const Mesh& mesh, double distance, const std::vector<FaceId>* face_origin,
                                 bool has_parent_maps, InputRelease* release = nullptr) {
  if (auto direct = offset_direct(mesh, distance, face_origin, has_parent_maps, release)) {
    return std::move(*direct);
  }
  if (release != nullptr && release->is_done) {
    // Cannot happen (the input was released only where nothing after could fail); said
    // rather than read the freed input.
    return invalid_argument("the offset's input breaks the mesh's invariants: its corners do not pair up");
  }
  const std::vector<dvec3> fnormals = face_normals(mesh);
  const VertexNormals vn = vertex_normals(mesh, fnormals);
  auto r = offset_through_soup(mesh, distance, face_origin, fnormals, vn);
  if (r.has_value() && !has_parent_maps) {
    r->face_parents.clear();
    r->vertex_parents.clear();
  }
  return r;
}

std::optional<KernelError> check_distance(double distance) {
  if (!(distance > 0.0) || !std::isfinite(distance)) {
    return KernelError{KernelError::Kind::InvalidArgument,
                       fmt::format("offset distance {} is not a positive number", distance),
                       {},
                       {},
                       {}};
  }
  return std::nullopt;
}

}  // namespace

Result<OffsetResult> offset(const Mesh& mesh, const OffsetOptions& options) {
  if (auto error = check_distance(options.distance)) return *error;
  return offset_impl(mesh, options.distance, nullptr, options.has_parent_maps);
}

Result<OffsetResult> offset_consuming(Mesh&& mesh, const OffsetOptions& options) {
  if (auto error = check_distance(options.distance)) return *error;
  InputRelease release{&mesh};
  return offset_impl(mesh, options.distance, nullptr, options.has_parent_maps, &release);
}

std::optional<OffsetResult> offset_direct_only(const Mesh& mesh, const OffsetOptions& options) {
  if (check_distance(options.distance)) return std::nullopt;
  return offset_direct(mesh, options.distance, nullptr, options.has_parent_maps);
}

Result<OffsetResult> offset_through_builder(const Mesh& mesh, const OffsetOptions& options) {
  if (auto error = check_distance(options.distance)) return *error;
  const std::vector<dvec3> fnormals = face_normals(mesh);
  return offset_through_soup(mesh, options.distance, nullptr, fnormals, vertex_normals(mesh, fnormals));
}

Result<OffsetResult> lattice(const Mesh& mesh, const LatticeOptions& options) {
  if (!(options.width > 0.0) || !(options.distance > 0.0) || !std::isfinite(options.width) ||
      !std::isfinite(options.distance)) {
    return KernelError{KernelError::Kind::InvalidArgument,
                       fmt::format("lattice width {} and distance {} must be positive",
                                   options.width, options.distance),
                       {},
                       {},
                       {}};
  }
  // Frame soup: the input vertices, then one inner vertex per face corner.
  PolygonSoup frame;
  frame.positions.assign(mesh.positions().begin(), mesh.positions().end());
  std::vector<FaceId> frame_origin;
  std::vector<int32_t> outer;
  std::vector<int32_t> inner;
  for (int32_t f = 0; f < mesh.face_count(); ++f) {
    outer.clear();
    inner.clear();
    dvec3 centre(0.0);
    mesh.for_each_face_use(FaceId(f), [&](EdgeUse u) {
      outer.push_back(mesh.use_tail(u).index);
      centre += mesh.position(mesh.use_tail(u));
    });
    centre /= double(outer.size());
    for (int32_t v : outer) {
      const dvec3& p = mesh.position(VertexId(v));
      const double len = glm::length(centre - p);
      const double t = len > 0.0 ? std::min(options.width / len, 0.9) : 0.0;
      inner.push_back(frame.add_vertex(p + t * (centre - p)));
    }
    const size_t n = outer.size();
    for (size_t i = 0; i < n; ++i) {
      const size_t j = (i + 1) % n;
      frame.add_face({outer[i], outer[j], inner[j], inner[i]});
      frame_origin.push_back(FaceId(f));
      frame.face_sources.push_back(mesh.face_source(FaceId(f)));
      if (mesh.has_face_colors()) {
        frame.face_colors.push_back(mesh.face_color(FaceId(f)));
      }
    }
  }
  auto frame_mesh = build_mesh(frame);
  if (!frame_mesh.has_value()) {
    KernelError error = frame_mesh.error();
    error.message = "lattice frame is not a manifold: " + error.message;
    return error;
  }
  return offset_impl(*frame_mesh, options.distance, &frame_origin, true);
}

}  // namespace nomec::kernel
