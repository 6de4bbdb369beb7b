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
#include <glm/geometric.hpp>

#include "kernel/large_arrays.h"

namespace nomec::kernel {

using glm::dvec3;

dvec3 newell_normal(const std::vector<dvec3>& points) {
  dvec3 n(0.0);
  for (size_t i = 0; i < points.size(); ++i) n += newell_term(points[i], points[(i + 1) % points.size()]);
  const double len = glm::length(n);
  return len > 0.0 ? n / len : dvec3(0.0);
}

std::vector<dvec3> face_normals(const Mesh& mesh) {
  std::vector<dvec3> normals(mesh.face_count());
  for (int32_t f = 0; f < mesh.face_count(); ++f) {
    // Newell: sum over edges (a, b) of (a - b) x (a + b) / 2 equals the sum of cross
    // products of consecutive edge vectors up to a factor; both give the area vector.
    dvec3 n(0.0);
    mesh.for_each_face_use(FaceId(f), [&](EdgeUse u) {
      n += newell_term(mesh.position(mesh.use_tail(u)), mesh.position(mesh.use_head(u)));
    });
    const double len = glm::length(n);
    normals[f] = len > 0.0 ? n / len : dvec3(0.0);
  }
  return normals;
}

VertexNormals vertex_normals(const Mesh& mesh, const std::vector<dvec3>& fnormals) {
  VertexNormals result;
  result.normals.assign(mesh.vertex_count(), dvec3(0.0));
  result.corner_signs.assign(2 * static_cast<size_t>(mesh.edge_count()), 0);
  result.is_mobius_vertex.assign(mesh.vertex_count(), 0);
  for (int32_t e = 0; e < mesh.edge_count(); ++e) {
    if (mesh.is_mobius(EdgeId(e))) {
      result.is_mobius_vertex[mesh.edge_vertex(EdgeId(e), 0).index] = 1;
      result.is_mobius_vertex[mesh.edge_vertex(EdgeId(e), 1).index] = 1;
    }
  }
  for (int32_t v = 0; v < mesh.vertex_count(); ++v) {
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

Result<OffsetResult> offset_impl(const Mesh& mesh, double distance,
                                 const std::vector<FaceId>* face_origin) {
  const int32_t V = mesh.vertex_count();
  const int32_t F = mesh.face_count();
  const std::vector<dvec3> fnormals = face_normals(mesh);
  const VertexNormals vn = vertex_normals(mesh, fnormals);

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

}  // namespace

Result<OffsetResult> offset(const Mesh& mesh, const OffsetOptions& options) {
  if (!(options.distance > 0.0) || !std::isfinite(options.distance)) {
    return KernelError{KernelError::Kind::InvalidArgument,
                       fmt::format("offset distance {} is not a positive number", options.distance),
                       {},
                       {},
                       {}};
  }
  return offset_impl(mesh, options.distance, nullptr);
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
  frame.positions = mesh.positions();
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
  return offset_impl(*frame_mesh, options.distance, &frame_origin);
}

}  // namespace nomec::kernel
