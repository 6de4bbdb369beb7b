// Merge tests: separate faces zipped into closed shapes, strips glued into Möbius bands,
// opposite-orientation joins becoming Möbius edges, tolerance handling, vertices that
// only touch staying apart, and refusal of non-manifold joins.
#include "kernel/merge.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <numeric>
#include <random>
#include <set>

#include "kernel/topology.h"
#include "tests/kernel/build.h"
#include "tests/kernel/shapes.h"

namespace nomec::kernel {
namespace {

using testing::Glue;
using testing::grid_soup;

using testing::build;

// Each face of `soup` as its own mesh with its own vertices.
std::vector<Mesh> explode(const PolygonSoup& soup) {
  std::vector<Mesh> parts;
  size_t offset = 0;
  for (int32_t f = 0; f < soup.face_count(); ++f) {
    PolygonSoup part;
    std::vector<int32_t> face;
    for (int32_t i = 0; i < soup.face_sizes[f]; ++i) {
      face.push_back(part.add_vertex(soup.positions[soup.face_vertices[offset + i]]));
    }
    offset += soup.face_sizes[f];
    part.add_face(face);
    part.face_sources.push_back({f, 3});
    parts.push_back(build(part));
  }
  return parts;
}

TEST(Merge, SixSeparateCubeFacesMakeClosedCube) {
  std::vector<Mesh> parts = explode(testing::cube_soup());
  std::vector<const Mesh*> ptrs;
  for (const Mesh& m : parts) {
    ptrs.push_back(&m);
  }
  Mesh all = concatenate(ptrs);
  EXPECT_EQ(all.vertex_count(), 24);
  EXPECT_EQ(topology(all).components.size(), 6u);
  auto merged = merge(ptrs);
  ASSERT_TRUE(merged.has_value()) << merged.error().message;
  EXPECT_EQ(merged->joined_edge_count, 12);
  const Mesh& cube = merged->mesh;
  TopologyReport r = topology(cube);
  ASSERT_EQ(r.components.size(), 1u);
  EXPECT_EQ(r.vertex_count, 8);
  EXPECT_EQ(r.edge_count, 12);
  EXPECT_EQ(r.face_count, 6);
  EXPECT_EQ(r.euler_characteristic, 2);
  EXPECT_TRUE(r.is_closed);
  EXPECT_TRUE(r.is_orientable);
  EXPECT_FALSE(cube.has_mobius_edges());
  // Provenance survives: face 4 came from input face 4 of instance 3.
  EXPECT_EQ(cube.face_source(FaceId(4)), (FaceSource{4, 3}));
  // The vertex map sends all three copies of a corner to one vertex.
  EXPECT_EQ(merged->vertex_map.size(), 24u);
}

TEST(Merge, SharpnessSurvivesWithTheLargerValue) {
  std::vector<Mesh> parts = explode(testing::cube_soup());
  // Faces 0 and 4 both contain corner (0,0,0) and edge (0,0,0)-(0,1,0).
  parts[0].set_vertex_sharpness(VertexId(0), 1.0f);
  parts[4].set_vertex_sharpness(VertexId(0), 2.5f);
  parts[0].set_sharpness(parts[0].find_edge(VertexId(0), VertexId(1)), 3.0f);
  std::vector<const Mesh*> ptrs;
  for (const Mesh& m : parts) {
    ptrs.push_back(&m);
  }
  auto merged = merge(ptrs);
  ASSERT_TRUE(merged.has_value()) << merged.error().message;
  const Mesh& cube = merged->mesh;
  const VertexId origin = merged->vertex_map[0];
  EXPECT_EQ(cube.position(origin), glm::dvec3(0, 0, 0));
  EXPECT_EQ(cube.vertex_sharpness(origin), 2.5f);
  const EdgeId edge = cube.find_edge(origin, merged->vertex_map[1]);
  ASSERT_TRUE(edge.is_valid());
  EXPECT_EQ(cube.sharpness(edge), 3.0f);
  EXPECT_FALSE(cube.is_boundary(edge));
}

TEST(Merge, StripGluedWithHalfTwistIsMobiusBand) {
  // An open 6x1 strip placed on a Möbius parametrisation: its two end rungs coincide
  // with opposite orientation.
  PolygonSoup strip = grid_soup(6, 1, Glue::None);
  PolygonSoup band = grid_soup(6, 1, Glue::Mobius);
  for (int i = 0; i <= 6; ++i) {
    for (int j = 0; j <= 1; ++j) {
      const int src = (i % 6) * 2 + (i == 6 ? 1 - j : j);
      strip.positions[i * 2 + j] = band.positions[src];
    }
  }
  auto merged = merge(build(strip), {.tolerance = 1e-9});
  ASSERT_TRUE(merged.has_value()) << merged.error().message;
  EXPECT_EQ(merged->joined_edge_count, 1);
  TopologyReport r = topology(merged->mesh);
  EXPECT_EQ(r.vertex_count, 12);
  EXPECT_EQ(r.euler_characteristic, 0);
  EXPECT_FALSE(r.is_orientable);
  EXPECT_EQ(r.border_loop_count, 1);
  EXPECT_EQ(r.components[0].mobius_edge_count, 1);
}

TEST(Merge, OppositeOrientationJoinIsMobiusEdge) {
  PolygonSoup s;
  s.add_vertex({0, 0, 0});
  s.add_vertex({1, 0, 0});
  s.add_vertex({1, 1, 0});
  s.add_vertex({0, 1, 0});
  s.add_vertex({1, 0, 0});  // duplicate of 1
  s.add_vertex({2, 0, 0});
  s.add_vertex({2, 1, 0});
  s.add_vertex({1, 1, 0});  // duplicate of 2
  s.add_face({0, 1, 2, 3});
  s.add_face({4, 7, 6, 5});  // reversed orientation
  auto merged = merge(build(s));
  ASSERT_TRUE(merged.has_value());
  EXPECT_EQ(merged->mesh.vertex_count(), 6);
  EXPECT_EQ(merged->mesh.edge_count(), 7);
  EdgeId shared = merged->mesh.find_edge(merged->vertex_map[1], merged->vertex_map[2]);
  ASSERT_TRUE(shared.is_valid());
  EXPECT_TRUE(merged->mesh.is_mobius(shared));
  EXPECT_FALSE(merged->mesh.is_boundary(shared));
  TopologyReport r = topology(merged->mesh);
  EXPECT_TRUE(r.is_orientable);  // a disk, just with one face listed backwards
  EXPECT_EQ(r.euler_characteristic, 1);
}

TEST(Merge, ToleranceAndAveraging) {
  PolygonSoup s;
  s.add_vertex({0, 0, 0});
  s.add_vertex({1, 0, 0});
  s.add_vertex({0.5, 1, 0});
  s.add_vertex({1.001, 0, 0});
  s.add_vertex({0.0, 0.001, 0});
  s.add_vertex({0.5, -1, 0});
  s.add_face({0, 1, 2});
  s.add_face({3, 4, 5});
  Mesh m = build(s);
  auto tight = merge(m, {.tolerance = 1e-4});
  ASSERT_TRUE(tight.has_value());
  EXPECT_EQ(tight->joined_edge_count, 0);
  EXPECT_EQ(tight->mesh.vertex_count(), 6);
  auto loose = merge(m, {.tolerance = 0.01});
  ASSERT_TRUE(loose.has_value());
  EXPECT_EQ(loose->joined_edge_count, 1);
  EXPECT_EQ(loose->mesh.vertex_count(), 4);
  const glm::dvec3 p = loose->mesh.position(loose->vertex_map[1]);
  EXPECT_NEAR(p.x, 1.0005, 1e-12);
  auto bad = merge(m, {.tolerance = -1});
  ASSERT_FALSE(bad.has_value());
  EXPECT_EQ(bad.error().kind, KernelError::Kind::InvalidArgument);
}

// The spatial search against every pair: triangles in pairs whose shared edge is copied
// with a jitter from well inside to just beyond the tolerance, scattered over a large box at
// several scales of tolerance (so that vertices fall near the sides of the search's cells
// and across them), give exactly the joins and merged vertices of a brute-force matching of
// all boundary edges (`merge` joins a boundary edge with the one other boundary edge, of
// another face, whose ends both lie within the tolerance of its ends).
TEST(Merge, SpatialSearchFindsExactlyTheCoincidingEdges) {
  std::mt19937_64 rng(18);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const double tol : {1e-9, 1e-4, 0.013, 0.5}) {
    PolygonSoup s;
    auto jittered = [&](glm::dvec3 p) {
      // Within the tolerance, at it, or up to 30 % beyond it, in a random direction.
      const double len = tol * (unit(rng) < 0.2 ? 1.0 : 1.3 * unit(rng));
      glm::dvec3 d(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5);
      return p + len * d / std::max(glm::length(d), 1e-300);
    };
    for (int k = 0; k < 300; ++k) {
      // A corner on a cell side of the search (a multiple of twelve tolerances) now and then.
      glm::dvec3 p(unit(rng), unit(rng), unit(rng));
      p *= 2000 * tol;
      if (k % 5 == 0) p.x = 12 * tol * std::round(p.x / (12 * tol)) + (unit(rng) - 0.5) * 3 * tol;
      const glm::dvec3 q = p + glm::dvec3(0, 0, 40 * tol);
      const int32_t a = s.add_vertex(p), b = s.add_vertex(q), c = s.add_vertex(p + glm::dvec3(40 * tol, 0, 0));
      s.add_face({a, b, c});
      const int32_t a2 = s.add_vertex(jittered(p)), b2 = s.add_vertex(jittered(q));
      const int32_t c2 = s.add_vertex(p + glm::dvec3(-40 * tol, 0, 20 * tol));
      s.add_face({b2, a2, c2});
    }
    const Mesh m = build(s);
    // Brute force over every pair of boundary edges.
    auto coincide = [&](VertexId x, VertexId y) {
      const glm::dvec3 d = m.position(x) - m.position(y);
      return glm::dot(d, d) <= tol * tol;
    };
    std::vector<int32_t> parent(static_cast<size_t>(m.vertex_count()));
    std::iota(parent.begin(), parent.end(), 0);
    auto root = [&](int32_t x) {
      while (parent[x] != x) x = parent[x];
      return x;
    };
    auto unite = [&](int32_t x, int32_t y) {
      x = root(x);
      y = root(y);
      if (x != y) parent[std::max(x, y)] = std::min(x, y);
    };
    int32_t joined = 0, conflicts = 0;
    for (int32_t e = 0; e < m.edge_count(); ++e) {
      if (!m.is_boundary(EdgeId(e))) continue;
      const VertexId a = m.edge_vertex(EdgeId(e), 0), b = m.edge_vertex(EdgeId(e), 1);
      int32_t found = 0, partner = -1;
      VertexId pa, pb;
      for (int32_t e2 = 0; e2 < m.edge_count(); ++e2) {
        if (e2 == e || !m.is_boundary(EdgeId(e2)) || m.edge_face(EdgeId(e2), 0) == m.edge_face(EdgeId(e), 0)) continue;
        for (int end = 0; end < 2; ++end) {
          const VertexId x = m.edge_vertex(EdgeId(e2), end), y = m.edge_vertex(EdgeId(e2), 1 - end);
          if (coincide(x, a) && coincide(y, b)) {
            ++found;
            partner = e2;
            pa = x;
            pb = y;
          }
        }
      }
      if (found > 1) ++conflicts;
      if (found != 1) continue;
      if (e < partner) ++joined;
      unite(a.index, pa.index);
      unite(b.index, pb.index);
    }
    ASSERT_EQ(conflicts, 0) << "tolerance " << tol;  // the pairs are far apart
    std::set<int32_t> classes;
    for (int32_t v = 0; v < m.vertex_count(); ++v) classes.insert(root(v));
    auto merged = merge(m, {.tolerance = tol});
    ASSERT_TRUE(merged.has_value()) << merged.error().message;
    EXPECT_EQ(merged->joined_edge_count, joined) << "tolerance " << tol;
    EXPECT_EQ(merged->mesh.vertex_count(), static_cast<int32_t>(classes.size())) << "tolerance " << tol;
    for (int32_t v = 0; v < m.vertex_count(); ++v) {
      for (int32_t w : {v + 1, v - 1}) {
        if (w < 0 || w >= m.vertex_count()) continue;
        EXPECT_EQ(merged->vertex_map[v] == merged->vertex_map[w], root(v) == root(w)) << v << " " << w;
      }
    }
    // Both outcomes, many times: joined pairs and pairs left apart.
    EXPECT_GT(joined, 60) << "tolerance " << tol;
    EXPECT_LT(joined, 290) << "tolerance " << tol;
  }
}

TEST(Merge, TouchingAtOneVertexIsNotMerged) {
  PolygonSoup s;
  s.add_vertex({0, 0, 0});
  s.add_vertex({1, 0, 0});
  s.add_vertex({1, 1, 0});
  s.add_vertex({0, 0, 0});
  s.add_vertex({-1, 0, 0});
  s.add_vertex({-1, -1, 0});
  s.add_face({0, 1, 2});
  s.add_face({3, 4, 5});
  auto merged = merge(build(s));
  ASSERT_TRUE(merged.has_value());
  EXPECT_EQ(merged->mesh.vertex_count(), 6);
  EXPECT_EQ(topology(merged->mesh).components.size(), 2u);
}

TEST(Merge, ThreeFacesOnOneEdgeAreRefused) {
  // A fin: three quads hinged on the segment (0,0,0)-(0,0,1), each with its own copy.
  PolygonSoup s;
  for (int k = 0; k < 3; ++k) {
    const double a = 2.0944 * k;
    const int base = s.add_vertex({0, 0, 0});
    s.add_vertex({0, 0, 1});
    s.add_vertex({std::cos(a), std::sin(a), 1});
    s.add_vertex({std::cos(a), std::sin(a), 0});
    s.add_face({base, base + 1, base + 2, base + 3});
  }
  auto merged = merge(build(s));
  ASSERT_FALSE(merged.has_value());
  EXPECT_EQ(merged.error().kind, KernelError::Kind::NonManifoldMerge);
  EXPECT_EQ(merged.error().edges.size(), 3u);
  EXPECT_EQ(merged.error().faces.size(), 3u);
}

TEST(Merge, JoinDuplicatingAFaceIsRefused) {
  // Mesh A: triangles (p q r) and (q p s) sharing the interior edge p-q. Mesh B: a copy
  // of (p q r). B's edges q-r and r-p match A's border, which merges B onto T1 and puts
  // three faces on p-q; that edge was never a candidate (it is interior in A), so the
  // refusal comes from the rebuilt mesh.
  PolygonSoup s;
  const int p = s.add_vertex({0, 0, 0});
  const int q = s.add_vertex({1, 0, 0});
  const int r = s.add_vertex({0.5, 1, 0});
  const int t = s.add_vertex({0.5, -1, 0});
  s.add_face({p, q, r});
  s.add_face({q, p, t});
  const int p2 = s.add_vertex({0, 0, 0});
  const int q2 = s.add_vertex({1, 0, 0});
  const int r2 = s.add_vertex({0.5, 1, 0});
  s.add_face({p2, q2, r2});
  auto merged = merge(build(s));
  ASSERT_FALSE(merged.has_value());
  EXPECT_EQ(merged.error().kind, KernelError::Kind::NonManifoldMerge);
  EXPECT_EQ(merged.error().faces, (std::vector<FaceId>{FaceId(0), FaceId(1), FaceId(2)}));
  EXPECT_NE(merged.error().message.find("more than two faces"), std::string::npos)
      << merged.error().message;
}

}  // namespace
}  // namespace nomec::kernel

namespace nomec::kernel {
namespace {

// append_disjoint gives the same mesh as concatenate (which rebuilds from a soup): same
// positions, faces in loop order, Möbius edges, borders, sharpness and sources.
TEST(AppendDisjoint, EqualsConcatenateOnMixedParts) {
  PolygonSoup mobius = testing::grid_soup(6, 2, Glue::Mobius);
  PolygonSoup cube = testing::cube_soup();
  cube.face_sources.assign(cube.face_count(), FaceSource{7, 2});
  Mesh a = build(mobius), b = build(cube), c = build(testing::grid_soup(3, 3, Glue::None));
  b.set_sharpness(EdgeId(0), 2.0f);
  c.set_vertex_sharpness(VertexId(1), 1.5f);
  std::vector<const Mesh*> parts = {&a, &b, &c};
  Mesh fast = append_disjoint(parts);
  Mesh slow = concatenate(parts);
  PolygonSoup fs = to_soup(fast), ss = to_soup(slow);
  EXPECT_EQ(fs.positions, ss.positions);
  EXPECT_EQ(fs.face_sizes, ss.face_sizes);
  EXPECT_EQ(fs.face_vertices, ss.face_vertices);
  EXPECT_EQ(fs.face_sources, ss.face_sources);
  ASSERT_EQ(fs.creases.size(), 1u);
  EXPECT_EQ(fs.creases[0].sharpness, 2.0f);
  ASSERT_EQ(fs.corners.size(), 1u);
  EXPECT_EQ(fs.corners[0].vertex, a.vertex_count() + b.vertex_count() + 1);
  TopologyReport tf = topology(fast), ts = topology(slow);
  EXPECT_EQ(tf.edge_count, ts.edge_count);
  EXPECT_TRUE(fast.has_mobius_edges());
  EXPECT_TRUE(slow.has_mobius_edges());
  EXPECT_EQ(tf.border_loop_count, ts.border_loop_count);
  EXPECT_EQ(tf.components.size(), 3u);
  EXPECT_EQ(fast.border_loops().size(), slow.border_loops().size());
  EXPECT_FALSE(tf.is_orientable);
}

}  // namespace
}  // namespace nomec::kernel
