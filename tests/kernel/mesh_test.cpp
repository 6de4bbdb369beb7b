// Unit tests for the winged-edge builder and traversals: exact counts, wings, border
// loops, Möbius flags, and the structured errors for non-manifold input.
#include "kernel/mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "kernel/topology.h"
#include "tests/kernel/shapes.h"

namespace nomec::kernel {
namespace {

using testing::cube_soup;
using testing::Glue;
using testing::grid_soup;

// Every wing is consistent (kernel::mesh_problem: next/prev are inverse, consecutive uses
// share a vertex, each face's loop closes, every edge has a face).
void expect_consistent(const Mesh& m) { EXPECT_EQ(mesh_problem(m), ""); }

TEST(MeshBuilder, CubeCountsAndWings) {
  auto mesh = build_mesh(cube_soup());
  ASSERT_TRUE(mesh.has_value()) << mesh.error().message;
  EXPECT_EQ(mesh->vertex_count(), 8);
  EXPECT_EQ(mesh->edge_count(), 12);
  EXPECT_EQ(mesh->face_count(), 6);
  EXPECT_TRUE(mesh->border_loops().empty());
  EXPECT_FALSE(mesh->has_mobius_edges());
  expect_consistent(*mesh);
  for (int32_t v = 0; v < 8; ++v) {
    EXPECT_EQ(mesh->vertex_valence(VertexId(v)), 3);
    EXPECT_EQ(mesh->vertex_ring(VertexId(v)).size(), 3u);
  }
  // Faces keep their input orientation and first vertex.
  std::vector<VertexId> f0 = mesh->face_vertices(FaceId(0));
  EXPECT_EQ(f0, (std::vector<VertexId>{VertexId(0), VertexId(2), VertexId(3), VertexId(1)}));
  EXPECT_EQ(mesh->vertex_name(VertexId(3)), "v3");
  EXPECT_EQ(mesh->find_edge(VertexId(0), VertexId(2)).is_valid(), true);
  EXPECT_EQ(mesh->find_edge(VertexId(0), VertexId(7)).is_valid(), false);
}

TEST(MeshBuilder, QuadGridBorderLoop) {
  auto mesh = build_mesh(grid_soup(3, 2, Glue::None));
  ASSERT_TRUE(mesh.has_value());
  EXPECT_EQ(mesh->vertex_count(), 12);
  EXPECT_EQ(mesh->edge_count(), 17);
  EXPECT_EQ(mesh->face_count(), 6);
  ASSERT_EQ(mesh->border_loops().size(), 1u);
  std::vector<EdgeId> loop = mesh->border_loop_edges(0);
  EXPECT_EQ(loop.size(), 10u);
  // Consecutive border edges share a vertex.
  for (size_t i = 0; i < loop.size(); ++i) {
    EdgeId a = loop[i], b = loop[(i + 1) % loop.size()];
    std::set<int32_t> va{mesh->edge_vertex(a, 0).index, mesh->edge_vertex(a, 1).index};
    EXPECT_TRUE(va.count(mesh->edge_vertex(b, 0).index) || va.count(mesh->edge_vertex(b, 1).index));
    EXPECT_EQ(mesh->border_prev(b), a);
  }
  // Corner vertex of the grid: one face, valence 2; border middle: 2 faces, valence 3.
  EXPECT_EQ(mesh->vertex_ring(VertexId(0)).size(), 1u);
  EXPECT_EQ(mesh->vertex_valence(VertexId(0)), 2);
  EXPECT_EQ(mesh->vertex_valence(VertexId(1)), 3);
  EXPECT_EQ(mesh->vertex_valence(VertexId(4)), 4);  // interior (1,1)
  expect_consistent(*mesh);
}

TEST(MeshBuilder, MobiusStripHasOneMobiusEdgeAndOneBorder) {
  auto mesh = build_mesh(grid_soup(5, 1, Glue::Mobius));
  ASSERT_TRUE(mesh.has_value()) << mesh.error().message;
  EXPECT_EQ(mesh->vertex_count(), 10);
  EXPECT_EQ(mesh->edge_count(), 15);
  EXPECT_EQ(mesh->face_count(), 5);
  int mobius = 0;
  for (int32_t e = 0; e < mesh->edge_count(); ++e) {
    mobius += mesh->is_mobius(EdgeId(e)) ? 1 : 0;
  }
  EXPECT_EQ(mobius, 1);
  ASSERT_EQ(mesh->border_loops().size(), 1u);
  EXPECT_EQ(mesh->border_loop_edges(0).size(), 10u);
  expect_consistent(*mesh);
}

TEST(MeshBuilder, VertexRingCrossesMobiusEdge) {
  // Möbius band of 4 quads and 2 rows: the middle row vertices are interior with
  // valence 4; at the glued seam the ring crosses the Möbius edge and flips.
  auto mesh = build_mesh(grid_soup(4, 2, Glue::Mobius));
  ASSERT_TRUE(mesh.has_value()) << mesh.error().message;
  // Vertex (0,1) = index 1 lies on the seam (Möbius edges touch it).
  const VertexId v(1);
  std::vector<VertexCorner> ring = mesh->vertex_ring(v);
  ASSERT_EQ(ring.size(), 4u);
  std::set<int32_t> faces;
  int flipped = 0;
  for (const VertexCorner& c : ring) {
    faces.insert(c.face.index);
    EXPECT_EQ(mesh->use_tail(c.use), v);
    EXPECT_EQ(mesh->use_face(c.use), c.face);
    flipped += c.is_flipped ? 1 : 0;
  }
  EXPECT_EQ(faces.size(), 4u);
  EXPECT_EQ(flipped, 2);  // the two faces across the seam
  EXPECT_EQ(mesh->vertex_valence(v), 4);
  // A border vertex on the seam: open fan of 2 faces.
  std::vector<VertexCorner> border_ring = mesh->vertex_ring(VertexId(0));
  EXPECT_EQ(border_ring.size(), 2u);
  EXPECT_NE(border_ring[0].face, border_ring[1].face);
}

TEST(MeshBuilder, KleinBottleIsClosedWithMobiusEdges) {
  auto mesh = build_mesh(grid_soup(4, 4, Glue::Klein));
  ASSERT_TRUE(mesh.has_value()) << mesh.error().message;
  EXPECT_EQ(mesh->vertex_count(), 16);
  EXPECT_EQ(mesh->edge_count(), 32);
  EXPECT_EQ(mesh->face_count(), 16);
  EXPECT_TRUE(mesh->border_loops().empty());
  EXPECT_TRUE(mesh->has_mobius_edges());
  for (int32_t v = 0; v < 16; ++v) {
    EXPECT_EQ(mesh->vertex_ring(VertexId(v)).size(), 4u) << v;
  }
  expect_consistent(*mesh);
}

TEST(MeshBuilder, HighValenceFanAndCone) {
  // A closed cone: a 200-triangle fan around a pole plus a 200-gon base. The pole has
  // valence 200, exercising the sorted-bucket path of the builder.
  PolygonSoup s;
  const int n = 200;
  const int pole = s.add_vertex({0, 0, 1});
  for (int i = 0; i < n; ++i) {
    s.add_vertex({std::cos(0.0314159 * i), std::sin(0.0314159 * i), 0});
  }
  std::vector<int32_t> base;
  for (int i = 0; i < n; ++i) {
    s.add_face({pole, 1 + i, 1 + (i + 1) % n});
    base.push_back(n - i);
  }
  s.add_face(base);
  auto mesh = build_mesh(s);
  ASSERT_TRUE(mesh.has_value()) << mesh.error().message;
  EXPECT_EQ(mesh->edge_count(), 2 * n);
  EXPECT_TRUE(mesh->border_loops().empty());
  EXPECT_FALSE(mesh->has_mobius_edges());
  EXPECT_EQ(mesh->vertex_valence(VertexId(pole)), n);
  // Edges are numbered in order of first appearance: face 0 creates edges 0, 1, 2.
  EXPECT_EQ(mesh->find_edge(VertexId(pole), VertexId(1)), EdgeId(0));
  EXPECT_EQ(mesh->find_edge(VertexId(2), VertexId(pole)), EdgeId(2));
  expect_consistent(*mesh);
}

TEST(MeshBuilder, ThirdFaceOnEdgeIsStructuredError) {
  PolygonSoup s;
  for (int i = 0; i < 5; ++i) {
    s.add_vertex({double(i), double(i * i), 0.0}, fmt::format("p{}", i));
  }
  s.add_face({0, 1, 2});
  s.add_face({1, 0, 3});
  s.add_face({0, 1, 4});
  auto mesh = build_mesh(s);
  ASSERT_FALSE(mesh.has_value());
  const KernelError& err = mesh.error();
  EXPECT_EQ(err.kind, KernelError::Kind::NonManifoldEdge);
  ASSERT_EQ(err.edges.size(), 1u);
  EXPECT_EQ(err.vertices, (std::vector<VertexId>{VertexId(0), VertexId(1)}));
  EXPECT_EQ(err.faces, (std::vector<FaceId>{FaceId(0), FaceId(1), FaceId(2)}));
  EXPECT_NE(err.message.find("`p0`-`p1`"), std::string::npos) << err.message;
}

TEST(MeshBuilder, ManyNonManifoldEdgesListTheFirstFiveInTheMessage) {
  // Seven separate "books" of three triangles on an edge each: every edge is reported in
  // `edges` (for the diagnostics' ranges), the message names five and counts the rest.
  PolygonSoup s;
  for (int b = 0; b < 7; ++b) {
    const int32_t o = s.vertex_count();
    for (int i = 0; i < 5; ++i) s.add_vertex({10.0 * b + i, double(i * i), 0.0}, fmt::format("b{}p{}", b, i));
    s.add_face({o, o + 1, o + 2});
    s.add_face({o + 1, o, o + 3});
    s.add_face({o, o + 1, o + 4});
  }
  auto mesh = build_mesh(s);
  ASSERT_FALSE(mesh.has_value());
  const KernelError& err = mesh.error();
  EXPECT_EQ(err.edges.size(), 7u);
  EXPECT_EQ(err.faces.size(), 21u);
  EXPECT_NE(err.message.find("7 edge(s) are shared by more than two faces"), std::string::npos) << err.message;
  EXPECT_NE(err.message.find("`b4p0`-`b4p1`"), std::string::npos) << err.message;
  EXPECT_EQ(err.message.find("`b5p0`"), std::string::npos) << err.message;
  EXPECT_NE(err.message.find("; and 2 more"), std::string::npos) << err.message;
}

TEST(MeshBuilder, BowtieVertexIsRejected) {
  PolygonSoup s;
  s.add_vertex({0, 0, 0});
  s.add_vertex({1, 0, 0});
  s.add_vertex({1, 1, 0});
  s.add_vertex({-1, 0, 0});
  s.add_vertex({-1, -1, 0});
  s.add_face({0, 1, 2});
  s.add_face({0, 3, 4});
  auto mesh = build_mesh(s);
  ASSERT_FALSE(mesh.has_value());
  EXPECT_EQ(mesh.error().kind, KernelError::Kind::NonManifoldVertex);
  EXPECT_EQ(mesh.error().vertices, std::vector<VertexId>{VertexId(0)});
}

TEST(MeshBuilder, DegenerateAndUnknownVertices) {
  PolygonSoup s;
  s.add_vertex({0, 0, 0});
  s.add_vertex({1, 0, 0});
  s.add_vertex({1, 1, 0});
  s.add_face({0, 1, 1});
  auto degenerate = build_mesh(s);
  ASSERT_FALSE(degenerate.has_value());
  EXPECT_EQ(degenerate.error().kind, KernelError::Kind::DegenerateFace);
  EXPECT_EQ(degenerate.error().faces, std::vector<FaceId>{FaceId(0)});

  PolygonSoup t;
  t.add_vertex({0, 0, 0});
  t.add_face({0, 1, 2});
  auto unknown = build_mesh(t);
  ASSERT_FALSE(unknown.has_value());
  EXPECT_EQ(unknown.error().kind, KernelError::Kind::UnknownVertex);
}

TEST(MeshBuilder, FacesByNames) {
  PolygonSoup s;
  s.add_vertex({0, 0, 0}, "a");
  s.add_vertex({1, 0, 0}, "b");
  s.add_vertex({0, 1, 0}, "c");
  std::vector<std::string> good{"a", "b", "c"};
  ASSERT_TRUE(s.add_face_by_names(good).has_value());
  std::vector<std::string> bad{"a", "b", "zz"};
  auto r = s.add_face_by_names(bad);
  ASSERT_FALSE(r.has_value());
  EXPECT_EQ(r.error().kind, KernelError::Kind::UnknownVertex);
  EXPECT_NE(r.error().message.find("`zz`"), std::string::npos);
  auto mesh = build_mesh(s);
  ASSERT_TRUE(mesh.has_value());
  EXPECT_EQ(mesh->face_count(), 1);
}

TEST(MeshBuilder, CreasesAndRoundTrip) {
  PolygonSoup s = cube_soup();
  s.creases.push_back({0, 2, 2.5f});
  s.face_colors.assign(6, glm::vec3(1, 0, 0));
  auto mesh = build_mesh(s);
  ASSERT_TRUE(mesh.has_value());
  EXPECT_FLOAT_EQ(mesh->sharpness(mesh->find_edge(VertexId(2), VertexId(0))), 2.5f);
  PolygonSoup back = to_soup(*mesh);
  EXPECT_EQ(back.face_vertices, s.face_vertices);
  ASSERT_EQ(back.creases.size(), 1u);
  EXPECT_FLOAT_EQ(back.creases[0].sharpness, 2.5f);
  EXPECT_EQ(back.face_colors.size(), 6u);
  EXPECT_TRUE(back.corners.empty());
  s.corners.push_back({3, 1.5f});
  auto with_corner = build_mesh(s);
  ASSERT_TRUE(with_corner.has_value());
  EXPECT_EQ(with_corner->vertex_sharpness(VertexId(3)), 1.5f);
  ASSERT_EQ(to_soup(*with_corner).corners.size(), 1u);
  EXPECT_EQ(to_soup(*with_corner).corners[0].vertex, 3);
  s.corners.push_back({42, 1.0f});
  auto bad = build_mesh(s);
  ASSERT_FALSE(bad.has_value());
  EXPECT_EQ(bad.error().kind, KernelError::Kind::UnknownVertex);
  EXPECT_EQ(back.names.size(), 8u);
}

// has_same_topology: a moved copy (positions only) has the same topology; a different
// orientation, a crease or another face source does not.
TEST(MeshTopology, SameTopologyIgnoresPositionsOnly) {
  PolygonSoup soup = cube_soup();
  Mesh a = *build_mesh(soup);
  PolygonSoup moved = soup;
  for (glm::dvec3& p : moved.positions) p += glm::dvec3(3, 0, 1);
  EXPECT_TRUE(has_same_topology(a, *build_mesh(moved)));
  PolygonSoup flipped = soup;
  for (size_t f = 0, at = 0; f < flipped.face_sizes.size(); at += flipped.face_sizes[f++]) {
    std::reverse(flipped.face_vertices.begin() + at, flipped.face_vertices.begin() + at + flipped.face_sizes[f]);
  }
  EXPECT_FALSE(has_same_topology(a, *build_mesh(flipped)));
  Mesh creased = a;
  creased.set_sharpness(EdgeId(3), 1.0f);
  EXPECT_FALSE(has_same_topology(a, creased));
  Mesh sourced = a;
  sourced.set_face_source(FaceId(2), FaceSource{5, 1});
  EXPECT_FALSE(has_same_topology(a, sourced));
  EXPECT_FALSE(has_same_topology(a, *build_mesh(grid_soup(2, 2, Glue::None))));
}

}  // namespace
}  // namespace nomec::kernel

namespace nomec::kernel {
namespace {

// The invariant checker finds each kind of damage (and is quiet on a good mesh).
TEST(MeshProblem, FindsBrokenWings) {
  auto good = build_mesh(testing::cube_soup());
  ASSERT_TRUE(good.has_value());
  EXPECT_EQ(mesh_problem(*good), "");
  {
    Mesh m = *good;
    std::swap(MeshAccess::next(m)[0], MeshAccess::next(m)[1]);
    EXPECT_NE(mesh_problem(m), "");
  }
  {
    Mesh m = *good;
    MeshAccess::use_faces(m)[0] = FaceId(5 - MeshAccess::use_faces(m)[0].index);
    EXPECT_NE(mesh_problem(m), "");
  }
  {
    Mesh m = *good;
    MeshAccess::positions(m)[3].y = std::nan("");
    EXPECT_EQ(mesh_problem(m), "vertex 3 has a non-finite position");
  }
  {
    Mesh m = *good;
    MeshAccess::edge_vertices(m)[4] = VertexId(99);
    EXPECT_EQ(mesh_problem(m), "edge 2 has an out-of-range vertex");
  }
}

}  // namespace
}  // namespace nomec::kernel
