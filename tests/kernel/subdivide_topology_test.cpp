// Differential tests of the child topology that Catmull-Clark writes arithmetically (no
// builder) against the generic builder run on the same child faces: every face corner must
// have the same twin corner, Möbius flag, wings, vertex fan and border neighbours, on
// meshes with borders, Möbius edges, Klein bottles, mixed polygons, creases and several
// components. Also the child→parent face map, stored only for non-quad parents.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <utility>
#include <vector>

#include "kernel/subdivide.h"
#include "kernel/topology.h"
#include "tests/kernel/build.h"
#include "tests/kernel/shapes.h"

namespace nomec::kernel {
namespace {

using testing::build;
using testing::Glue;
using testing::grid_soup;

// A corner is (face, position in the face's loop from its first use); both meshes number
// faces and start loops alike, so corners name the same use in both.
using Corner = std::pair<int32_t, int32_t>;

std::map<int32_t, Corner> corners_of(const Mesh& m) {
  std::map<int32_t, Corner> out;
  for (int32_t f = 0; f < m.face_count(); ++f) {
    int32_t i = 0;
    m.for_each_face_use(FaceId(f), [&](EdgeUse u) { out[u.index] = {f, i++}; });
  }
  return out;
}

// The border neighbours of a border edge as sorted vertex pairs, keyed by its own pair.
using Pair = std::pair<int32_t, int32_t>;
Pair pair_of(const Mesh& m, EdgeId e) {
  const int32_t a = m.edge_vertex(e, 0).index, b = m.edge_vertex(e, 1).index;
  return {std::min(a, b), std::max(a, b)};
}
std::map<Pair, std::vector<Pair>> border_neighbours(const Mesh& m) {
  std::map<Pair, std::vector<Pair>> out;
  for (int32_t loop = 0; loop < static_cast<int32_t>(m.border_loops().size()); ++loop) {
    for (EdgeId e : m.border_loop_edges(loop)) {
      std::vector<Pair> n{pair_of(m, m.border_next(e)), pair_of(m, m.border_prev(e))};
      std::sort(n.begin(), n.end());
      out[pair_of(m, e)] = n;
    }
  }
  return out;
}

std::vector<Corner> sorted_ring(const Mesh& m, VertexId v, const std::map<int32_t, Corner>& corners) {
  std::vector<Corner> ring;
  m.for_each_vertex_corner(v, [&](const VertexCorner& c) { ring.push_back(corners.at(c.use.index)); });
  std::sort(ring.begin(), ring.end());
  return ring;
}

void expect_same_as_builder(const Mesh& child) {
  ASSERT_EQ(mesh_problem(child), "");
  const Mesh built = build(to_soup(child));
  ASSERT_EQ(built.vertex_count(), child.vertex_count());
  ASSERT_EQ(built.edge_count(), child.edge_count());
  ASSERT_EQ(built.face_count(), child.face_count());
  const auto cc = corners_of(child);
  const auto bc = corners_of(built);
  for (int32_t f = 0; f < child.face_count(); ++f) {
    ASSERT_EQ(child.face_size(FaceId(f)), built.face_size(FaceId(f)));
    EXPECT_EQ(child.face_source(FaceId(f)), built.face_source(FaceId(f)));
    std::vector<EdgeUse> cu, bu;
    child.for_each_face_use(FaceId(f), [&](EdgeUse u) { cu.push_back(u); });
    built.for_each_face_use(FaceId(f), [&](EdgeUse u) { bu.push_back(u); });
    for (size_t i = 0; i < cu.size(); ++i) {
      SCOPED_TRACE(::testing::Message() << "face " << f << " corner " << i);
      EXPECT_EQ(child.use_tail(cu[i]), built.use_tail(bu[i]));
      EXPECT_EQ(child.use_head(cu[i]), built.use_head(bu[i]));
      EXPECT_EQ(cc.at(child.prev(cu[i]).index), bc.at(built.prev(bu[i]).index));
      EXPECT_EQ(cc.at(child.next(cu[i]).index), bc.at(built.next(bu[i]).index));
      EXPECT_EQ(child.is_mobius(cu[i].edge()), built.is_mobius(bu[i].edge()));
      EXPECT_EQ(child.sharpness(cu[i].edge()), built.sharpness(bu[i].edge()));
      ASSERT_EQ(child.is_boundary(cu[i].edge()), built.is_boundary(bu[i].edge()));
      if (!child.is_boundary(cu[i].edge())) {
        EXPECT_EQ(cc.at(cu[i].twin().index), bc.at(bu[i].twin().index));
      }
    }
  }
  for (int32_t v = 0; v < child.vertex_count(); ++v) {
    SCOPED_TRACE(::testing::Message() << "vertex " << v);
    EXPECT_EQ(child.is_boundary_vertex(VertexId(v)), built.is_boundary_vertex(VertexId(v)));
    EXPECT_EQ(sorted_ring(child, VertexId(v), cc), sorted_ring(built, VertexId(v), bc));
  }
  EXPECT_EQ(child.border_loops().size(), built.border_loops().size());
  EXPECT_EQ(border_neighbours(child), border_neighbours(built));
}

// Appends `b` to `a` as a separate component, moved by `shift`.
PolygonSoup with_component(PolygonSoup a, const PolygonSoup& b, glm::dvec3 shift) {
  const int32_t base = a.vertex_count();
  for (const glm::dvec3& p : b.positions) a.add_vertex(p + shift);
  size_t offset = 0;
  for (int32_t n : b.face_sizes) {
    std::vector<int32_t> face;
    for (int32_t i = 0; i < n; ++i) face.push_back(base + b.face_vertices[offset + i]);
    a.add_face(face);
    offset += n;
  }
  for (const PolygonSoup::Crease& c : b.creases) a.creases.push_back({base + c.a, base + c.b, c.sharpness});
  return a;
}

// Reverses every third face, so their shared edges become Möbius edges.
PolygonSoup with_flipped_faces(PolygonSoup s) {
  size_t offset = 0;
  for (int32_t f = 0; f < s.face_count(); ++f) {
    if (f % 3 == 1) {
      std::reverse(s.face_vertices.begin() + offset, s.face_vertices.begin() + offset + s.face_sizes[f]);
    }
    offset += s.face_sizes[f];
  }
  return s;
}

void expect_levels_same_as_builder(const PolygonSoup& soup, int levels) {
  auto result = subdivide(build(soup), {.levels = levels});
  ASSERT_TRUE(result.has_value());
  for (int level = 0; level < levels; ++level) {
    SCOPED_TRACE(::testing::Message() << "level " << level + 1);
    expect_same_as_builder((*result)[level].mesh);
  }
}

TEST(SubdivideTopology, GridWithBorder) { expect_levels_same_as_builder(grid_soup(4, 3, Glue::None), 2); }

TEST(SubdivideTopology, MobiusBand) { expect_levels_same_as_builder(grid_soup(5, 2, Glue::Mobius), 2); }

TEST(SubdivideTopology, KleinBottle) { expect_levels_same_as_builder(grid_soup(4, 4, Glue::Klein), 2); }

TEST(SubdivideTopology, MixedPolygonsWithFlippedFacesAndCreases) {
  PolygonSoup s = with_flipped_faces(testing::mixed_disk_soup());
  s.creases.push_back({0, 1, 1.5f});
  s.creases.push_back({5, 6, kInfiniteSharpness});
  expect_levels_same_as_builder(s, 2);
}

TEST(SubdivideTopology, SeveralComponents) {
  PolygonSoup s = with_component(testing::cube_soup(), grid_soup(5, 2, Glue::Mobius), {5, 0, 0});
  s = with_component(std::move(s), testing::mixed_disk_soup(), {0, 5, 0});
  s = with_component(std::move(s), grid_soup(3, 3, Glue::Cylinder), {0, 0, 5});
  expect_levels_same_as_builder(s, 2);
}

TEST(SubdivideTopology, QuadParentsNeedNoStoredFaceMap) {
  auto levels = subdivide(build(grid_soup(4, 3, Glue::Torus)), {.levels = 2});
  ASSERT_TRUE(levels.has_value());
  for (const SubdivisionLevel& l : *levels) {
    EXPECT_TRUE(l.are_parent_faces_quads);
    EXPECT_TRUE(l.face_parents.empty());
    EXPECT_EQ(l.face_parent(FaceId(9)), FaceId(2));
  }
}

TEST(SubdivideTopology, FaceMapStoredFromTheFirstOtherPolygon) {
  // Quads first, then a triangle: the map is filled back for the quads' children.
  PolygonSoup s = grid_soup(2, 1, Glue::None);  // vertices 0..5, quads 0-1
  const int32_t apex = s.add_vertex({1, -1, 0});
  s.add_face({apex, 2, 0});
  SubdivisionLevel l = subdivide_once(build(s));
  EXPECT_FALSE(l.are_parent_faces_quads);
  ASSERT_EQ(l.face_parents.size(), 4u + 4u + 3u);
  for (int32_t q = 0; q < 11; ++q) {
    EXPECT_EQ(l.face_parent(FaceId(q)), FaceId(q < 8 ? q / 4 : 2));
    // The child face holds its parent's face point.
    const std::vector<VertexId> vs = l.mesh.face_vertices(FaceId(q));
    EXPECT_NE(std::find(vs.begin(), vs.end(), VertexId(l.face_parent(FaceId(q)).index)), vs.end());
  }
  // A triangle and a pentagon have 4 corners per face on average but are not quads.
  PolygonSoup house;
  for (int i = 0; i < 6; ++i) house.add_vertex({double(i % 3), double(i / 3), 0.1 * i});
  house.add_face({0, 1, 2, 5, 3});
  house.add_face({0, 3, 4});
  SubdivisionLevel h = subdivide_once(build(house));
  EXPECT_FALSE(h.are_parent_faces_quads);
  ASSERT_EQ(h.face_parents.size(), 8u);
  EXPECT_EQ(h.face_parent(FaceId(4)), FaceId(0));
  EXPECT_EQ(h.face_parent(FaceId(5)), FaceId(1));
  // Without maps nothing is stored.
  SubdivisionLevel none = subdivide_once(build(house), {.has_parent_maps = false});
  EXPECT_TRUE(none.face_parents.empty());
}

}  // namespace
}  // namespace nomec::kernel
