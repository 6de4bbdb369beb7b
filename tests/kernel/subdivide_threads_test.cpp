// Catmull-Clark on two threads must give exactly the one-thread result: every array of
// every level (positions bit for bit, wings, edge ends, flags, sharpness, vertex anchors,
// faces' first uses, sources, colours, border loops) and the child→parent maps, on closed
// and bordered, orientable and single-sided meshes, mixed polygons, creases and corners,
// and faces numbered at random (so that most vertices lie on the seam between the two
// threads' faces and their sums are added after both threads, in one pass's order).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "kernel/subdivide.h"
#include "tests/kernel/build.h"
#include "tests/kernel/shapes.h"

namespace nomec::kernel {
namespace {

using testing::build;
using testing::Glue;
using testing::grid_soup;
using testing::mixed_torus_from;

// Every stored array of `a` and `b`, each compared exactly; positions by their bytes.
void expect_same_arrays(const Mesh& a, const Mesh& b) {
  using A = MeshAccess;
  ASSERT_EQ(a.positions().size(), b.positions().size());
  EXPECT_EQ(std::memcmp(a.positions().data(), b.positions().data(), a.positions().size() * sizeof(glm::dvec3)), 0)
      << "positions";
  EXPECT_TRUE(A::vertex_edges(a) == A::vertex_edges(b)) << "vertex anchors";
  EXPECT_TRUE(A::edge_vertices(a) == A::edge_vertices(b)) << "edge ends";
  EXPECT_TRUE(A::use_faces(a) == A::use_faces(b)) << "faces of uses";
  EXPECT_TRUE(A::next(a) == A::next(b)) << "next wings";
  EXPECT_TRUE(A::prev(a) == A::prev(b)) << "prev wings";
  EXPECT_TRUE(A::edge_flags(a) == A::edge_flags(b)) << "edge flags";
  EXPECT_TRUE(A::sharpness(a) == A::sharpness(b)) << "edge sharpness";
  EXPECT_TRUE(A::vertex_sharpness(a) == A::vertex_sharpness(b)) << "vertex sharpness";
  EXPECT_TRUE(A::face_uses(a) == A::face_uses(b)) << "faces' first uses";
  EXPECT_TRUE(A::face_sources(a) == A::face_sources(b)) << "face sources";
  EXPECT_TRUE(A::face_colors(a) == A::face_colors(b)) << "face colours";
  EXPECT_TRUE(a.border_loops() == b.border_loops()) << "border loops";
}

void expect_same_levels(const std::vector<SubdivisionLevel>& a, const std::vector<SubdivisionLevel>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    SCOPED_TRACE(::testing::Message() << "level " << i + 1);
    expect_same_arrays(a[i].mesh, b[i].mesh);
    EXPECT_EQ(a[i].face_parents, b[i].face_parents);
    EXPECT_EQ(a[i].are_parent_faces_quads, b[i].are_parent_faces_quads);
    EXPECT_EQ(a[i].parent_face_count, b[i].parent_face_count);
    EXPECT_EQ(a[i].parent_edge_count, b[i].parent_edge_count);
  }
}

// `s` with its faces (and their sources and colours) in a deterministic shuffled order.
PolygonSoup shuffled_faces(const PolygonSoup& s) {
  std::vector<int32_t> order(s.face_count());
  for (int32_t f = 0; f < s.face_count(); ++f) order[f] = f;
  uint64_t state = 0x9e3779b97f4a7c15u;
  for (int32_t i = s.face_count() - 1; i > 0; --i) {
    state = state * 6364136223846793005u + 1442695040888963407u;
    std::swap(order[i], order[static_cast<int32_t>((state >> 33) % uint64_t(i + 1))]);
  }
  std::vector<int32_t> starts(s.face_count() + 1, 0);
  for (int32_t f = 0; f < s.face_count(); ++f) starts[f + 1] = starts[f] + s.face_sizes[f];
  PolygonSoup out;
  out.positions = s.positions;
  out.creases = s.creases;
  out.corners = s.corners;
  for (const int32_t f : order) {
    out.add_face(std::span<const int32_t>(s.face_vertices.data() + starts[f], s.face_sizes[f]));
    out.face_sources.push_back(s.face_sources.empty() ? FaceSource{f, -1} : s.face_sources[f]);
    if (!s.face_colors.empty()) out.face_colors.push_back(s.face_colors[f]);
  }
  return out;
}

// A jittered torus of n x m cells with triangles and pentagon pairs (`mixed_torus_from`).
PolygonSoup mixed_torus_soup(int n, int m) { return mixed_torus_from(grid_soup(n, m, Glue::Torus, 0.05), n, m); }

struct Case {
  std::string name;
  PolygonSoup soup;
};

std::vector<Case> cases() {
  std::vector<Case> out;
  out.push_back({"torus", grid_soup(12, 9, Glue::Torus, 0.1)});
  out.push_back({"disk with a border", grid_soup(9, 7, Glue::None, 0.1)});
  out.push_back({"annulus, two borders", grid_soup(10, 5, Glue::Cylinder, 0.1)});
  out.push_back({"Mobius band", grid_soup(11, 4, Glue::Mobius, 0.1)});
  out.push_back({"Klein bottle", grid_soup(10, 6, Glue::Klein, 0.1)});
  out.push_back({"mixed torus", mixed_torus_soup(12, 8)});
  PolygonSoup disk = testing::mixed_disk_soup();
  for (int f = 0; f < disk.face_count(); ++f) disk.face_colors.push_back(glm::vec3(0, float(f), 1));
  out.push_back({"mixed disk, coloured", disk});
  PolygonSoup cube = testing::cube_soup();
  for (int f = 0; f < 6; ++f) cube.face_sources.push_back({100 + f, f % 2});
  cube.creases.push_back({0, 2, 2.5f});
  cube.creases.push_back({0, 1, kInfiniteSharpness});
  cube.creases.push_back({4, 5, 0.5f});
  cube.corners.push_back({5, 1.5f});
  out.push_back({"cube with creases and a corner", cube});
  PolygonSoup creased = grid_soup(10, 8, Glue::Mobius, 0.1);
  for (int j = 0; j < 8; ++j) creased.creases.push_back({3 * 9 + j, 3 * 9 + j + 1, 1.5f + 0.25f * float(j % 3)});
  creased.corners.push_back({40, 2.0f});
  out.push_back({"Mobius band with creases", creased});
  out.push_back({"torus, faces shuffled", shuffled_faces(grid_soup(12, 9, Glue::Torus, 0.1))});
  out.push_back({"mixed torus, faces shuffled", shuffled_faces(mixed_torus_soup(12, 8))});
  out.push_back({"Mobius band, faces shuffled", shuffled_faces(grid_soup(11, 4, Glue::Mobius, 0.1))});
  return out;
}

TEST(SubdivideThreads, EveryLevelEqualsOneThread) {
  for (const Case& c : cases()) {
    const Mesh mesh = build(c.soup);
    for (const SubdivisionOptions base :
         {SubdivisionOptions{}, SubdivisionOptions{.vertex_rule = VertexRule::DeRose},
          SubdivisionOptions{.is_sharpness_honoured = false}, SubdivisionOptions{.has_parent_maps = false}}) {
      SubdivisionOptions one = base, two = base;
      one.levels = two.levels = 3;
      one.threading = Threading::OneThread;
      two.threading = Threading::TwoThreads;
      auto a = subdivide(mesh, one);
      auto b = subdivide(mesh, two);
      ASSERT_TRUE(a.has_value());
      ASSERT_TRUE(b.has_value());
      SCOPED_TRACE(c.name);
      expect_same_levels(*a, *b);
    }
  }
}

TEST(SubdivideThreads, LastLevelEqualsOneThread) {
  for (const Case& c : cases()) {
    const Mesh mesh = build(c.soup);
    for (int32_t levels = 1; levels <= 3; ++levels) {
      auto a = subdivide_last_level(mesh, {.levels = levels, .threading = Threading::OneThread});
      auto b = subdivide_last_level(mesh, {.levels = levels, .threading = Threading::TwoThreads});
      ASSERT_TRUE(a.has_value());
      ASSERT_TRUE(b.has_value());
      SCOPED_TRACE(::testing::Message() << c.name << ", " << levels << " levels");
      expect_same_arrays(*a, *b);
    }
  }
}

// Meshes large enough that the automatic choice takes two threads from some level on.
TEST(SubdivideThreads, AutomaticEqualsOneThreadOnLargeMeshes) {
  for (const PolygonSoup& soup : {grid_soup(64, 48, Glue::Torus, 0.05), shuffled_faces(mixed_torus_soup(60, 40)),
                                  grid_soup(96, 40, Glue::Mobius, 0.05)}) {
    const Mesh mesh = build(soup);
    // Level 1 on one thread; level 3, whose parent has at least 3 times level 1's edges
    // (4E minus the border edges), on two.
    ASSERT_LT(mesh.edge_count(), kTwoThreadEdges);
    ASSERT_GE(3 * subdivide_once(mesh).mesh.edge_count(), kTwoThreadEdges);
    auto a = subdivide_last_level(mesh, {.levels = 3, .threading = Threading::OneThread});
    auto b = subdivide_last_level(mesh, {.levels = 3});
    ASSERT_TRUE(a.has_value());
    ASSERT_TRUE(b.has_value());
    expect_same_arrays(*a, *b);
  }
}

}  // namespace
}  // namespace nomec::kernel
