// Curve generators: helix, spiral, Bézier and B-spline polylines (vertex counts, end
// points, closure) and their argument errors.
#include <cmath>

#include "tests/generators/helpers.h"

namespace nomec::backend::testing {
namespace {

TEST(Helix, OpenPolyline) {
  Generated g = run("helix", numbers({{"radius", 2}, {"height", 3}, {"turns", 2}, {"segs", 16}}));
  EXPECT_EQ(g.soup.vertex_count(), 17);
  EXPECT_EQ(g.soup.face_count(), 0);
  ASSERT_EQ(g.curves.size(), 1u);
  EXPECT_FALSE(g.curves[0].is_closed);
  EXPECT_EQ(g.curves[0].vertices.size(), 17u);
  expect_near(named(g.soup, "v0"), {2, 0, 0});
  expect_near(named(g.soup, "v4"), {-2, 0, 0.75});
  expect_near(named(g.soup, "v16"), {2, 0, 3});
  EXPECT_EQ(run_error("helix", numbers({{"radius", 2}, {"height", 3}, {"turns", 0}, {"segs", 16}})).argument,
            "turns");
}

TEST(Spiral, RadiusGrowsPerTurn) {
  Generated g = run("spiral", numbers({{"growth", 1}, {"height", 0}, {"turns", 2}, {"segs", 8}}));
  EXPECT_EQ(g.soup.vertex_count(), 9);
  expect_near(named(g.soup, "v0"), {0, 0, 0});
  expect_near(named(g.soup, "v4"), {1, 0, 0});
  expect_near(named(g.soup, "v8"), {2, 0, 0});
  EXPECT_EQ(run_error("spiral", numbers({{"growth", 1}, {"height", 0}, {"turns", 2}, {"segs", 0}})).argument,
            "segs");
}

Args with_points(std::vector<glm::dvec3> pts, std::vector<std::pair<std::string, double>> nums) {
  Args a = numbers(std::move(nums), "nome3");
  a.points = std::move(pts);
  for (size_t i = 0; i < a.points.size(); ++i) a.point_names.push_back("p" + std::to_string(i));
  return a;
}

TEST(BezierCurve, InterpolatesEndPoints) {
  Generated g = run("beziercurve", with_points({{0, 0, 0}, {1, 2, 0}, {2, 0, 0}}, {{"segs", 4}}));
  EXPECT_EQ(g.soup.vertex_count(), 5);
  expect_near(named(g.soup, "v0"), {0, 0, 0});
  expect_near(named(g.soup, "v2"), {1, 1, 0});
  expect_near(named(g.soup, "v4"), {2, 0, 0});
  EXPECT_EQ(run("beziercurve", with_points({{0, 0, 0}, {1, 0, 0}}, {})).soup.vertex_count(), 17);
  EXPECT_EQ(run_error("beziercurve", with_points({{0, 0, 0}}, {})).argument, "points");
}

TEST(BSpline, ClampedAndClosed) {
  std::vector<glm::dvec3> pts = {{0, 0, 0}, {1, 1, 0}, {2, -1, 0}, {3, 1, 0}, {4, 0, 0}};
  Generated open = run("bspline", with_points(pts, {{"order", 4}, {"segs", 10}}));
  EXPECT_EQ(open.soup.vertex_count(), 11);
  EXPECT_FALSE(open.curves[0].is_closed);
  expect_near(named(open.soup, "v0"), {0, 0, 0});
  expect_near(named(open.soup, "v10"), {4, 0, 0});
  // Order 2 is the control polygon itself.
  Generated linear = run("bspline", with_points(pts, {{"order", 2}, {"segs", 8}}));
  expect_near(named(linear.soup, "v2"), {1, 1, 0});
  expect_near(named(linear.soup, "v3"), {1.5, 0, 0});

  std::vector<glm::dvec3> square = {{1, 1, 0}, {-1, 1, 0}, {-1, -1, 0}, {1, -1, 0}};
  Generated loop = run("bspline", with_points(square, {{"order", 3}, {"segs", 8}, {"closed", 1}}));
  EXPECT_EQ(loop.soup.vertex_count(), 8);
  EXPECT_TRUE(loop.curves[0].is_closed);
  // A uniform quadratic B-spline passes through the edge midpoints.
  expect_near(named(loop.soup, "v0"), {0, 1, 0});
  expect_near(named(loop.soup, "v2"), {-1, 0, 0});
  EXPECT_EQ(run_error("bspline", with_points({{0, 0, 0}, {1, 0, 0}}, {{"order", 4}})).argument, "points");
}

}  // namespace
}  // namespace nomec::backend::testing
