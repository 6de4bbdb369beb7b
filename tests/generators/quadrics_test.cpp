// SLIDE's disk, ring and cyclide (backend/generators/quadrics.cpp; fields and defaults are
// nomec's, docs/dialects.md): counts by hand, named positions, faces facing +z (flat shapes)
// or out of the tube (cyclide), and the errors naming the field as SLIDE writes it.
#include <cmath>

#include <glm/geometric.hpp>

#include "tests/generators/helpers.h"

namespace nomec::backend::testing {
namespace {

// The normal of every face of a flat soup (Newell's method), which must be +z.
void expect_all_facing_up(const kernel::PolygonSoup& s) {
  size_t off = 0;
  for (int32_t n : s.face_sizes) {
    glm::dvec3 normal(0.0);
    for (int32_t k = 0; k < n; ++k) {
      const glm::dvec3 a = s.positions[s.face_vertices[off + k]];
      const glm::dvec3 b = s.positions[s.face_vertices[off + (k + 1) % n]];
      normal += glm::cross(a, b);
    }
    EXPECT_GT(normal.z, 0) << "face at " << off;
    EXPECT_NEAR(normal.x, 0, 1e-9);
    EXPECT_NEAR(normal.y, 0, 1e-9);
    off += n;
  }
}

TEST(Disk, DefaultsMakeAFanOfSixteenTrianglesFacingUp) {
  Generated g = run("disk", numbers({}, "slide"));
  kernel::TopologyReport r = topo(g.soup);
  EXPECT_EQ(r.vertex_count, 17);  // the centre and 16 around the rim
  EXPECT_EQ(r.face_count, 16);
  EXPECT_EQ(r.edge_count, 32);    // 16 spokes + 16 rim edges
  EXPECT_EQ(r.euler_characteristic, 1);
  EXPECT_EQ(r.border_loop_count, 1);  // the rim only
  EXPECT_TRUE(r.is_orientable);
  expect_near(named(g.soup, "center"), {0, 0, 0});
  expect_near(named(g.soup, "v0"), {1, 0, 0});
  expect_near(named(g.soup, "v4"), {0, 1, 0});  // θ from +x towards +y, 22.5° per slice
  expect_all_facing_up(g.soup);
}

TEST(Disk, PieSliceAtAHeight) {
  // A quarter disk of radius 2 at z = 0.5 in 3 slices: centre + rim v0…v3 = 5 vertices,
  // 3 triangles, 3 spokes + 3 rim edges + the last spoke = 7 edges; χ = 5 − 7 + 3 = 1.
  Generated g = run("disk", numbers({{"radius", 2}, {"height", 0.5}, {"theta_max", 90}, {"theta_segs", 3}}, "slide"));
  kernel::TopologyReport r = topo(g.soup);
  EXPECT_EQ(r.vertex_count, 5);
  EXPECT_EQ(r.face_count, 3);
  EXPECT_EQ(r.edge_count, 7);
  EXPECT_EQ(r.border_loop_count, 1);
  expect_near(named(g.soup, "center"), {0, 0, 0.5});
  expect_near(named(g.soup, "v3"), {0, 2, 0.5});
  expect_all_facing_up(g.soup);
  // One slice of a pie is a single triangle.
  EXPECT_EQ(run("disk", numbers({{"theta_max", 45}, {"theta_segs", 1}}, "slide")).soup.face_count(), 1);
}

TEST(Disk, Errors) {
  EXPECT_EQ(run_error("disk", numbers({{"theta_segs", 2}}, "slide")).argument, "thetaslices");
  EXPECT_EQ(run_error("disk", numbers({{"radius", 0}}, "slide")).argument, "radius");
  EXPECT_EQ(run_error("disk", numbers({{"theta_max", 400}}, "slide")).argument, "thetamax");
}

TEST(Ring, DefaultsMakeAnAnnulusOfSixteenQuads) {
  Generated g = run("ring", numbers({}, "slide"));
  kernel::TopologyReport r = topo(g.soup);
  EXPECT_EQ(r.vertex_count, 32);  // 16 inner + 16 outer
  EXPECT_EQ(r.face_count, 16);
  EXPECT_EQ(r.edge_count, 48);    // 16 inner + 16 outer + 16 radial
  EXPECT_EQ(r.euler_characteristic, 0);
  EXPECT_EQ(r.border_loop_count, 2);
  EXPECT_TRUE(r.is_orientable);
  expect_near(named(g.soup, "v0_0"), {0.5, 0, 0});
  expect_near(named(g.soup, "v0_1"), {1, 0, 0});
  expect_all_facing_up(g.soup);
}

TEST(Ring, OneRadiusGivesTheOtherAndASliceHasOneBorder) {
  // Only the outer radius: the inner one is half of it.
  Generated g = run("ring", numbers({{"outer_radius", 3}}, "slide"));
  expect_near(named(g.soup, "v0_0"), {1.5, 0, 0});
  // Only the inner radius: the outer one is twice it.
  g = run("ring", numbers({{"inner_radius", 2}}, "slide"));
  expect_near(named(g.soup, "v0_1"), {4, 0, 0});
  // A half ring in 4 slices at z = −1: 5 + 5 vertices, 4 quads, 4 + 4 + 5 = 13 edges, χ = 1.
  g = run("ring", numbers({{"theta_max", 180}, {"theta_segs", 4}, {"height", -1}}, "slide"));
  kernel::TopologyReport r = topo(g.soup);
  EXPECT_EQ(r.vertex_count, 10);
  EXPECT_EQ(r.face_count, 4);
  EXPECT_EQ(r.edge_count, 13);
  EXPECT_EQ(r.border_loop_count, 1);
  expect_near(named(g.soup, "v4_1"), {-1, 0, -1});
  expect_all_facing_up(g.soup);
}

TEST(Ring, Errors) {
  NamedError e = run_error("ring", numbers({{"inner_radius", 1}, {"outer_radius", 0.5}}, "slide"));
  EXPECT_EQ(e.argument, "outerradius");
  EXPECT_EQ(e.message, "`outerradius` must be greater than `innerradius`");
  EXPECT_EQ(run_error("ring", numbers({{"inner_radius", 0}}, "slide")).argument, "innerradius");
  // A negative outer radius is reported as such, not as smaller than the inner one.
  e = run_error("ring", numbers({{"inner_radius", 0.5}, {"outer_radius", -1}}, "slide"));
  EXPECT_EQ(e.message, "`outerradius` must be positive, got -1");
  EXPECT_EQ(run_error("ring", numbers({{"theta_segs", 2}}, "slide")).argument, "thetaslices");
}

TEST(Cyclide, DefaultsMakeAClosedRingWithATubeThinAtPlusX) {
  Generated g = run("cyclide", numbers({}, "slide"));
  kernel::TopologyReport r = topo(g.soup);
  EXPECT_EQ(r.vertex_count, 128);  // 16 × 8, both seams welded
  EXPECT_EQ(r.face_count, 128);
  EXPECT_EQ(r.edge_count, 256);
  EXPECT_EQ(r.euler_characteristic, 0);  // a torus: no hole, unlike NOME3's `dupin`
  EXPECT_EQ(r.border_loop_count, 0);
  EXPECT_TRUE(r.is_closed);
  EXPECT_TRUE(r.is_orientable);
  EXPECT_GT(signed_volume(g.soup), 0);  // faces point out of the tube
  // Major radius 1, minor 0.25, eccentricity 0.125: the tube's section at θ = 0 spans x from
  // a + c − d = 0.875 to a − c + d = 1.125 (radius d − c), at θ = 180° from −1.375 to −0.625.
  expect_near(named(g.soup, "v0_0"), {1.125, 0, 0});
  expect_near(named(g.soup, "v0_4"), {0.875, 0, 0});
  expect_near(named(g.soup, "v8_0"), {-1.375, 0, 0});
  expect_near(named(g.soup, "v8_4"), {-0.625, 0, 0});
}

TEST(Cyclide, EccentricityZeroIsSlidesTorus) {
  Generated cy = run("cyclide", numbers({{"major_radius", 2}, {"minor_radius", 0.5}, {"eccentricity", 0},
                                         {"theta_segs", 12}, {"phi_segs", 6}},
                                        "slide"));
  Generated to = run("torus", numbers({{"major_radius", 2}, {"minor_radius", 0.5}, {"theta_segs", 12}, {"phi_segs", 6}},
                                      "slide"));
  // The torus names its vertices v{i+1}_{j} (NOME3's), the cyclide v{i}_{j}.
  for (int i = 0; i < 12; ++i) {
    for (int j = 0; j < 6; ++j) {
      expect_near(named(cy.soup, "v" + std::to_string(i) + "_" + std::to_string(j)),
                  named(to.soup, "v" + std::to_string(i + 1) + "_" + std::to_string(j)));
    }
  }
  EXPECT_NEAR(signed_volume(cy.soup), signed_volume(to.soup), 1e-9);
}

TEST(Cyclide, PartialTurnIsATubeOpenAtBothEnds) {
  // A third of a turn in 4 slices: 5 rings of 8 = 40 vertices, 32 quads, 5·8 + 4·8 = 72 edges.
  Generated g = run("cyclide", numbers({{"theta_max", 120}, {"theta_segs", 4}}, "slide"));
  kernel::TopologyReport r = topo(g.soup);
  EXPECT_EQ(r.vertex_count, 40);
  EXPECT_EQ(r.face_count, 32);
  EXPECT_EQ(r.edge_count, 72);
  EXPECT_EQ(r.border_loop_count, 2);
}

TEST(Cyclide, Errors) {
  NamedError e = run_error("cyclide", numbers({{"minor_radius", 1}, {"major_radius", 1}}, "slide"));
  EXPECT_EQ(e.argument, "minorradius");
  e = run_error("cyclide", numbers({{"minor_radius", 0.2}, {"eccentricity", -0.2}}, "slide"));
  EXPECT_EQ(e.argument, "eccentricity");
  // The default minor radius (a quarter of the major one) is checked too, by the geometry.
  e = run_error("cyclide", numbers({{"eccentricity", 0.3}}, "slide"));
  EXPECT_EQ(e.argument, "eccentricity");
  EXPECT_EQ(run_error("cyclide", numbers({{"phi_segs", 2}}, "slide")).argument, "phislices");
}

}  // namespace
}  // namespace nomec::backend::testing
