// Topology report on analytic shapes: Euler characteristic, orientability, border
// loops and genus for disks, annuli, Möbius bands, tori, Klein bottles and cubes.
#include "kernel/topology.h"

#include <gtest/gtest.h>

#include "tests/kernel/shapes.h"

namespace nomec::kernel {
namespace {

using testing::cube_soup;
using testing::Glue;
using testing::grid_soup;

TopologyReport report_of(const PolygonSoup& s) {
  auto mesh = build_mesh(s);
  EXPECT_TRUE(mesh.has_value()) << (mesh ? "" : mesh.error().message);
  return topology(*mesh);
}

TEST(Topology, CubeIsClosedOrientableSphere) {
  TopologyReport r = report_of(cube_soup());
  ASSERT_EQ(r.components.size(), 1u);
  const ComponentTopology& c = r.components[0];
  EXPECT_EQ(c.vertex_count, 8);
  EXPECT_EQ(c.edge_count, 12);
  EXPECT_EQ(c.face_count, 6);
  EXPECT_EQ(c.euler_characteristic, 2);
  EXPECT_TRUE(c.is_orientable);
  EXPECT_TRUE(c.is_closed);
  EXPECT_EQ(c.genus, 0);
}

TEST(Topology, MobiusBandIsNonOrientableWithOneBorder) {
  TopologyReport r = report_of(grid_soup(6, 2, Glue::Mobius));
  ASSERT_EQ(r.components.size(), 1u);
  const ComponentTopology& c = r.components[0];
  EXPECT_EQ(c.euler_characteristic, 0);
  EXPECT_FALSE(c.is_orientable);
  EXPECT_EQ(c.border_loop_count, 1);
  EXPECT_FALSE(c.is_closed);
  EXPECT_EQ(c.genus, 1);  // one cross-cap
}

TEST(Topology, KleinBottleIsClosedNonOrientable) {
  TopologyReport r = report_of(grid_soup(4, 4, Glue::Klein));
  ASSERT_EQ(r.components.size(), 1u);
  const ComponentTopology& c = r.components[0];
  EXPECT_EQ(c.vertex_count, 16);
  EXPECT_EQ(c.edge_count, 32);
  EXPECT_EQ(c.face_count, 16);
  EXPECT_EQ(c.euler_characteristic, 0);
  EXPECT_FALSE(c.is_orientable);
  EXPECT_TRUE(c.is_closed);
  EXPECT_EQ(c.border_loop_count, 0);
  EXPECT_EQ(c.genus, 2);  // two cross-caps
}

TEST(Topology, TorusAnnulusDisk) {
  TopologyReport torus = report_of(grid_soup(5, 4, Glue::Torus));
  EXPECT_EQ(torus.euler_characteristic, 0);
  EXPECT_TRUE(torus.is_orientable);
  EXPECT_TRUE(torus.is_closed);
  EXPECT_EQ(torus.components[0].genus, 1);

  TopologyReport annulus = report_of(grid_soup(5, 2, Glue::Cylinder));
  EXPECT_EQ(annulus.euler_characteristic, 0);
  EXPECT_TRUE(annulus.is_orientable);
  EXPECT_EQ(annulus.border_loop_count, 2);
  EXPECT_EQ(annulus.components[0].genus, 0);

  TopologyReport disk = report_of(grid_soup(3, 3, Glue::None));
  EXPECT_EQ(disk.euler_characteristic, 1);
  EXPECT_EQ(disk.border_loop_count, 1);
  EXPECT_EQ(disk.components[0].genus, 0);
}

TEST(Topology, ReversedFaceInOrientableMeshStaysOrientable) {
  // Reversing one face of a cube creates 4 Möbius edges, but the surface is still a
  // two-sided sphere.
  PolygonSoup s = cube_soup();
  std::reverse(s.face_vertices.begin(), s.face_vertices.begin() + 4);
  auto mesh = build_mesh(s);
  ASSERT_TRUE(mesh.has_value());
  TopologyReport r = topology(*mesh);
  EXPECT_EQ(r.components[0].mobius_edge_count, 4);
  EXPECT_TRUE(r.is_orientable);
  EXPECT_EQ(r.euler_characteristic, 2);
}

TEST(Topology, SeparateComponentsAndIsolatedVertex) {
  PolygonSoup s = cube_soup();
  PolygonSoup d = grid_soup(2, 2, Glue::None);
  const int32_t base = s.vertex_count();
  for (const auto& p : d.positions) {
    s.add_vertex(p + glm::dvec3(5, 0, 0));
  }
  for (size_t i = 0; i < d.face_sizes.size(); ++i) {
    std::vector<int32_t> f(d.face_vertices.begin() + 4 * i, d.face_vertices.begin() + 4 * i + 4);
    for (int32_t& v : f) {
      v += base;
    }
    s.add_face(f);
  }
  s.add_vertex({9, 9, 9});
  TopologyReport r = report_of(s);
  ASSERT_EQ(r.components.size(), 2u);
  EXPECT_EQ(r.components[0].euler_characteristic, 2);
  EXPECT_EQ(r.components[1].euler_characteristic, 1);
  EXPECT_EQ(r.components[1].first_face, FaceId(6));
  EXPECT_EQ(r.isolated_vertex_count, 1);
  EXPECT_EQ(r.euler_characteristic, 3);
  EXPECT_FALSE(r.is_closed);
}

TEST(Topology, BoundingBoxAndPositionHash) {
  PolygonSoup s = cube_soup();
  s.add_vertex({50, 50, 50});  // unused: ignored by both
  auto mesh = build_mesh(s);
  ASSERT_TRUE(mesh.has_value());
  BoundingBox box = bounding_box(*mesh);
  EXPECT_EQ(box.min, glm::dvec3(0, 0, 0));
  EXPECT_EQ(box.max, glm::dvec3(1, 1, 1));
  // Renumbering the vertices keeps the hash; moving one vertex changes it.
  PolygonSoup renumbered = cube_soup();
  std::reverse(renumbered.positions.begin(), renumbered.positions.end());
  for (int32_t& v : renumbered.face_vertices) {
    v = 7 - v;
  }
  auto other = build_mesh(renumbered);
  ASSERT_TRUE(other.has_value());
  EXPECT_EQ(position_hash(*mesh, 1e-6), position_hash(*other, 1e-6));
  renumbered.positions[0].x += 0.01;
  auto moved = build_mesh(renumbered);
  EXPECT_NE(position_hash(*mesh, 1e-6), position_hash(*moved, 1e-6));
}

}  // namespace
}  // namespace nomec::kernel
