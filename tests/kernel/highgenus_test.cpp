// High-genus constructions: every expected count is derived in the test's comment from
// Euler's formula χ = V − E + F = 2 − 2g (closed orientable) before it is asserted, and
// every result is checked with the winged-edge invariants, closedness and orientability
// (orientable exactly when the input was).
#include "kernel/highgenus.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include "kernel/subdivide.h"
#include "kernel/topology.h"
#include "tests/kernel/build.h"
#include "tests/kernel/shapes.h"

namespace nomec::kernel {
namespace {

using testing::Glue;
using testing::grid_soup;

using testing::build;

/// A box of `n` unit cubes in a row: 4(n + 1) V, 4n + 2 quads (top faces t_i = 0 … n−1
/// first), a sphere.
PolygonSoup box_soup(int n) {
  PolygonSoup s;
  for (int i = 0; i <= n; ++i) {
    for (int k = 0; k < 4; ++k) s.add_vertex({double(i), double(k & 1), double(k >> 1)});
  }
  auto v = [](int i, int y, int z) { return 4 * i + y + 2 * z; };
  for (int i = 0; i < n; ++i) s.add_face({v(i, 0, 1), v(i + 1, 0, 1), v(i + 1, 1, 1), v(i, 1, 1)});  // top
  for (int i = 0; i < n; ++i) s.add_face({v(i + 1, 0, 0), v(i, 0, 0), v(i, 1, 0), v(i + 1, 1, 0)});  // bottom
  for (int i = 0; i < n; ++i) s.add_face({v(i, 0, 0), v(i + 1, 0, 0), v(i + 1, 0, 1), v(i, 0, 1)});  // y = 0
  for (int i = 0; i < n; ++i) s.add_face({v(i, 1, 1), v(i + 1, 1, 1), v(i + 1, 1, 0), v(i, 1, 0)});  // y = 1
  s.add_face({v(0, 0, 0), v(0, 0, 1), v(0, 1, 1), v(0, 1, 0)});
  s.add_face({v(n, 0, 1), v(n, 0, 0), v(n, 1, 0), v(n, 1, 1)});
  return s;
}

using testing::tetra_soup;

// The one component's report, after checking the mesh's invariants.
ComponentTopology single(const Mesh& m) {
  EXPECT_EQ(mesh_problem(m), "");
  TopologyReport t = topology(m);
  EXPECT_EQ(t.components.size(), 1u);
  return t.components.empty() ? ComponentTopology{} : t.components[0];
}

// The face whose centroid is nearest to `p`.
FaceId face_near(const Mesh& m, glm::dvec3 p) {
  FaceId best;
  double d = 1e300;
  for (int32_t f = 0; f < m.face_count(); ++f) {
    glm::dvec3 c(0.0);
    const auto vs = m.face_vertices(FaceId(f));
    for (VertexId v : vs) c += m.position(v);
    c /= double(vs.size());
    if (glm::length(c - p) < d) d = glm::length(c - p), best = FaceId(f);
  }
  return best;
}

// ---- Sierpinski ----

TEST(Sierpinski, TetrahedronLevelOneHasGenusThree) {
  // One level: 6 midpoints, 12 corner triangles, 6 self-loops (3 merge the 4 central
  // triangles, 3 split again, leaving one face per original vertex): V = 4 + 6,
  // E = 12 + 12 + 6, F = 12 + 4 → χ = 10 − 30 + 16 = −4 = 2(V − E), genus 3.
  // Each loop is built as a triangle: +2 V and +2 E per loop, χ unchanged: V = 22,
  // E = 42, F = 16.
  auto r = sierpinski(build(tetra_soup()), SierpinskiOptions{1, 0});
  ASSERT_TRUE(r.has_value()) << r.error().message;
  ComponentTopology c = single(*r);
  EXPECT_EQ(c.vertex_count, 22);
  EXPECT_EQ(c.edge_count, 42);
  EXPECT_EQ(c.face_count, 16);
  EXPECT_EQ(c.euler_characteristic, -4);
  EXPECT_EQ(c.genus, 3);
  EXPECT_TRUE(c.is_closed);
  EXPECT_TRUE(c.is_orientable);
}

TEST(Sierpinski, TetrahedronLevelTwoHasGenusFifteen) {
  // Levels run on the mesh with its self-loops (built as triangles only at the end). With
  // N non-loop edges and L loops, a level makes V' = V + N (midpoints), C = 2N corner cuts
  // (a corner next to a loop spans it: `x v v y` is cut as one), N new loops, and
  // E' = 2N + L + C + N = 5N + L. The central polygons end as one closing face per cluster
  // of corners: one per vertex, two for a vertex with a loop (the loop separates the two
  // sub-polyhedra touching there): F' = C + V + L. So χ' = 2(V − N).
  //   Level 1 of the tetrahedron (V = 4, N = 6, L = 0): V = 10, N = 24, L = 6, F = 16,
  //   χ = −4. Level 2: V = 34, E = 126, F = 48 + 16 = 64, χ = 2(10 − 24) = −28, genus 15:
  //   16 small tetrahedra touching at 30 points (30 − 15 = 15 independent loops).
  // Building the 30 loops as triangles adds 2 V and 2 E each: V = 94, E = 186.
  auto r = sierpinski(build(tetra_soup()), SierpinskiOptions{2, 0});
  ASSERT_TRUE(r.has_value()) << r.error().message;
  ComponentTopology c = single(*r);
  EXPECT_EQ(c.vertex_count, 94);
  EXPECT_EQ(c.edge_count, 186);
  EXPECT_EQ(c.face_count, 64);
  EXPECT_EQ(c.euler_characteristic, -28);
  EXPECT_EQ(c.genus, 15);
  EXPECT_TRUE(c.is_closed);
  EXPECT_TRUE(c.is_orientable);
}

TEST(Sierpinski, CubeLevelOneHasGenusFive) {
  // χ' = 2(V − E) = 2(8 − 12) = −8: genus 5. V = 8 + 12 + 24, E = 7·12, F = 24 + 8.
  auto r = sierpinski(build(testing::cube_soup()), SierpinskiOptions{1, 0});
  ASSERT_TRUE(r.has_value()) << r.error().message;
  ComponentTopology c = single(*r);
  EXPECT_EQ(c.vertex_count, 44);
  EXPECT_EQ(c.edge_count, 84);
  EXPECT_EQ(c.face_count, 32);
  EXPECT_EQ(c.genus, 5);
}

TEST(Sierpinski, LevelZeroIsTheInputAndLimitsAreChecked) {
  Mesh cube = build(testing::cube_soup());
  auto same = sierpinski(cube, SierpinskiOptions{0, 0});
  ASSERT_TRUE(same.has_value());
  EXPECT_TRUE(has_same_topology(*same, cube));
  // Estimates F' ≤ 2E + V before each level (loops not yet built): 32, 140, 572.
  auto big = sierpinski(cube, SierpinskiOptions{3, 300});
  ASSERT_FALSE(big.has_value());
  EXPECT_NE(big.error().message.find("level 3 would make about"), std::string::npos) << big.error().message;
  EXPECT_FALSE(sierpinski(cube, SierpinskiOptions{-1, 0}).has_value());
}

TEST(Sierpinski, MobiusBandStaysSingleSided) {
  // A band of 6 quads, each touching the border: the 6 interior edges' midpoints get
  // loops, the 12 border ones not. V = 12 + 18 + 12, E = 36 + 24 + 6 + 12, F = 24 + 2
  // (the 6 loops join the 6 central quads around the band: 5 merges, then 1 split):
  // χ = 42 − 78 + 26 = −10, and the faces keep their orientations: single-sided.
  auto r = sierpinski(build(grid_soup(6, 1, Glue::Mobius, 0.01)), SierpinskiOptions{1, 0});
  ASSERT_TRUE(r.has_value()) << r.error().message;
  EXPECT_EQ(mesh_problem(*r), "");
  TopologyReport t = topology(*r);
  EXPECT_FALSE(t.is_orientable);
  EXPECT_EQ(t.euler_characteristic, -10);
}

// ---- Menger ----

TEST(Menger, UnitCubeAtAThirdIsTheLevelOneSponge) {
  // Per face: 4 corner squares, 4 edge squares, 4 tunnel walls (12 quads, 72 in all).
  // With thickness 1/3 the inner copies meet at the central cube's edges, so the inner
  // walls and corner polygons collapse away: V = 8 + 24 trisection points + 24 insets +
  // 8 inner corners = 64, E = 36 + 72 + 24 + 12 = 144, F = 72: χ = −8, genus 5 — the
  // level-1 Menger sponge (its solid is the thickened 1-skeleton of the cube, 8 vertices
  // and 12 edges: genus 12 − 8 + 1 = 5).
  auto r = menger(build(testing::cube_soup()), MengerOptions{1, 1.0 / 3.0, 0, 0});
  ASSERT_TRUE(r.has_value()) << r.error().message;
  ComponentTopology c = single(*r);
  EXPECT_EQ(c.vertex_count, 64);
  EXPECT_EQ(c.edge_count, 144);
  EXPECT_EQ(c.face_count, 72);
  EXPECT_EQ(c.genus, 5);
  EXPECT_TRUE(c.is_closed);
  EXPECT_TRUE(c.is_orientable);
}

TEST(Menger, RightAnglesCollapseTheWallsAtAnyThickness) {
  // At a cube corner every face's inner copy ends at v + t·(1, 1, 1), whatever t is: the
  // walls always collapse, and thickness 0.2 has the counts of the third.
  auto r = menger(build(testing::cube_soup()), MengerOptions{1, 0.2, 0, 0});
  ASSERT_TRUE(r.has_value()) << r.error().message;
  ComponentTopology c = single(*r);
  EXPECT_EQ(c.vertex_count, 64);
  EXPECT_EQ(c.edge_count, 144);
  EXPECT_EQ(c.face_count, 72);
  EXPECT_EQ(c.genus, 5);
}

TEST(Menger, CubeLevelTwoHasGenusEightyOne) {
  // Without collapse a level gives χ' = 2(V − E); collapsing a wall removes as many
  // vertices and faces as edges, so χ is kept. From level 1 (V = 64, E = 144):
  // χ = −160, genus 81, the genus of the level-2 Menger sponge.
  auto r = menger(build(testing::cube_soup()), MengerOptions{2, 1.0 / 3.0, 0, 0});
  ASSERT_TRUE(r.has_value()) << r.error().message;
  ComponentTopology c = single(*r);
  EXPECT_EQ(c.euler_characteristic, -160);
  EXPECT_EQ(c.genus, 81);
  EXPECT_TRUE(c.is_closed);
  EXPECT_TRUE(c.is_orientable);
}

TEST(Menger, TetrahedronKeepsItsInnerWallsAndBadOptionsFail) {
  // Acute corners: the inner copies do not meet, nothing collapses. V = 4 + 12 trisection
  // points + 12 insets + 12 inner corners = 40; F = 3·12 (corner and edge squares, tunnel
  // walls) + 6 inner walls + 4 inner triangles = 46; E = 18 + 36 + 24 + 12 = 90:
  // χ = −4 = 2(V − E) of the tetrahedron, genus 3.
  auto r = menger(build(tetra_soup()), MengerOptions{1, 0.2, 0, 0});
  ASSERT_TRUE(r.has_value()) << r.error().message;
  ComponentTopology c = single(*r);
  EXPECT_EQ(c.vertex_count, 40);
  EXPECT_EQ(c.edge_count, 90);
  EXPECT_EQ(c.face_count, 46);
  EXPECT_EQ(c.genus, 3);
  EXPECT_TRUE(c.is_orientable);
  Mesh cube = build(testing::cube_soup());
  EXPECT_FALSE(menger(cube, MengerOptions{1, 0, 0, 0}).has_value());
  EXPECT_FALSE(menger(cube, MengerOptions{1, 0.2, -1, 0}).has_value());
  EXPECT_FALSE(menger(cube, MengerOptions{3, 0.2, 0, 5000}).has_value());
}

TEST(Menger, TorusAndKleinBottleKeepTheirSidedness) {
  // An 8 x 4 grid glued into a torus or a Klein bottle (V = 32, E = 64):
  // χ' = 2(V − E) = −64 for both; the Klein bottle's sponge is single-sided (its walls
  // cross the Möbius edges), the torus's two-sided.
  for (Glue glue : {Glue::Torus, Glue::Klein}) {
    auto r = menger(build(grid_soup(8, 4, glue, 0.01)), MengerOptions{1, 0.05, 0, 0});
    ASSERT_TRUE(r.has_value()) << r.error().message;
    ComponentTopology c = single(*r);
    EXPECT_EQ(c.euler_characteristic, -64);
    EXPECT_TRUE(c.is_closed);
    EXPECT_EQ(c.is_orientable, glue == Glue::Torus);
  }
}

// ---- handles ----

TEST(Handle, PipeAddsOneToTheGenus) {
  // A box of 5 cubes (V = 24, E = 44, F = 22, χ = 2); a one-segment pipe between the top
  // faces t0 and t4 removes both and adds 4 quads and 4 edges: V = 24, E = 48, F = 24,
  // χ = 0, genus 1.
  HandleOptions o;
  o.faces[0] = FaceId(0);
  o.faces[1] = FaceId(4);
  auto r = connect_faces(build(box_soup(5)), o);
  ASSERT_TRUE(r.has_value()) << r.error().message;
  ComponentTopology c = single(*r);
  EXPECT_EQ(c.vertex_count, 24);
  EXPECT_EQ(c.edge_count, 48);
  EXPECT_EQ(c.face_count, 24);
  EXPECT_EQ(c.genus, 1);
  EXPECT_TRUE(c.is_orientable);
  // Between the top faces of a box of 3 cubes the mirror pairing of the corners needs
  // edges that exist already (t0's corners at x = 1 are joined to t2's at x = 2 through
  // t1): refused, clearly.
  o.faces[1] = FaceId(2);
  o.corners[0] = VertexId(2);   // (0 0 1)
  o.corners[1] = VertexId(14);  // (3 0 1)
  auto dup = connect_faces(build(box_soup(3)), o);
  ASSERT_FALSE(dup.has_value());
  EXPECT_NE(dup.error().message.find("that an edge joins already"), std::string::npos) << dup.error().message;
}

TEST(Handle, CurvedTwistedHandleWithSegments) {
  // Box of 3 cubes (V = 16, E = 28, F = 14), 6 segments between t0 and t2: 5 rings of 4
  // new vertices, 5·4 ring edges and 6·4 lengthwise edges, 6·4 quads: V = 36,
  // E = 28 + 20 + 24 = 72, F = 12 + 24 = 36 → χ = 0, genus 1.
  HandleOptions o;
  o.faces[0] = FaceId(0);
  o.faces[1] = FaceId(2);
  o.corners[0] = VertexId(2);  // (0 0 1)
  o.corners[1] = VertexId(14);  // (3 0 1)
  o.segments = 6;
  o.weights[0] = 2;
  o.weights[1] = 2;
  o.twist = 1;
  auto r = connect_faces(build(box_soup(3)), o);
  ASSERT_TRUE(r.has_value()) << r.error().message;
  ComponentTopology c = single(*r);
  EXPECT_EQ(c.vertex_count, 36);
  EXPECT_EQ(c.edge_count, 72);
  EXPECT_EQ(c.face_count, 36);
  EXPECT_EQ(c.genus, 1);
  EXPECT_TRUE(c.is_orientable);
  // The handle arches over the box: its rings rise above the top (z = 1) along the
  // normals, the highest by more than half the distance between the faces' centres.
  double top = 0;
  for (int32_t v = 16; v < r->vertex_count(); ++v) top = std::max(top, r->position(VertexId(v)).z);
  EXPECT_GT(top, 2.0);
}

TEST(Handle, TwoSeparateMeshesAreJoinedAndUnequalFacesEqualised) {
  // A cube and a tetrahedron: the triangle gets its longest edge split (the tetrahedron
  // face across it gets the vertex too): V = 8 + 5, E = 12 + 7 + 4, F = 6 + 4 − 2 + 4.
  // χ = 13 − 23 + 12 = 2: one sphere.
  PolygonSoup s = testing::cube_soup();
  PolygonSoup t = tetra_soup();
  for (const glm::dvec3& p : t.positions) s.add_vertex(p + glm::dvec3(4, 0, 0));
  for (int32_t f = 0; f < t.face_count(); ++f) {
    s.add_face({t.face_vertices[3 * f] + 8, t.face_vertices[3 * f + 1] + 8, t.face_vertices[3 * f + 2] + 8});
  }
  Mesh both = build(s);
  EXPECT_EQ(topology(both).components.size(), 2u);
  HandleOptions o;
  o.faces[0] = FaceId(5);  // x = 1
  o.faces[1] = FaceId(6 + 1);
  auto r = connect_faces(both, o);
  ASSERT_TRUE(r.has_value()) << r.error().message;
  ComponentTopology c = single(*r);
  EXPECT_EQ(c.vertex_count, 13);
  EXPECT_EQ(c.edge_count, 23);
  EXPECT_EQ(c.face_count, 12);
  EXPECT_EQ(c.genus, 0);
  EXPECT_TRUE(c.is_orientable);
}

TEST(Handle, AcrossAKleinBottleItStaysSingleSided) {
  // χ = 0 before; a handle costs 2: χ = −2, still single-sided and closed.
  Mesh k = build(grid_soup(8, 4, Glue::Klein, 0.01));
  HandleOptions o;
  o.faces[0] = FaceId(0);
  o.faces[1] = FaceId(4 * 4 + 2);
  o.segments = 3;
  auto r = connect_faces(k, o);
  ASSERT_TRUE(r.has_value()) << r.error().message;
  ComponentTopology c = single(*r);
  EXPECT_EQ(c.euler_characteristic, -2);
  EXPECT_FALSE(c.is_orientable);
  EXPECT_TRUE(c.is_closed);
}

TEST(Handle, RefusesTouchingFacesAndForeignCorners) {
  Mesh cube = build(testing::cube_soup());
  HandleOptions o;
  o.faces[0] = FaceId(0);
  o.faces[1] = FaceId(2);  // shares the edge 0-1 with face 0
  auto r = connect_faces(cube, o);
  ASSERT_FALSE(r.has_value());
  EXPECT_NE(r.error().message.find("share a vertex"), std::string::npos);
  o.faces[1] = FaceId(1);
  o.corners[0] = VertexId(4);  // a top vertex, not on the bottom face
  EXPECT_FALSE(connect_faces(cube, o).has_value());
  o.corners[0] = VertexId::None();
  o.faces[1] = FaceId(0);
  EXPECT_FALSE(connect_faces(cube, o).has_value());
  o.faces[1] = FaceId(9);
  EXPECT_FALSE(connect_faces(cube, o).has_value());
}

// ---- rind ----

Mesh rounded_cube() {
  // The cube subdivided twice: 96 quads, 4 x 4 per side.
  auto s = subdivide(build(testing::cube_soup()), SubdivisionOptions{});
  EXPECT_TRUE(s.has_value());
  auto t = subdivide(s->back().mesh, SubdivisionOptions{});
  EXPECT_TRUE(t.has_value());
  return std::move(t->back().mesh);
}

TEST(Rind, PunchingKHolesThroughASphereGivesGenusKMinusOne) {
  // The crust of a sphere is two spheres (χ = 4). A punch removes 2 faces and adds n
  // walls and n edges: χ drops by 2, so k separate punches give χ = 4 − 2k, one
  // component for k ≥ 1, genus k − 1.
  Mesh sphere = rounded_cube();
  const glm::dvec3 c = 0.5 * (bounding_box(sphere).min + bounding_box(sphere).max);
  const glm::dvec3 targets[3] = {c + glm::dvec3(0.1, 0.1, 1), c + glm::dvec3(-0.1, -0.1, -1), c + glm::dvec3(1, 0.1, 0.1)};
  for (int k = 1; k <= 3; ++k) {
    RindOptions o;
    o.thickness = 0.05;
    for (int i = 0; i < k; ++i) o.punch.push_back(face_near(sphere, targets[i]));
    auto r = rind(sphere, o);
    ASSERT_TRUE(r.has_value()) << r.error().message;
    ComponentTopology t = single(*r);
    EXPECT_EQ(t.euler_characteristic, 4 - 2 * k) << k;
    EXPECT_EQ(t.genus, k - 1) << k;
    EXPECT_TRUE(t.is_closed);
    EXPECT_TRUE(t.is_orientable);
  }
}

TEST(Rind, AdjacentPunchesMakeOneHoleAndPeelKeepsTheGenus) {
  Mesh sphere = rounded_cube();
  // Two neighbouring faces on top: one region, one hole: χ = 4 − 2 = 2, genus 0.
  RindOptions o;
  o.thickness = 0.05;
  const FaceId a = face_near(sphere, {0.4, 0.4, 1.2}), b = face_near(sphere, {0.6, 0.4, 1.2});
  ASSERT_NE(a, b);
  o.punch = {a, b};
  auto r = rind(sphere, o);
  ASSERT_TRUE(r.has_value()) << r.error().message;
  EXPECT_EQ(single(*r).genus, 0);
  // Peeling them instead: the outer sheet sinks to a floor, the two sheets stay apart.
  RindOptions p;
  p.thickness = 0.05;
  p.peel = {a, b};
  auto q = rind(sphere, p);
  ASSERT_TRUE(q.has_value()) << q.error().message;
  TopologyReport t = topology(*q);
  ASSERT_EQ(t.components.size(), 2u);
  EXPECT_EQ(t.euler_characteristic, 4);
  EXPECT_TRUE(t.is_closed);
  // A face both punched and peeled, or a punch next to a peel, is refused.
  RindOptions bad = o;
  bad.peel = {a};
  EXPECT_FALSE(rind(sphere, bad).has_value());
  bad.punch = {a};
  bad.peel = {b};
  EXPECT_FALSE(rind(sphere, bad).has_value());
}

TEST(Rind, PinchedRegionsAreRefused) {
  // Two faces touching at one vertex only: the region's edge passes the vertex twice.
  Mesh sphere = rounded_cube();
  RindOptions o;
  o.thickness = 0.05;
  o.punch = {face_near(sphere, {0.4, 0.4, 1.2}), face_near(sphere, {0.6, 0.6, 1.2})};
  auto r = rind(sphere, o);
  ASSERT_FALSE(r.has_value());
  EXPECT_NE(r.error().message.find("pinched"), std::string::npos);
}

TEST(Rind, MobiusBandCrustWithAHole) {
  // The crust of a Möbius band is a torus (χ = 0); a punch through an inner face: χ = −2,
  // genus 2, orientable (the crust of anything is two-sided). Face 1 is in the middle
  // row of the 8 x 3 band, away from its border.
  Mesh band = build(grid_soup(8, 3, Glue::Mobius, 0.01));
  RindOptions o;
  o.thickness = 0.05;
  o.punch = {FaceId(1)};
  auto r = rind(band, o);
  ASSERT_TRUE(r.has_value()) << r.error().message;
  ComponentTopology c = single(*r);
  EXPECT_TRUE(c.is_orientable);
  EXPECT_TRUE(c.is_closed);
  EXPECT_EQ(c.euler_characteristic, -2);
  EXPECT_EQ(c.genus, 2);
}

}  // namespace
}  // namespace nomec::kernel
