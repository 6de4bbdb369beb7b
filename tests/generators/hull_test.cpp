// The convex hull (backend/generators/hull.cpp): a cube's corners with points inside give the
// cube (6 quads, χ = 2, faces outward), a random cloud's hull holds every point, and
// degenerate point sets (too few, one place, one line, one plane) are errors naming `points`.
#include <cmath>
#include <random>

#include <glm/geometric.hpp>

#include "tests/generators/helpers.h"

namespace nomec::backend::testing {
namespace {

Args cloud(std::vector<glm::dvec3> points) {
  Args a;
  a.dialect = "slide";
  for (size_t i = 0; i < points.size(); ++i) a.point_names.push_back("p" + std::to_string(i));
  a.points = std::move(points);
  return a;
}

std::vector<glm::dvec3> cube_corners() {
  std::vector<glm::dvec3> out;
  for (int i = 0; i < 8; ++i) out.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  return out;
}

// Every point is inside or on every face's plane (faces outward: the plane's normal by
// Newell's method, the point no farther in front than `tol`).
void expect_holds(const kernel::PolygonSoup& s, const std::vector<glm::dvec3>& points, double tol) {
  size_t off = 0;
  for (int32_t n : s.face_sizes) {
    glm::dvec3 normal(0.0), centre(0.0);
    for (int32_t k = 0; k < n; ++k) {
      const glm::dvec3 a = s.positions[s.face_vertices[off + k]];
      normal += glm::cross(a, s.positions[s.face_vertices[off + (k + 1) % n]]);
      centre += a / double(n);
    }
    normal = glm::normalize(normal);
    for (const glm::dvec3& p : points) EXPECT_LE(glm::dot(normal, p - centre), tol);
    off += n;
  }
}

TEST(Convexhull, CubeCornersAndInsidePointsGiveTheCube) {
  // The 8 corners in order, then the centre, a point inside and a point on a side: the
  // hull is the cube, each flat side one quad. V = 8, E = 12, F = 6, χ = 8 − 12 + 6 = 2.
  std::vector<glm::dvec3> pts = cube_corners();
  pts.emplace_back(0.5, 0.5, 0.5);
  pts.emplace_back(0.2, 0.7, 0.4);
  pts.emplace_back(0.5, 0.5, 1.0);
  Generated g = run("convexhull", cloud(pts));
  kernel::TopologyReport r = topo(g.soup);
  EXPECT_EQ(r.vertex_count, 8);
  EXPECT_EQ(r.edge_count, 12);
  EXPECT_EQ(r.face_count, 6);
  EXPECT_EQ(r.euler_characteristic, 2);
  EXPECT_TRUE(r.is_closed);
  EXPECT_TRUE(r.is_orientable);
  for (int32_t n : g.soup.face_sizes) EXPECT_EQ(n, 4);
  EXPECT_NEAR(signed_volume(g.soup), 1.0, 1e-12);  // the unit cube, faces outward
  // Hull vertices keep their points' names; the points inside are positions (aliases).
  expect_near(named(g.soup, "p7"), {1, 1, 1});
  ASSERT_EQ(g.aliases.size(), 3u);
  EXPECT_EQ(g.aliases[0].first, "p8");
  expect_holds(g.soup, pts, 1e-12);
}

TEST(Convexhull, InsidePointsFirstAndRepeatedCornersChangeNothing) {
  // The same cube, the inside points first and two corners twice: still 6 quads.
  std::vector<glm::dvec3> pts{{0.5, 0.5, 0.5}, {0.1, 0.2, 0.3}};
  for (const glm::dvec3& c : cube_corners()) pts.push_back(c * 2.0 - 1.0);
  pts.emplace_back(1, 1, 1);
  pts.emplace_back(-1, -1, -1);
  Generated g = run("convexhull", cloud(pts));
  kernel::TopologyReport r = topo(g.soup);
  EXPECT_EQ(r.vertex_count, 8);
  EXPECT_EQ(r.face_count, 6);
  EXPECT_EQ(r.euler_characteristic, 2);
  EXPECT_NEAR(signed_volume(g.soup), 8.0, 1e-12);
}

TEST(Convexhull, PointOnAnEdgeIsNotACorner) {
  // The unit cube plus q = (2, 0, 0), which puts the corner (1, 0, 0) on the straight edge
  // from (0, 0, 0) to q: it is not a corner. q sees only the side x = 1; the triangles from q
  // to its edges lie in z = 0 and y = 0 (merged into those sides, now quads (0,0,0) q
  // (1,1,0) (0,1,0) and (0,0,0) (0,0,1) (1,0,1) q) and in the new planes x + y = 2 and
  // x + z = 2 (two triangles). F = 3 unchanged quads + 2 + 2 = 7, V = 8 − 1 + 1 = 8,
  // E = V + F − 2 = 13. Volume: the cube and the pyramid over x = 1 with apex q, 1 + 1/3.
  std::vector<glm::dvec3> pts = cube_corners();
  pts.emplace_back(2, 0, 0);
  Generated g = run("convexhull", cloud(pts));
  kernel::TopologyReport r = topo(g.soup);
  EXPECT_EQ(r.vertex_count, 8);
  EXPECT_EQ(r.face_count, 7);
  EXPECT_EQ(r.edge_count, 13);
  EXPECT_TRUE(r.is_closed);
  EXPECT_GT(signed_volume(g.soup), 0);
  EXPECT_NEAR(signed_volume(g.soup), 4.0 / 3.0, 1e-12);
  expect_holds(g.soup, pts, 1e-12);
}

TEST(Convexhull, RandomCloudHullHoldsEveryPoint) {
  std::mt19937 rng(15);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int round = 0; round < 5; ++round) {
    std::vector<glm::dvec3> pts;
    for (int i = 0; i < 200; ++i) pts.emplace_back(u(rng), u(rng), 0.5 * (u(rng) + 1.0));
    Generated g = run("convexhull", cloud(pts));
    kernel::TopologyReport r = topo(g.soup);
    EXPECT_TRUE(r.is_closed);
    EXPECT_TRUE(r.is_orientable);
    EXPECT_EQ(r.euler_characteristic, 2);
    EXPECT_EQ(r.components.size(), 1u);
    EXPECT_GT(signed_volume(g.soup), 0);
    expect_holds(g.soup, pts, 1e-9);
    // Random points are in general position: every side is a triangle, F = 2V − 4.
    EXPECT_EQ(r.face_count, 2 * r.vertex_count - 4);
    // Every point is a vertex or an alias.
    EXPECT_EQ(g.soup.vertex_count() + static_cast<int32_t>(g.aliases.size()), 200);
  }
}

TEST(Convexhull, PointsOnASphereAreAllCorners) {
  // 6 + 8 points: the octahedron's corners and the cube's, all on the unit sphere, so all
  // are corners; each octahedron corner caps a face of the cube with a pyramid of 4
  // triangles (no two in one plane): F = 24, V = 14, E = 36.
  std::vector<glm::dvec3> pts{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (const glm::dvec3& c : cube_corners()) pts.push_back(glm::normalize(c * 2.0 - 1.0));
  kernel::TopologyReport r = topo(run("convexhull", cloud(pts)).soup);
  EXPECT_EQ(r.vertex_count, 14);
  EXPECT_EQ(r.face_count, 24);
  EXPECT_EQ(r.edge_count, 36);
  EXPECT_EQ(r.euler_characteristic, 2);
}

TEST(Convexhull, DegeneratePointSetsAreErrors) {
  NamedError e = run_error("convexhull", cloud({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
  EXPECT_EQ(e.argument, "points");
  EXPECT_EQ(e.message, "a convex hull needs at least 4 points (not all in one plane), got 3");
  e = run_error("convexhull", cloud({{1, 1, 1}, {1, 1, 1}, {1, 1, 1}, {1, 1, 1}}));
  EXPECT_EQ(e.message, "all 4 points are at one place: their convex hull is a point");
  e = run_error("convexhull", cloud({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {-3, -3, -3}, {0.5, 0.5, 0.5}}));
  EXPECT_EQ(e.message, "all 5 points lie on one line: their convex hull is a segment");
  std::vector<glm::dvec3> flat = cube_corners();
  for (glm::dvec3& p : flat) p.z = 0.3;
  e = run_error("convexhull", cloud(flat));
  EXPECT_EQ(e.argument, "points");
  EXPECT_EQ(e.message, "all 8 points lie in one plane: their convex hull is flat, not a solid");
  // Too many points for the quadratic hull: refused, not a long wait.
  std::vector<glm::dvec3> many;
  for (int i = 0; i < 10001; ++i) many.emplace_back(std::cos(i), std::sin(i), i * 1e-4);
  EXPECT_EQ(run_error("convexhull", cloud(many)).message, "a convex hull of more than 10000 points is not built, got 10001");
}

}  // namespace
}  // namespace nomec::backend::testing
