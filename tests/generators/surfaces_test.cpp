// Torus, sphere, ellipsoid, cylinder, hyperboloid, Dupin cyclide and torus knot: full
// ranges give closed surfaces with welded seams and single pole vertices, partial ranges
// give open patches; orientation is outward (positive enclosed volume).
#include <cmath>
#include <set>
#include <glm/geometric.hpp>

#include "tests/generators/helpers.h"

namespace nomec::backend::testing {
namespace {

Args torus_args(double theta_max, double phi_min, double phi_max, int ts, int ps) {
  return numbers({{"major_radius", 5}, {"minor_radius", 1}, {"theta_max", theta_max},
                  {"phi_min", phi_min}, {"phi_max", phi_max}, {"theta_segs", double(ts)},
                  {"phi_segs", double(ps)}},
                 "nome3");
}

TEST(Torus, Errors) {
  EXPECT_EQ(run_error("torus", torus_args(400, 0, 360, 8, 6)).argument, "theta_max");
  EXPECT_EQ(run_error("torus", torus_args(0, 0, 360, 8, 6)).argument, "theta_max");
  EXPECT_EQ(run_error("torus", torus_args(360, 0, 360, 2, 6)).argument, "theta_segs");
  EXPECT_EQ(run_error("torus", torus_args(360, 0, 360, 8, 2)).argument, "phi_segs");
  EXPECT_EQ(run_error("torus", torus_args(360, 10, 0, 8, 6)).argument, "phi_max");
  // The 6-argument torus of nome3/olympictorus.nom lacks phi_segs.
  Args six = torus_args(360, 0, 360, 8, 6);
  std::erase_if(six.numbers, [](const auto& kv) { return kv.first == "phi_segs"; });
  EXPECT_EQ(run_error("torus", six).argument, "phi_segs");
}

Args sphere_args(double theta_max, double phi_min, double phi_max, int ts, int ps) {
  return numbers({{"radius", 2}, {"theta_max", theta_max}, {"phi_min", phi_min},
                  {"phi_max", phi_max}, {"theta_segs", double(ts)}, {"phi_segs", double(ps)}},
                 "nome3");
}

TEST(Sphere, Errors) {
  EXPECT_EQ(run_error("sphere", sphere_args(360, -100, 90, 8, 6)).argument, "phi_min");
  EXPECT_EQ(run_error("sphere", sphere_args(360, -90, 95, 8, 6)).argument, "phi_max");
  EXPECT_EQ(run_error("sphere", sphere_args(360, -90, 90, 8, 1)).argument, "phi_segs");
  EXPECT_EQ(run_error("sphere", sphere_args(360, -90, 90, 2, 4)).argument, "theta_segs");
}

// NOME3's cylinder (compat.md D1): rings `v{j}_{i}` (NOME3 `v{j}-{i}`) at z = 0 and z = height,
// an unwelded seam closed by a quad at exactly 360, wedge faces to the axis below 360, and
// `topcap` (z = 0) / `botcap` (z = height).
Args cylinder(double theta_max, int segs, std::set<std::string> flags = {}) {
  Args a = numbers({{"radius", 1}, {"height", 2}, {"theta_max", theta_max}, {"theta_segs", double(segs)}}, "nome3");
  a.flags = std::move(flags);
  return a;
}

TEST(Cylinder, FullTurnHasAnUnweldedSeamClosedByAQuad) {
  Generated g = run("cylinder", cylinder(360, 8));
  kernel::TopologyReport r = topo(g.soup);
  EXPECT_EQ(r.vertex_count, 18);  // 2 rings of 9: the last column lies on the first
  EXPECT_EQ(r.face_count, 9);     // 8 sides and the seam's closing quad
  EXPECT_EQ(r.edge_count, 27);
  EXPECT_EQ(r.euler_characteristic, 0);
  EXPECT_EQ(r.border_loop_count, 2);
  expect_near(named(g.soup, "v0_0"), {1, 0, 0});
  expect_near(named(g.soup, "v0_2"), {0, 1, 0});
  expect_near(named(g.soup, "v1_8"), {1, 0, 2});
  // Both caps: a closed octagonal prism, outward (volume 2√2 · 2).
  Generated capped = run("cylinder", cylinder(360, 8, {"topcap", "botcap"}));
  kernel::TopologyReport rc = topo(capped.soup);
  EXPECT_EQ(rc.face_count, 11);
  EXPECT_TRUE(rc.is_closed);
  EXPECT_EQ(rc.euler_characteristic, 2);
  EXPECT_NEAR(signed_volume(capped.soup), 4 * std::sqrt(2.0), 1e-9);
}

TEST(Cylinder, WedgeClosesThroughTheAxisAndTruncatesTheAngle) {
  // theta_max 90.9 is read as 90 (NOME3 truncates it).
  Generated g = run("cylinder", cylinder(90.9, 4, {"topcap", "botcap"}));
  kernel::TopologyReport r = topo(g.soup);
  EXPECT_EQ(r.vertex_count, 12);  // 2 × 5 and the axis vertices
  EXPECT_EQ(r.face_count, 8);     // 4 sides, 2 wedge quads, 2 caps
  EXPECT_TRUE(r.is_closed);
  EXPECT_TRUE(r.is_orientable);
  expect_near(named(g.soup, "v0_4"), {0, 1, 0});
  expect_near(named(g.soup, "top_center"), {0, 0, 0});
  expect_near(named(g.soup, "bottom_center"), {0, 0, 2});
  // Four triangles of 22.5° around the axis, 2 high, outward.
  EXPECT_NEAR(signed_volume(g.soup), 2 * 4 * 0.5 * std::sin(M_PI / 8), 1e-9);
  // Without caps: the side and the two wedge quads, one border loop.
  kernel::TopologyReport open = topo(run("cylinder", cylinder(90, 4)).soup);
  EXPECT_EQ(open.face_count, 6);
  EXPECT_EQ(open.border_loop_count, 2);
}

TEST(Cylinder, ErrorsAndSlideDefaults) {
  EXPECT_EQ(run_error("cylinder", cylinder(360, 2)).argument, "theta_segs");
  EXPECT_EQ(run_error("cylinder", cylinder(0.5, 4)).argument, "theta_max");  // truncated to 0
  Args slide = numbers({{"theta_segs", 6}}, "slide");
  slide.flags = {"begincap", "endcap"};
  Generated g = run("cylinder", slide);  // radius 1, height 1, full turn
  EXPECT_TRUE(topo(g.soup).is_closed);
  expect_near(named(g.soup, "v1_3"), {-1, 0, 1});
}

// SLIDE's cone (slide.md §4.1): fields as fractions of the height, caps as single polygons.
TEST(Cone, DefaultsMakeAnOpenConeToTheApex) {
  Generated g = run("cone", numbers({}, "slide"));
  kernel::TopologyReport r = topo(g.soup);
  EXPECT_EQ(r.vertex_count, 17);  // 16 around the base and the apex
  EXPECT_EQ(r.face_count, 16);
  EXPECT_EQ(r.euler_characteristic, 1);  // a disk
  EXPECT_EQ(r.border_loop_count, 1);
  expect_near(named(g.soup, "v0_0"), {1, 0, 0});
  expect_near(named(g.soup, "v0_1"), {0, 0, 1});
}

TEST(Cone, PyramidFrustumOfARealSlideFile) {
  // `cone pyr radius 1.0 height 2.0 zmin 0.0 zmax 0.5 thetaslices 4 begincap 1 endcone`: the
  // top ring sits at z = 0.5·2 with radius 0.5, corners on the axes; the base is covered.
  Args a = numbers({{"radius", 1}, {"height", 2}, {"zmin", 0}, {"zmax", 0.5}, {"theta_segs", 4}, {"begincap", 1}},
                   "slide");
  Generated g = run("cone", a);
  kernel::TopologyReport r = topo(g.soup);
  EXPECT_EQ(r.vertex_count, 8);
  EXPECT_EQ(r.face_count, 5);
  EXPECT_EQ(r.border_loop_count, 1);
  EXPECT_EQ(r.euler_characteristic, 1);
  expect_near(named(g.soup, "v0_1"), {0.5, 0, 1});
  expect_near(named(g.soup, "v1_1"), {0, 0.5, 1});
  a.numbers.push_back({"endcap", 1});
  kernel::TopologyReport closed = topo(run("cone", a).soup);
  EXPECT_TRUE(closed.is_closed);
  EXPECT_EQ(closed.euler_characteristic, 2);
  EXPECT_TRUE(closed.is_orientable);
  EXPECT_GT(signed_volume(run("cone", a).soup), 0);  // the caps face out like the sides
}

TEST(Cone, FractionsAreCheckedLikeEveryArgument) {
  NamedError e = run_error("cone", numbers({{"zmin", 0.6}, {"zmax", 0.5}}, "slide"));
  EXPECT_EQ(e.argument, "zmax");
  e = run_error("cone", numbers({{"zmax", 1.5}}, "slide"));
  EXPECT_EQ(e.argument, "zmax");
  EXPECT_EQ(e.message, "`zmax` is a fraction and must be within [0, 1], got 1.5");
  EXPECT_EQ(run_error("cone", numbers({{"theta_segs", 2}}, "slide")).argument, "thetaslices");
}

// NOME3's hyperboloid (compat.md D4): rows at the whole numbers z = −c … c with radius
// factor √(z² + 1), n vertices per ring, triangles; wraps only for angle = 2.
TEST(Hyperboloid, RowsAtWholeNumbersOfZ) {
  Generated g = run("hyperboloid", numbers({{"n", 8}, {"a", 1}, {"b", 2}, {"c", 2.5}, {"sheet", 0}, {"angle", 2}}, "nome3"));
  kernel::TopologyReport r = topo(g.soup);
  EXPECT_EQ(r.vertex_count, 40);  // 8 around × rows z = -2 … 2
  EXPECT_EQ(r.face_count, 64);    // 2 triangles per cell, 8 × 4 cells
  EXPECT_EQ(r.euler_characteristic, 0);
  EXPECT_EQ(r.border_loop_count, 2);
  EXPECT_TRUE(r.is_orientable);
  expect_near(named(g.soup, "v0_0"), {std::sqrt(5.0), 0, -2});
  expect_near(named(g.soup, "v2_2"), {0, 2, 0});
  // Faces point away from the axis: the first triangle's normal at θ = 0 points along +x.
  const auto& P = g.soup.positions;
  const int32_t* f = g.soup.face_vertices.data();
  const glm::dvec3 n = glm::cross(P[f[1]] - P[f[0]], P[f[2]] - P[f[0]]);
  EXPECT_GT(n.x, 0);
  // Half a turn (angle 1) does not wrap and stops one step short of 180°.
  Generated half = run("hyperboloid", numbers({{"n", 8}, {"a", 1}, {"b", 1}, {"c", 1}, {"sheet", 0}, {"angle", 1}}, "nome3"));
  EXPECT_EQ(half.soup.face_count(), 2 * 7 * 2);
  expect_near(named(half.soup, "v7_1"), {std::cos(7 * M_PI / 8), std::sin(7 * M_PI / 8), 0});
  EXPECT_EQ(run_error("hyperboloid", numbers({{"n", 8}, {"a", 1}, {"b", 1}, {"c", 1}, {"sheet", 1}, {"angle", 2}}, "nome3"))
                .argument,
            "sheet");
  EXPECT_EQ(run_error("hyperboloid", numbers({{"n", 8}, {"a", 1}, {"b", 1}, {"c", 0.5}, {"sheet", 0}, {"angle", 2}}, "nome3"))
                .argument,
            "c");
}

// NOME3's Dupin cyclide (compat.md D4): an n × n grid of triangles, extents in units of π.
TEST(Dupin, FullCyclideIsATorusWithNome3sOneQuadHole) {
  auto args = [](double u, double v, double n) {
    return numbers({{"a", 1}, {"b", 0.98}, {"c", 0.4}, {"d", 0.5}, {"u", u}, {"v", v}, {"n", n}}, "nome3");
  };
  Generated g = run("dupin", args(2, 2, 12));
  kernel::TopologyReport r = topo(g.soup);
  EXPECT_EQ(r.vertex_count, 144);
  EXPECT_EQ(r.face_count, 286);  // 2n² − 2: NOME3 leaves the corner cell (n−1, n−1) out
  EXPECT_EQ(r.euler_characteristic, -1);
  EXPECT_EQ(r.border_loop_count, 1);  // the hole: 4 border edges
  EXPECT_EQ(r.edge_count, 144 + 286 + 1);
  EXPECT_TRUE(r.is_orientable);
  // v0_0 at u = v = 0: ((d (c − a) + b²) / (a − c), 0, 0).
  expect_near(named(g.soup, "v0_0"), {(0.5 * (0.4 - 1) + 0.98 * 0.98) / (1 - 0.4), 0, 0});
  // A half extent in u does not wrap: a band with two borders.
  kernel::TopologyReport band = topo(run("dupin", args(1, 2, 12)).soup);
  EXPECT_EQ(band.face_count, 2 * 11 * 12);
  EXPECT_EQ(band.border_loop_count, 2);
  EXPECT_EQ(run_error("dupin", numbers({{"a", 1}, {"b", 1}, {"c", 1}, {"d", 0.5}, {"u", 2}, {"v", 2}, {"n", 8}}, "nome3"))
                .argument,
            "c");
  EXPECT_EQ(run_error("dupin", args(3, 2, 12)).argument, "u");
}

Args knot(double p, double q) {
  return numbers({{"symm", p}, {"turns", q}, {"major_radius", 10}, {"minor_radius", 3},
                  {"tube_radius", 0.5}, {"circ_segs", 8}, {"sweep_segs", 60}},
                 "nome3");
}

TEST(TorusKnot, ClosedTube) {
  Generated g = run("torusknot", knot(2, 3));
  kernel::TopologyReport r = topo(g.soup);
  ASSERT_EQ(r.components.size(), 1u);
  EXPECT_EQ(r.vertex_count, 480);
  EXPECT_EQ(r.edge_count, 960);
  EXPECT_EQ(r.face_count, 480);
  EXPECT_EQ(r.euler_characteristic, 0);
  EXPECT_TRUE(r.is_closed);
  EXPECT_TRUE(r.is_orientable);
  EXPECT_EQ(r.components[0].mobius_edge_count, 0);
  EXPECT_GT(signed_volume(g.soup), 0);
  // Tube volume ~ pi t^2 * curve length; only the sign and rough size matter here.
  // The centre line starts at (R + r, 0, 0): vertex v1_0 is tube_radius away from it.
  const glm::dvec3 v = named(g.soup, "v1_0") - glm::dvec3(13, 0, 0);
  EXPECT_NEAR(std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z), 0.5, 1e-9);
  EXPECT_EQ(topo(run("torusknot", knot(1, 1)).soup).euler_characteristic, 0);
  EXPECT_EQ(topo(run("torusknot", knot(-3, 2)).soup).euler_characteristic, 0);
  EXPECT_EQ(run_error("torusknot", knot(0, 3)).argument, "symm");
  EXPECT_EQ(run_error("torusknot", knot(2, 1.5)).argument, "turns");
}

}  // namespace
}  // namespace nomec::backend::testing
