// Curve generators: helix, spiral, Bézier and B-spline polylines (vertex counts, end
// points, closure) and their argument errors.
#include <cmath>

#include "tests/generators/helpers.h"

namespace nomec::backend::testing {
namespace {

// NOME3's helix (compat.md D4): `segs` vertices at θ_i = (i/segs)·theta_max, z = spacing·θ in
// radians; the strip stops one step short of theta_max.
TEST(Helix, SegsVerticesRisingBySpacingPerRadian) {
  Generated g = run("helix", numbers({{"radius", 2}, {"spacing", 0.5}, {"theta_max", 720}, {"segs", 16}}, "nome3"));
  EXPECT_EQ(g.soup.vertex_count(), 16);
  EXPECT_EQ(g.soup.face_count(), 0);
  ASSERT_EQ(g.curves.size(), 1u);
  EXPECT_FALSE(g.curves[0].is_closed);
  EXPECT_EQ(g.curves[0].vertices.size(), 16u);
  expect_near(named(g.soup, "v0"), {2, 0, 0});
  expect_near(named(g.soup, "v4"), {-2, 0, 0.5 * M_PI});
  expect_near(named(g.soup, "v15"), {2 * std::cos(M_PI * 15 / 4), 2 * std::sin(M_PI * 15 / 4), 0.5 * 4 * M_PI * 15 / 16});
  EXPECT_EQ(run_error("helix", numbers({{"radius", 2}, {"spacing", 1}, {"theta_max", 0}, {"segs", 16}}, "nome3")).argument,
            "theta_max");
  EXPECT_EQ(run_error("helix", numbers({{"radius", 2}, {"spacing", 1}, {"theta_max", 360}, {"segs", 1}}, "nome3")).argument,
            "segs");
}

// NOME3's spiral (compat.md D4): a ribbon of triangles between `u{i}` at z = 0 and `l{i}` at
// z = −0.13; θ_i = 2·angle·i/segs radians (angle truncated), radius i·rate.
TEST(Spiral, RibbonBetweenTwoRows) {
  Generated g = run("spiral", numbers({{"rate", 0.5}, {"angle", 3.7}, {"segs", 6}}, "nome3"));
  kernel::TopologyReport r = topo(g.soup);
  EXPECT_EQ(r.vertex_count, 14);
  EXPECT_EQ(r.face_count, 12);
  EXPECT_EQ(r.euler_characteristic, 1);  // a strip: a disk
  EXPECT_EQ(r.border_loop_count, 1);
  EXPECT_TRUE(r.is_orientable);
  expect_near(named(g.soup, "u0"), {0, 0, 0});
  expect_near(named(g.soup, "l0"), {0, 0, -0.13});
  // angle 3.7 is read as 3: θ_2 = 2·3·2/6 = 2 radians, radius 1.
  expect_near(named(g.soup, "u2"), {std::cos(2.0), std::sin(2.0), 0});
  expect_near(named(g.soup, "l6"), {3 * std::cos(6.0), 3 * std::sin(6.0), -0.13});
  EXPECT_EQ(run_error("spiral", numbers({{"rate", 1}, {"angle", 0.5}, {"segs", 8}}, "nome3")).argument, "angle");
  EXPECT_EQ(run_error("spiral", numbers({{"rate", 1}, {"angle", 2}, {"segs", 0}}, "nome3")).argument, "segs");
}

Args with_points(std::vector<glm::dvec3> pts, std::vector<std::pair<std::string, double>> nums,
                 std::string dialect = "nome3") {
  Args a = numbers(std::move(nums), std::move(dialect));
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
  EXPECT_EQ(run("beziercurve", with_points({{0, 0, 0}, {1, 0, 0}}, {})).soup.vertex_count(), 9);  // NOME3: 8 segments
  EXPECT_EQ(run_error("beziercurve", with_points({{0, 0, 0}}, {})).argument, "points");
}

// SLIDE's bsplinecurve keeps nomec's clamped knots (NOME3's: tests/generators/original_test.cpp).
TEST(BSpline, ClampedAndClosed) {
  std::vector<glm::dvec3> pts = {{0, 0, 0}, {1, 1, 0}, {2, -1, 0}, {3, 1, 0}, {4, 0, 0}};
  Generated open = run("bspline", with_points(pts, {{"order", 4}, {"segs", 10}}, "slide"));
  EXPECT_EQ(open.soup.vertex_count(), 11);
  EXPECT_FALSE(open.curves[0].is_closed);
  expect_near(named(open.soup, "v0"), {0, 0, 0});
  expect_near(named(open.soup, "v10"), {4, 0, 0});
  // Order 2 is the control polygon itself.
  Generated linear = run("bspline", with_points(pts, {{"order", 2}, {"segs", 8}}, "slide"));
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
