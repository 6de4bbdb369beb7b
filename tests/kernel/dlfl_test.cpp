// DLFL operator tests: insert an edge between corners of one face (a split) and of two
// faces (a merge, which adds a handle, or a self-loop at a shared vertex), delete it
// again, split edges, point spheres; invariants after every step and Euler counts of the
// built meshes (V − E + F changes by ∓2 exactly when a merge adds a handle).
#include "kernel/dlfl.h"

#include <gtest/gtest.h>

#include "kernel/topology.h"
#include "tests/kernel/shapes.h"

namespace nomec::kernel {
namespace {

using testing::Glue;
using testing::grid_soup;

LoopMesh cube_loops() {
  auto mesh = build_mesh(testing::cube_soup());
  EXPECT_TRUE(mesh.has_value());
  return LoopMesh::from_mesh(*mesh);
}

int32_t index_of(const LoopMesh& m, int32_t f, int32_t v) {
  const auto& l = m.face(f);
  return static_cast<int32_t>(std::find(l.begin(), l.end(), v) - l.begin());
}

TopologyReport built(const LoopMesh& m) {
  auto mesh = m.to_mesh();
  EXPECT_TRUE(mesh.has_value()) << (mesh ? "" : mesh.error().message);
  if (!mesh) return {};
  EXPECT_EQ(mesh_problem(*mesh), "");
  return topology(*mesh);
}

TEST(Dlfl, CoFacialInsertSplitsAFaceAndDeleteMergesItBack) {
  LoopMesh m = cube_loops();
  // Face 0 is (0 2 3 1): the diagonal 0-3 splits it into two triangles.
  auto g = m.insert_edge(LoopCorner{0, 0}, LoopCorner{0, 2});
  ASSERT_TRUE(g.has_value()) << g.error().message;
  EXPECT_EQ(m.problem(), "");
  EXPECT_EQ(m.face(0), (std::vector<int32_t>{0, 2, 3}));
  EXPECT_EQ(m.face(*g), (std::vector<int32_t>{3, 1, 0}));
  TopologyReport t = built(m);
  EXPECT_EQ(t.vertex_count, 8);
  EXPECT_EQ(t.edge_count, 13);
  EXPECT_EQ(t.face_count, 7);
  // The same edge again would be a double edge.
  EXPECT_FALSE(m.insert_edge(LoopCorner{0, 0}, LoopCorner{0, 2}).has_value());
  // Delete the diagonal (it leaves corner 2 of face 0, vertex 3 -> 0): one quad again.
  auto d = m.delete_edge(LoopCorner{0, 2});
  ASSERT_TRUE(d.has_value()) << d.error().message;
  EXPECT_EQ(m.problem(), "");
  EXPECT_EQ(m.face(0).size(), 4u);
  EXPECT_TRUE(m.face(*g).empty());
  t = built(m);
  EXPECT_EQ(t.edge_count, 12);
  EXPECT_EQ(t.face_count, 6);
  EXPECT_EQ(t.euler_characteristic, 2);
}

TEST(Dlfl, NonCoFacialInsertMergesFacesIntoAHandle) {
  LoopMesh m = cube_loops();
  // Bottom face 0 (0 2 3 1) and top face 1 (4 5 7 6): corners 0 and 7 (index 2) are not
  // joined by an edge (0 and 4 are).
  EXPECT_FALSE(m.insert_edge(LoopCorner{0, 0}, LoopCorner{1, 0}).has_value());
  auto f = m.insert_edge(LoopCorner{0, 0}, LoopCorner{1, 2});
  ASSERT_TRUE(f.has_value()) << f.error().message;
  EXPECT_EQ(*f, 0);
  EXPECT_EQ(m.problem(), "");
  // a, …, a, b, …, b: 4 + 4 + 2 corners, both ends visited twice.
  EXPECT_EQ(m.face(0), (std::vector<int32_t>{0, 2, 3, 1, 0, 7, 6, 4, 5, 7}));
  EXPECT_TRUE(m.face(1).empty());
  // V = 8, E = 13, F = 5: χ = 0, one handle (genus 1) on a closed orientable surface.
  TopologyReport t = built(m);
  EXPECT_EQ(t.euler_characteristic, 0);
  ASSERT_EQ(t.components.size(), 1u);
  EXPECT_EQ(t.components[0].genus, 1);
  EXPECT_TRUE(t.is_orientable);
  EXPECT_TRUE(t.is_closed);
  // Deleting the inserted edge (it leaves corner 4 of the merged face, 0 -> 7) splits
  // the face back into the two quads.
  auto d = m.delete_edge(LoopCorner{0, 4});
  ASSERT_TRUE(d.has_value()) << d.error().message;
  EXPECT_EQ(m.problem(), "");
  EXPECT_EQ(built(m).euler_characteristic, 2);
}

TEST(Dlfl, InsertBetweenCornersOfOneVertexMakesASelfLoop) {
  LoopMesh m = cube_loops();
  // Vertex 0 has corners in faces 0 (0 2 3 1), 2 (0 1 5 4) and 4 (0 4 6 2).
  auto f = m.insert_edge(LoopCorner{0, index_of(m, 0, 0)}, LoopCorner{2, index_of(m, 2, 0)});
  ASSERT_TRUE(f.has_value()) << f.error().message;
  EXPECT_EQ(m.problem(), "");
  EXPECT_EQ(m.edge_use_count(0, 0), 2);
  // A second loop at the same vertex would be a double edge.
  EXPECT_FALSE(m.insert_edge(LoopCorner{4, 0}, LoopCorner{0, 0}).has_value());
  // The loop is built as a triangle at vertex 0 (2 more vertices, 2 more edges): V = 10,
  // E = 15, F = 5, χ = 0 — merging two faces always costs 2 of χ.
  TopologyReport t = built(m);
  EXPECT_EQ(t.vertex_count, 10);
  EXPECT_EQ(t.edge_count, 15);
  EXPECT_EQ(t.face_count, 5);
  EXPECT_EQ(t.components[0].genus, 1);
}

TEST(Dlfl, BulkInsertionEqualsOneByOne) {
  // Two insertions that first merge faces 0 and 1 (corners 0 and 7), then split the merged
  // face again (corners 2 and 4 of the old faces, now both in it): one by one, the second
  // needs the merged face's corner positions; in bulk the old faces' corners are named.
  LoopMesh one = cube_loops();
  ASSERT_TRUE(one.insert_edge(LoopCorner{0, 0}, LoopCorner{1, 2}).has_value());
  // Merged face 0: 0 2 3 1 0 7 6 4 5 7; vertex 2 at index 1, vertex 4 at index 7.
  ASSERT_TRUE(one.insert_edge(LoopCorner{0, 1}, LoopCorner{0, 7}).has_value());
  LoopMesh bulk = cube_loops();
  auto ok = bulk.insert_edges({{LoopCorner{0, 0}, LoopCorner{1, 2}}, {LoopCorner{0, 1}, LoopCorner{1, 0}}});
  ASSERT_TRUE(ok.has_value()) << ok.error().message;
  EXPECT_EQ(bulk.problem(), "");
  auto sizes = [](const LoopMesh& m) {
    std::vector<size_t> out;
    for (int32_t f = 0; f < m.face_count(); ++f) {
      if (!m.face(f).empty()) out.push_back(m.face(f).size());
    }
    std::sort(out.begin(), out.end());
    return out;
  };
  EXPECT_EQ(sizes(bulk), sizes(one));
  TopologyReport a = built(one), b = built(bulk);
  EXPECT_EQ(a.edge_count, b.edge_count);
  EXPECT_EQ(a.face_count, b.face_count);
  EXPECT_EQ(a.euler_characteristic, b.euler_characteristic);
  // V = 8, E = 14, F = 6: χ = 0, one handle.
  EXPECT_EQ(b.euler_characteristic, 0);
  // Refused without a change: an existing edge, a corner used twice.
  EXPECT_FALSE(bulk.insert_edges({{LoopCorner{2, 0}, LoopCorner{2, 1}}}).has_value());
  EXPECT_FALSE(bulk.insert_edges({{LoopCorner{2, 0}, LoopCorner{2, 2}}, {LoopCorner{2, 0}, LoopCorner{3, 0}}}).has_value());
  EXPECT_EQ(bulk.problem(), "");
}

TEST(Dlfl, SplitEdgeAddsTheVertexToBothFaces) {
  LoopMesh m = cube_loops();
  auto w = m.split_edge(LoopCorner{0, 0}, {0, 0.5, 0});  // edge 0 -> 2
  ASSERT_TRUE(w.has_value()) << w.error().message;
  EXPECT_EQ(*w, 8);
  EXPECT_EQ(m.problem(), "");
  EXPECT_EQ(m.face(0), (std::vector<int32_t>{0, 8, 2, 3, 1}));
  EXPECT_EQ(m.face(4), (std::vector<int32_t>{0, 4, 6, 2, 8}));
  TopologyReport t = built(m);
  EXPECT_EQ(t.vertex_count, 9);
  EXPECT_EQ(t.edge_count, 13);
  EXPECT_EQ(t.euler_characteristic, 2);
  // split_all_edges: every edge once, a midpoint flag per new vertex.
  std::vector<uint8_t> is_new = m.split_all_edges();
  EXPECT_EQ(m.problem(), "");
  EXPECT_EQ(m.vertex_count(), 9 + 13);
  EXPECT_EQ(std::count(is_new.begin(), is_new.end(), 1), 13);
  EXPECT_EQ(built(m).edge_count, 26);
}

TEST(Dlfl, PointSphereJoinsAFaceByADanglingEdge) {
  LoopMesh m = cube_loops();
  const int32_t ps = m.create_point_sphere({0.5, 0.5, -1});
  EXPECT_EQ(m.face(ps).size(), 1u);
  EXPECT_EQ(m.problem(), "");
  // A point sphere has no edge: building it is refused.
  EXPECT_EQ(m.to_mesh().error().kind, KernelError::Kind::DegenerateFace);
  auto f = m.insert_edge(LoopCorner{0, 0}, LoopCorner{ps, 0});
  ASSERT_TRUE(f.has_value()) << f.error().message;
  EXPECT_EQ(m.problem(), "");
  EXPECT_EQ(m.face(0), (std::vector<int32_t>{0, 2, 3, 1, 0, 8}));
  EXPECT_EQ(m.edge_use_count(0, 8), 2);
  // Deleting the dangling edge gives the point sphere back.
  auto d = m.delete_edge(LoopCorner{0, 4});
  ASSERT_TRUE(d.has_value()) << d.error().message;
  EXPECT_EQ(m.problem(), "");
  EXPECT_EQ(m.face(0), (std::vector<int32_t>{8}));
}

TEST(Dlfl, OperatorsRefuseBadCorners) {
  LoopMesh m = cube_loops();
  EXPECT_FALSE(m.insert_edge(LoopCorner{0, 0}, LoopCorner{0, 0}).has_value());
  EXPECT_FALSE(m.insert_edge(LoopCorner{0, 9}, LoopCorner{1, 0}).has_value());
  EXPECT_FALSE(m.insert_edge(LoopCorner{6, 0}, LoopCorner{1, 0}).has_value());
  EXPECT_FALSE(m.delete_edge(LoopCorner{-1, 0}).has_value());
  EXPECT_FALSE(m.split_edge(LoopCorner{0, 4}, {}).has_value());
  EXPECT_EQ(m.problem(), "");
}

TEST(Dlfl, BorderEdgeCannotBeDeleted) {
  auto band = build_mesh(grid_soup(6, 1, Glue::Mobius, 0.01));
  ASSERT_TRUE(band.has_value());
  LoopMesh m = LoopMesh::from_mesh(*band);
  // Some edge of face 0 is on the border: deleting it is refused.
  int refused = 0;
  for (int32_t k = 0; k < 4; ++k) refused += m.delete_edge(LoopCorner{0, k}).has_value() ? 0 : 1;
  EXPECT_GE(refused, 1);
  EXPECT_EQ(m.problem(), "");
}

TEST(Dlfl, MergeAcrossAMobiusBandKeepsItSingleSided) {
  auto band = build_mesh(grid_soup(8, 1, Glue::Mobius, 0.01));
  ASSERT_TRUE(band.has_value());
  LoopMesh m = LoopMesh::from_mesh(*band);
  // Faces 0 and 4 are half way round the band and share no vertex.
  auto f = m.insert_edge(LoopCorner{0, 0}, LoopCorner{4, 0});
  ASSERT_TRUE(f.has_value()) << f.error().message;
  EXPECT_EQ(m.problem(), "");
  TopologyReport t = built(m);
  // χ drops by 2 (one edge more, one face less); the band stays one-sided.
  EXPECT_EQ(t.euler_characteristic, -2);
  EXPECT_FALSE(t.is_orientable);
}

}  // namespace
}  // namespace nomec::kernel
