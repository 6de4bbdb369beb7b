// Face deletion tests: cleanup of edges and vertices, F_a refill on edges that lost
// their first face, splitting of pinched vertices, Möbius bands cut open, provenance.
#include "kernel/edit.h"

#include <gtest/gtest.h>

#include "kernel/topology.h"
#include "tests/kernel/build.h"
#include "tests/kernel/shapes.h"

namespace nomec::kernel {
namespace {

using testing::Glue;
using testing::grid_soup;

using testing::build;

TEST(DeleteFaces, CubeMinusOneFaceIsOpenBox) {
  Mesh cube = build(testing::cube_soup());
  std::vector<FaceId> del{FaceId(0)};
  auto r = delete_faces(cube, del);
  ASSERT_TRUE(r.has_value()) << r.error().message;
  TopologyReport t = topology(r->mesh);
  EXPECT_EQ(t.vertex_count, 8);
  EXPECT_EQ(t.edge_count, 12);
  EXPECT_EQ(t.face_count, 5);
  EXPECT_EQ(t.euler_characteristic, 1);
  EXPECT_EQ(t.border_loop_count, 1);
  EXPECT_EQ(r->face_parents[0], FaceId(1));
  // Every edge has F_a filled; the four rim edges are boundary.
  int boundary = 0;
  for (int32_t e = 0; e < r->mesh.edge_count(); ++e) {
    EXPECT_TRUE(r->mesh.edge_face(EdgeId(e), 0).is_valid());
    boundary += r->mesh.is_boundary(EdgeId(e)) ? 1 : 0;
  }
  EXPECT_EQ(boundary, 4);
}

TEST(DeleteFaces, SharedEdgeAndVertexRemoved) {
  Mesh grid = build(grid_soup(2, 1, Glue::None));  // two quads side by side
  std::vector<FaceId> del{FaceId(1)};
  auto r = delete_faces(grid, del);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->mesh.vertex_count(), 4);
  EXPECT_EQ(r->mesh.edge_count(), 4);
  std::vector<FaceId> both{FaceId(0), FaceId(1), FaceId(1)};
  auto empty = delete_faces(grid, both);
  ASSERT_TRUE(empty.has_value());
  EXPECT_EQ(empty->mesh.vertex_count(), 0);
  EXPECT_EQ(empty->mesh.edge_count(), 0);
}

TEST(DeleteFaces, PinchedVertexIsSplit) {
  // 2x2 grid: deleting two diagonal quads leaves the centre vertex with two fans.
  Mesh grid = build(grid_soup(2, 2, Glue::None));
  std::vector<FaceId> del{FaceId(1), FaceId(2)};
  auto r = delete_faces(grid, del);
  ASSERT_TRUE(r.has_value()) << r.error().message;
  EXPECT_EQ(r->split_vertex_count, 1);
  EXPECT_EQ(r->mesh.vertex_count(), 8);
  TopologyReport t = topology(r->mesh);
  EXPECT_EQ(t.components.size(), 2u);
  EXPECT_EQ(t.border_loop_count, 2);
}

TEST(DeleteFaces, CuttingMobiusBandGivesDisk) {
  Mesh band = build(grid_soup(6, 1, Glue::Mobius));
  std::vector<FaceId> del{FaceId(0)};
  auto r = delete_faces(band, del);
  ASSERT_TRUE(r.has_value()) << r.error().message;
  TopologyReport t = topology(r->mesh);
  EXPECT_TRUE(t.is_orientable);
  EXPECT_EQ(t.euler_characteristic, 1);
  EXPECT_EQ(t.border_loop_count, 1);
}

TEST(DeleteFaces, KeepsCreasesAndSources) {
  PolygonSoup s = testing::cube_soup();
  s.creases.push_back({1, 3, 2.0f});
  s.corners.push_back({7, 4.0f});
  for (int f = 0; f < 6; ++f) {
    s.face_sources.push_back({f, 9});
  }
  Mesh cube = build(s);
  std::vector<FaceId> del{FaceId(0), FaceId(2)};
  auto r = delete_faces(cube, del);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->mesh.face_source(FaceId(0)), (FaceSource{1, 9}));
  int sharp = 0;
  for (int32_t e = 0; e < r->mesh.edge_count(); ++e) {
    sharp += r->mesh.sharpness(EdgeId(e)) == 2.0f ? 1 : 0;
  }
  EXPECT_EQ(sharp, 1);
  int corners = 0;
  for (int32_t v = 0; v < r->mesh.vertex_count(); ++v) {
    if (r->mesh.vertex_sharpness(VertexId(v)) == 4.0f) {
      ++corners;
      EXPECT_EQ(r->vertex_parents[v], VertexId(7));
    }
  }
  EXPECT_EQ(corners, 1);
  std::vector<FaceId> bad{FaceId(17)};
  EXPECT_FALSE(delete_faces(cube, bad).has_value());
}

}  // namespace
}  // namespace nomec::kernel
