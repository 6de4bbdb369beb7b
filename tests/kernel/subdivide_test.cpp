// Catmull-Clark unit tests: exact counts per level, invariants (Euler characteristic,
// orientability, borders) on single-sided surfaces, the vertex rules on hand-computed
// positions, crease decay, provenance, colours and the child→parent maps.
#include "kernel/subdivide.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <memory>
#include <vector>

#include "kernel/topology.h"
#include "tests/kernel/build.h"
#include "tests/kernel/shapes.h"

namespace nomec::kernel {
namespace {

using testing::cube_soup;
using testing::Glue;
using testing::grid_soup;

using testing::build;

// Consistent wings (kernel::mesh_problem) and only quads.
void expect_wings_consistent(const Mesh& m) {
  ASSERT_EQ(mesh_problem(m), "");
  for (int32_t f = 0; f < m.face_count(); ++f) ASSERT_EQ(m.face_size(FaceId(f)), 4);
}

TEST(Subdivide, CubeLevelCounts) {
  Mesh cube = build(cube_soup());
  auto levels = subdivide(cube, {.levels = 3});
  ASSERT_TRUE(levels.has_value());
  const Mesh& l1 = (*levels)[0].mesh;
  EXPECT_EQ(l1.vertex_count(), 26);
  EXPECT_EQ(l1.edge_count(), 48);
  EXPECT_EQ(l1.face_count(), 24);
  const Mesh& l2 = (*levels)[1].mesh;
  EXPECT_EQ(l2.vertex_count(), 98);
  EXPECT_EQ(l2.edge_count(), 192);
  EXPECT_EQ(l2.face_count(), 96);
  const Mesh& l3 = (*levels)[2].mesh;
  EXPECT_EQ(l3.face_count(), 384);
  for (const SubdivisionLevel& level : *levels) {
    expect_wings_consistent(level.mesh);
    TopologyReport r = topology(level.mesh);
    EXPECT_EQ(r.euler_characteristic, 2);
    EXPECT_TRUE(r.is_orientable);
    EXPECT_TRUE(r.is_closed);
  }
}

TEST(Subdivide, CubeLevelOnePositions) {
  // Cube corner (valence 3, smooth): v = (n-3)/n v0 + 2/n R + 1/n F = 2/3 R + 1/3 F...
  // For corner (0,0,0): R = avg of midpoints (0.25,0,0)... = (1/6,1/6,1/6),
  // F = avg of face centres = (1/3,1/3,1/3) -> v = (2/9,2/9,2/9).
  Mesh cube = build(cube_soup());
  SubdivisionLevel l1 = subdivide_once(cube);
  const glm::dvec3 v0 = l1.mesh.position(VertexId(6 + 12 + 0));
  EXPECT_NEAR(v0.x, 2.0 / 9.0, 1e-15);
  EXPECT_NEAR(v0.y, 2.0 / 9.0, 1e-15);
  EXPECT_NEAR(v0.z, 2.0 / 9.0, 1e-15);
  // Face point of face 0 (z = 0) is its centre.
  EXPECT_EQ(l1.mesh.position(VertexId(0)), glm::dvec3(0.5, 0.5, 0.0));
  // DeRose: v = (n-2)/n v0 + 1/n E + 1/n F; edge points of a corner edge are
  // (v0 + v1 + f1 + f2)/4, e.g. edge (0,0,0)-(1,0,0) -> (0.5, 0.125, 0.125); the average
  // over the three edges is (1/4)(1,1,1); F = (1/3)(1,1,1) -> v = (1/3)(1/4 + 1/3).
  SubdivisionLevel d1 = subdivide_once(cube, {.vertex_rule = VertexRule::DeRose});
  const glm::dvec3 d0 = d1.mesh.position(VertexId(6 + 12 + 0));
  EXPECT_NEAR(d0.x, 1.0 / 3.0 * (1.0 / 4.0 + 1.0 / 3.0), 1e-15);
  EXPECT_NEAR(d0.z, 1.0 / 3.0 * (1.0 / 4.0 + 1.0 / 3.0), 1e-15);
}

TEST(Subdivide, BoundaryRules) {
  // Single quad: boundary edges infinitely sharp, every corner has n_sharp = 2 -> crease
  // rule: v = 3/4 v0 + 1/8 (a + b).
  PolygonSoup s;
  s.add_vertex({0, 0, 0});
  s.add_vertex({4, 0, 0});
  s.add_vertex({4, 4, 0});
  s.add_vertex({0, 4, 0});
  s.add_face({0, 1, 2, 3});
  SubdivisionLevel l1 = subdivide_once(build(s));
  EXPECT_EQ(l1.mesh.vertex_count(), 9);
  EXPECT_EQ(l1.mesh.edge_count(), 12);
  EXPECT_EQ(l1.mesh.face_count(), 4);
  EXPECT_EQ(l1.mesh.position(VertexId(1 + 4 + 0)), glm::dvec3(0.5, 0.5, 0));
  EXPECT_EQ(l1.mesh.position(VertexId(1 + 0)), glm::dvec3(2, 0, 0));  // edge midpoint
  ASSERT_EQ(l1.mesh.border_loops().size(), 1u);
  EXPECT_EQ(l1.mesh.border_loop_edges(0).size(), 8u);
}

TEST(Subdivide, CreaseDecaysByOnePerLevel) {
  PolygonSoup s = cube_soup();
  s.creases.push_back({0, 2, 2.0f});
  Mesh cube = build(s);
  auto levels = subdivide(cube, {.levels = 3});
  ASSERT_TRUE(levels.has_value());
  const EdgeId parent = cube.find_edge(VertexId(0), VertexId(2));
  const Mesh& l1 = (*levels)[0].mesh;
  EXPECT_EQ(l1.sharpness(EdgeId(2 * parent.index)), 1.0f);
  EXPECT_EQ(l1.sharpness(EdgeId(2 * parent.index + 1)), 1.0f);
  // The edge point of a sharp edge is its midpoint.
  EXPECT_EQ(l1.position(VertexId(6 + parent.index)), glm::dvec3(0, 0.5, 0));
  const Mesh& l2 = (*levels)[1].mesh;
  EXPECT_EQ(l2.sharpness(EdgeId(4 * parent.index)), 0.0f);
  int sharp_edges = 0;
  for (int32_t e = 0; e < l2.edge_count(); ++e) {
    sharp_edges += l2.sharpness(EdgeId(e)) > 0 ? 1 : 0;
  }
  EXPECT_EQ(sharp_edges, 0);
}

TEST(Subdivide, InfiniteCreaseKeepsCornerFixed) {
  // Three infinitely sharp edges at cube vertex 0: corner rule, the vertex never moves.
  PolygonSoup s = cube_soup();
  s.creases.push_back({0, 1, kInfiniteSharpness});
  s.creases.push_back({0, 2, kInfiniteSharpness});
  s.creases.push_back({0, 4, kInfiniteSharpness});
  Mesh m = build(s);
  int32_t corner = 0;  // index of the corner's descendant in the current level
  for (int level = 0; level < 3; ++level) {
    SubdivisionLevel next = subdivide_once(m);
    const int32_t child = m.face_count() + m.edge_count() + corner;
    EXPECT_EQ(next.vertex_parent(VertexId(child)).kind, VertexParent::Kind::Vertex);
    EXPECT_EQ(next.vertex_parent(VertexId(child)).index, corner);
    EXPECT_EQ(next.mesh.position(VertexId(child)), glm::dvec3(0, 0, 0)) << level;
    corner = child;
    m = std::move(next.mesh);
  }
}

TEST(Subdivide, PlainRuleIgnoresCreasesAndCorners) {
  PolygonSoup sharp = cube_soup();
  sharp.creases.push_back({0, 2, kInfiniteSharpness});
  sharp.corners.push_back({7, 3.0f});
  Mesh creased = build(sharp);
  Mesh smooth = build(cube_soup());
  SubdivisionLevel plain = subdivide_once(creased, {.is_sharpness_honoured = false});
  SubdivisionLevel reference = subdivide_once(smooth);
  EXPECT_EQ(plain.mesh.positions(), reference.mesh.positions());
  EXPECT_FALSE(plain.mesh.has_sharpness());
  // Honoured: the corner stays put and decays 3 -> 2 on its vertex point.
  SubdivisionLevel honoured = subdivide_once(creased);
  const VertexId corner(6 + 12 + 7);
  EXPECT_EQ(honoured.mesh.position(corner), glm::dvec3(1, 1, 1));
  EXPECT_EQ(honoured.mesh.vertex_sharpness(corner), 2.0f);
  EXPECT_EQ(honoured.mesh.vertex_sharpness(VertexId(0)), 0.0f);
}

TEST(Subdivide, MobiusBandStaysNonOrientableWithOneBorder) {
  Mesh band = build(grid_soup(5, 1, Glue::Mobius));
  auto levels = subdivide(band, {.levels = 3});
  ASSERT_TRUE(levels.has_value());
  int32_t faces = 5;
  for (const SubdivisionLevel& level : *levels) {
    faces *= 4;
    TopologyReport r = topology(level.mesh);
    EXPECT_EQ(r.face_count, faces);
    EXPECT_EQ(r.euler_characteristic, 0);
    EXPECT_FALSE(r.is_orientable);
    EXPECT_EQ(r.border_loop_count, 1);
    EXPECT_TRUE(level.mesh.has_mobius_edges());
    expect_wings_consistent(level.mesh);
  }
}

TEST(Subdivide, KleinBottleStaysClosedNonOrientable) {
  Mesh klein = build(grid_soup(4, 4, Glue::Klein));
  auto levels = subdivide(klein, {.levels = 2});
  ASSERT_TRUE(levels.has_value());
  for (const SubdivisionLevel& level : *levels) {
    TopologyReport r = topology(level.mesh);
    EXPECT_EQ(r.euler_characteristic, 0);
    EXPECT_FALSE(r.is_orientable);
    EXPECT_TRUE(r.is_closed);
    expect_wings_consistent(level.mesh);
  }
}

TEST(Subdivide, ProvenanceColoursAndParentMaps) {
  PolygonSoup s = cube_soup();
  for (int f = 0; f < 6; ++f) {
    s.face_sources.push_back({100 + f, 7});
    s.face_colors.push_back(glm::vec3(float(f), 0, 0));
  }
  Mesh cube = build(s);
  auto levels = subdivide(cube, {.levels = 2});
  ASSERT_TRUE(levels.has_value());
  const SubdivisionLevel& l1 = (*levels)[0];
  const SubdivisionLevel& l2 = (*levels)[1];
  ASSERT_EQ(l2.mesh.face_count(), 96);
  for (int32_t f = 0; f < 96; ++f) {
    const FaceId p1 = l2.face_parent(FaceId(f));
    const FaceId p0 = l1.face_parent(p1);
    EXPECT_EQ(l2.mesh.face_source(FaceId(f)), (FaceSource{100 + p0.index, 7}));
    EXPECT_EQ(l2.mesh.face_color(FaceId(f)).x, float(p0.index));
  }
  EXPECT_EQ(l1.face_parent(FaceId(5)), FaceId(1));  // 4 children per quad, in order
  EXPECT_EQ(l1.vertex_parent(VertexId(3)).kind, VertexParent::Kind::Face);
  EXPECT_EQ(l1.vertex_parent(VertexId(6 + 4)).kind, VertexParent::Kind::Edge);
  EXPECT_EQ(l1.vertex_parent(VertexId(6 + 4)).index, 4);
  EXPECT_EQ(l1.edge_parent(EdgeId(23)).kind, EdgeParent::Kind::Edge);
  EXPECT_EQ(l1.edge_parent(EdgeId(23)).index, 11);
  EXPECT_EQ(l1.edge_parent(EdgeId(27)).kind, EdgeParent::Kind::Face);
  EXPECT_EQ(l1.edge_parent(EdgeId(27)).index, 0);
  EXPECT_EQ(l1.edge_parent(EdgeId(28)).index, 1);
  EXPECT_EQ(l1.edge_parent(EdgeId(24)).kind, EdgeParent::Kind::Face);
  EXPECT_EQ(l1.edge_parent(EdgeId(24)).index, 0);
}

TEST(Subdivide, ParentMapsAgreeWithTopology) {
  Mesh band = build(grid_soup(5, 2, Glue::Mobius));
  SubdivisionLevel l1 = subdivide_once(band);
  const Mesh& c = l1.mesh;
  for (int32_t e = 0; e < c.edge_count(); ++e) {
    const EdgeParent ep = l1.edge_parent(EdgeId(e));
    const VertexParent a = l1.vertex_parent(c.edge_vertex(EdgeId(e), 0));
    const VertexParent b = l1.vertex_parent(c.edge_vertex(EdgeId(e), 1));
    if (ep.kind == EdgeParent::Kind::Edge) {
      // A half: one end is the parent edge's point, the other one of its vertices.
      const VertexParent& mid = a.kind == VertexParent::Kind::Edge ? a : b;
      const VertexParent& end = a.kind == VertexParent::Kind::Edge ? b : a;
      EXPECT_EQ(mid.index, ep.index);
      ASSERT_EQ(end.kind, VertexParent::Kind::Vertex);
      const EdgeId parent(ep.index);
      EXPECT_TRUE(band.edge_vertex(parent, 0).index == end.index ||
                  band.edge_vertex(parent, 1).index == end.index);
      EXPECT_EQ(c.is_mobius(EdgeId(e)), band.is_mobius(parent));
    } else {
      EXPECT_EQ(a.kind, VertexParent::Kind::Edge);
      EXPECT_EQ(b.kind, VertexParent::Kind::Face);
      EXPECT_EQ(b.index, ep.index);
      EXPECT_FALSE(c.is_mobius(EdgeId(e)));
    }
  }
  for (int32_t f = 0; f < c.face_count(); ++f) {
    // Each child face contains the face point of its parent face.
    int face_points = 0;
    for (VertexId v : c.face_vertices(FaceId(f))) {
      const VertexParent p = l1.vertex_parent(v);
      if (p.kind == VertexParent::Kind::Face) {
        ++face_points;
        EXPECT_EQ(p.index, l1.face_parent(FaceId(f)).index);
      }
    }
    EXPECT_EQ(face_points, 1);
  }
}

TEST(Subdivide, MixedPolygonsBecomeQuads) {
  Mesh disk = build(testing::mixed_disk_soup());
  EXPECT_EQ(disk.vertex_count(), 15);
  EXPECT_EQ(disk.edge_count(), 25);
  EXPECT_EQ(disk.face_count(), 11);
  SubdivisionLevel l1 = subdivide_once(disk);
  EXPECT_EQ(l1.mesh.face_count(), 5 + 5 * 4 + 5 * 3);
  EXPECT_EQ(l1.mesh.vertex_count(), 15 + 25 + 11);
  TopologyReport r = topology(l1.mesh);
  EXPECT_EQ(r.euler_characteristic, 1);
  EXPECT_EQ(r.border_loop_count, 1);
  expect_wings_consistent(l1.mesh);
}

// Sorted positions, for comparing meshes whose elements are numbered differently.
std::vector<std::array<double, 3>> sorted_positions(const Mesh& m) {
  std::vector<std::array<double, 3>> out;
  for (const glm::dvec3& p : m.positions()) {
    out.push_back({p.x, p.y, p.z});
  }
  std::sort(out.begin(), out.end());
  return out;
}

TEST(Subdivide, PositionsIndependentOfFaceOrientation) {
  // Reversing faces only flips orientations (creating Möbius edges); the refined
  // geometry must be identical, including creases and borders.
  PolygonSoup s = testing::mixed_disk_soup();
  s.creases.push_back({0, 1, 1.5f});
  PolygonSoup flipped = s;
  size_t offset = 0;
  for (int32_t f = 0; f < s.face_count(); ++f) {
    if (f % 2 == 1) {
      std::reverse(flipped.face_vertices.begin() + offset,
                   flipped.face_vertices.begin() + offset + s.face_sizes[f]);
    }
    offset += s.face_sizes[f];
  }
  Mesh a = build(s);
  Mesh b = build(flipped);
  ASSERT_TRUE(b.has_mobius_edges());
  auto la = subdivide(a, {.levels = 3});
  auto lb = subdivide(b, {.levels = 3});
  for (int level = 0; level < 3; ++level) {
    auto pa = sorted_positions((*la)[level].mesh);
    auto pb = sorted_positions((*lb)[level].mesh);
    ASSERT_EQ(pa.size(), pb.size());
    for (size_t i = 0; i < pa.size(); ++i) {
      for (int c = 0; c < 3; ++c) {
        ASSERT_NEAR(pa[i][c], pb[i][c], 1e-12) << "level " << level + 1;
      }
    }
    TopologyReport r = topology((*lb)[level].mesh);
    EXPECT_TRUE(r.is_orientable);
    EXPECT_EQ(r.euler_characteristic, 1);
  }
}

TEST(Subdivide, EmptyMeshAndIsolatedVertex) {
  Mesh empty = build(PolygonSoup{});
  SubdivisionLevel l1 = subdivide_once(empty);
  EXPECT_EQ(l1.mesh.vertex_count(), 0);
  EXPECT_EQ(l1.mesh.face_count(), 0);
  PolygonSoup s = cube_soup();
  s.add_vertex({5, 5, 5});  // not used by any face
  SubdivisionLevel l2 = subdivide_once(build(s));
  EXPECT_EQ(l2.mesh.vertex_count(), 6 + 12 + 9);
  const VertexId lonely(6 + 12 + 8);
  EXPECT_EQ(l2.mesh.position(lonely), glm::dvec3(5, 5, 5));
  EXPECT_FALSE(l2.mesh.vertex_edge(lonely).is_valid());
  TopologyReport r = topology(l2.mesh);
  EXPECT_EQ(r.isolated_vertex_count, 1);
  EXPECT_EQ(r.euler_characteristic, 2);
}

TEST(Subdivide, RejectsBadLevelCount) {
  Mesh cube = build(cube_soup());
  auto r = subdivide(cube, {.levels = -1});
  ASSERT_FALSE(r.has_value());
  EXPECT_EQ(r.error().kind, KernelError::Kind::InvalidArgument);
}


// ---- subdivide_last_level: the freeing path must give exactly the retaining path's mesh --

// Every stored array of `a` and `b` equal, positions bit for bit.
void expect_identical(const Mesh& a, const Mesh& b) {
  EXPECT_TRUE(has_same_topology(a, b));
  ASSERT_EQ(a.positions().size(), b.positions().size());
  for (size_t v = 0; v < a.positions().size(); ++v) {
    ASSERT_EQ(std::memcmp(&a.positions()[v], &b.positions()[v], sizeof(glm::dvec3)), 0) << v;
  }
}

// Soups covering what the levels in between drop or must carry: non-quad faces (the first
// level stores its face sources), borders and their loops, Möbius edges, creases and
// corners that decay over the levels, colours and explicit face sources.
std::vector<PolygonSoup> last_level_soups() {
  std::vector<PolygonSoup> soups;
  PolygonSoup cube = cube_soup();
  for (int f = 0; f < 6; ++f) {
    cube.face_sources.push_back({100 + f, f % 2});
    cube.face_colors.push_back(glm::vec3(float(f), 0.5f, 0));
  }
  cube.creases.push_back({0, 2, 2.5f});
  cube.creases.push_back({0, 1, kInfiniteSharpness});
  cube.corners.push_back({5, 1.5f});
  soups.push_back(cube);
  PolygonSoup disk = testing::mixed_disk_soup();
  for (int f = 0; f < disk.face_count(); ++f) disk.face_colors.push_back(glm::vec3(0, float(f), 1));
  soups.push_back(disk);
  soups.push_back(testing::mixed_disk_soup());
  for (Glue glue : {Glue::None, Glue::Cylinder, Glue::Mobius, Glue::Torus, Glue::Klein}) {
    soups.push_back(grid_soup(5, 4, glue, 0.1));
  }
  PolygonSoup tetra = testing::tetra_soup();
  tetra.creases.push_back({0, 1, 1.0f});
  soups.push_back(tetra);
  return soups;
}

TEST(SubdivideLastLevel, EqualsLastOfAllLevels) {
  for (const PolygonSoup& soup : last_level_soups()) {
    const Mesh mesh = build(soup);
    for (const SubdivisionOptions base :
         {SubdivisionOptions{}, SubdivisionOptions{.vertex_rule = VertexRule::DeRose},
          SubdivisionOptions{.is_sharpness_honoured = false}, SubdivisionOptions{.has_parent_maps = false}}) {
      for (int32_t levels = 1; levels <= 4; ++levels) {
        SubdivisionOptions options = base;
        options.levels = levels;
        auto all = subdivide(mesh, options);
        auto last = subdivide_last_level(mesh, options);
        ASSERT_TRUE(all.has_value());
        ASSERT_TRUE(last.has_value());
        SCOPED_TRACE(::testing::Message() << soup.face_count() << " faces, " << levels << " levels");
        expect_identical(*last, all->back().mesh);
        expect_wings_consistent(*last);
      }
    }
  }
}

TEST(SubdivideLastLevel, ZeroLevelsReturnsTheInput) {
  PolygonSoup s = cube_soup();
  s.names = {"a", "b", "c", "d", "e", "f", "g", "h"};
  const Mesh cube = build(s);
  auto same = subdivide_last_level(cube, {.levels = 0});
  ASSERT_TRUE(same.has_value());
  expect_identical(*same, cube);
}

TEST(SubdivideLastLevel, SameFailuresAsAllLevels) {
  const Mesh cube = build(cube_soup());
  for (const SubdivisionOptions options :
       {SubdivisionOptions{.levels = -1}, SubdivisionOptions{.levels = 13},
        SubdivisionOptions{.levels = 3, .max_vertices = 100}, SubdivisionOptions{.levels = 2, .max_vertices = 26}}) {
    auto all = subdivide(cube, options);
    auto last = subdivide_last_level(cube, options);
    ASSERT_FALSE(all.has_value());
    ASSERT_FALSE(last.has_value());
    EXPECT_EQ(last.error().kind, all.error().kind);
    EXPECT_EQ(last.error().message, all.error().message);
  }
}


// Fills and frees heap blocks of the sizes of the arrays that refining each of `parents`
// leaves unwritten at first (`resize_for_overwrite`), so the allocator is likely to hand
// them back to the refinement: an element it forgot to write then keeps `byte`.
void poison_heap(const std::vector<const Mesh*>& parents, unsigned char byte) {
  std::vector<std::unique_ptr<unsigned char[]>> blocks;
  for (const Mesh* m : parents) {
    size_t corners = 0;
    for (int32_t f = 0; f < m->face_count(); ++f) corners += static_cast<size_t>(m->face_size(FaceId(f)));
    const size_t child_edges = 2 * static_cast<size_t>(m->edge_count()) + corners;
    const size_t child_vertices = static_cast<size_t>(m->vertex_count()) + m->edge_count() + m->face_count();
    for (const size_t bytes : {2 * child_edges * sizeof(EdgeUse), child_vertices * sizeof(EdgeId)}) {
      for (int copy = 0; copy < 4; ++copy) {
        blocks.emplace_back(new unsigned char[bytes]);
        std::memset(blocks.back().get(), byte, bytes);
      }
    }
  }
}

// The child's wings, faces of uses and vertex anchors are allocated without being filled;
// whatever the memory held before, the result is the same and consistent.
TEST(SubdivideLastLevel, ChildArraysAreFullyWritten) {
  for (const PolygonSoup& soup : last_level_soups()) {
    const Mesh mesh = build(soup);
    for (int32_t levels = 1; levels <= 3; ++levels) {
      auto reference = subdivide(mesh, {.levels = levels});
      ASSERT_TRUE(reference.has_value());
      std::vector<const Mesh*> parents{&mesh};
      for (const SubdivisionLevel& l : *reference) parents.push_back(&l.mesh);
      for (const unsigned char byte : {0x00, 0xff, 0x5a}) {
        SCOPED_TRACE(::testing::Message() << soup.face_count() << " faces, " << levels << " levels, byte " << int(byte));
        poison_heap(parents, byte);
        auto all = subdivide(mesh, {.levels = levels});
        ASSERT_TRUE(all.has_value());
        for (size_t i = 0; i < all->size(); ++i) {
          expect_identical((*all)[i].mesh, (*reference)[i].mesh);
          EXPECT_EQ(mesh_problem((*all)[i].mesh), "");
        }
        poison_heap(parents, byte);
        auto last = subdivide_last_level(mesh, {.levels = levels});
        ASSERT_TRUE(last.has_value());
        expect_identical(*last, reference->back().mesh);
      }
    }
  }
}

}  // namespace
}  // namespace nomec::kernel
