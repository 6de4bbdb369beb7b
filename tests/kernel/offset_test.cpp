// Offset and lattice tests: disks become spheres, Möbius bands and Klein bottles become
// tori, closed orientable inputs give two shells, the slab can be subdivided again, and
// the lattice of a cube is a genus-5 handlebody surface.
#include "kernel/offset.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>
#include <glm/geometric.hpp>

#include "kernel/subdivide.h"
#include "kernel/topology.h"
#include "tests/kernel/build.h"
#include "tests/kernel/shapes.h"

namespace nomec::kernel {
namespace {

using testing::Glue;
using testing::grid_soup;

using testing::build;

// `s` with its faces in a shuffled order, each rotated to start at a random corner (so the
// twin of a corner comes before or after it in every combination), all faces coloured.
PolygonSoup shuffled_soup(const PolygonSoup& s, uint32_t& seed) {
  auto random = [&](uint32_t n) {
    seed = seed * 1664525u + 1013904223u;
    return (seed >> 8) % n;
  };
  std::vector<std::vector<int32_t>> faces;
  size_t at = 0;
  for (int32_t n : s.face_sizes) {
    faces.emplace_back(s.face_vertices.begin() + at, s.face_vertices.begin() + at + n);
    at += n;
  }
  for (size_t i = faces.size(); i > 1; --i) std::swap(faces[i - 1], faces[random(uint32_t(i))]);
  PolygonSoup shuffled;
  shuffled.positions = s.positions;
  for (auto& f : faces) {
    std::rotate(f.begin(), f.begin() + random(uint32_t(f.size())), f.end());
    shuffled.add_face(f);
  }
  shuffled.face_colors.assign(shuffled.face_count(), glm::vec3(0.25f, 0.5f, 1.0f));
  return shuffled;
}

// Expects the direct slab and the reference construction of `mesh` to be the same: every
// array, the parents and the inconsistent-corner count, with and without parent maps.
void expect_direct_equals_reference(const Mesh& mesh, double distance, const std::string& what) {
  auto direct = offset(mesh, {.distance = distance});
  auto reference = offset_through_builder(mesh, {.distance = distance});
  ASSERT_TRUE(direct.has_value()) << what;
  ASSERT_TRUE(reference.has_value()) << what;
  EXPECT_TRUE(has_same_topology(direct->mesh, reference->mesh)) << what;
  EXPECT_EQ(direct->mesh.positions(), reference->mesh.positions()) << what;
  EXPECT_EQ(direct->mesh.has_mobius_edges(), reference->mesh.has_mobius_edges()) << what;
  EXPECT_EQ(direct->vertex_parents, reference->vertex_parents) << what;
  ASSERT_EQ(direct->face_parents.size(), reference->face_parents.size()) << what;
  for (size_t f = 0; f < direct->face_parents.size(); ++f) {
    ASSERT_EQ(direct->face_parents[f].kind, reference->face_parents[f].kind) << what << " face " << f;
    ASSERT_EQ(direct->face_parents[f].face, reference->face_parents[f].face) << what << " face " << f;
    ASSERT_EQ(direct->face_parents[f].edge, reference->face_parents[f].edge) << what << " face " << f;
  }
  EXPECT_EQ(direct->inconsistent_normal_count, reference->inconsistent_normal_count) << what;
  auto without_maps = offset(mesh, {.distance = distance, .has_parent_maps = false});
  ASSERT_TRUE(without_maps.has_value()) << what;
  EXPECT_TRUE(has_same_topology(without_maps->mesh, reference->mesh)) << what;
  EXPECT_EQ(without_maps->mesh.positions(), reference->mesh.positions()) << what;
  EXPECT_TRUE(without_maps->face_parents.empty() && without_maps->vertex_parents.empty()) << what;
  // The slab above came from the direct construction, not from its fallback (which is the
  // reference construction itself).
  auto direct_only = offset_direct_only(mesh, {.distance = distance});
  ASSERT_TRUE(direct_only.has_value()) << what;
  EXPECT_TRUE(has_same_topology(direct_only->mesh, reference->mesh)) << what;
  // The same slab from a copy the offset may free as it goes: without Möbius edges and with
  // every vertex used, the input's positions, wings and anchors are freed before the slab's
  // arrays are made (so nothing may read them after); otherwise the input is left whole.
  Mesh consumed = mesh;
  auto from_consumed = offset_consuming(std::move(consumed), {.distance = distance});
  ASSERT_TRUE(from_consumed.has_value()) << what;
  EXPECT_TRUE(has_same_topology(from_consumed->mesh, reference->mesh)) << what;
  EXPECT_EQ(from_consumed->mesh.positions(), reference->mesh.positions()) << what;
  EXPECT_EQ(from_consumed->vertex_parents, reference->vertex_parents) << what;
  EXPECT_EQ(from_consumed->face_parents.size(), reference->face_parents.size()) << what;
  EXPECT_EQ(from_consumed->inconsistent_normal_count, reference->inconsistent_normal_count) << what;
  bool every_vertex_used = true;
  for (int32_t v = 0; v < mesh.vertex_count(); ++v) every_vertex_used &= mesh.vertex_edge(VertexId(v)).is_valid();
  const bool is_released = every_vertex_used && !mesh.has_mobius_edges();
  EXPECT_EQ(consumed.positions().empty(), is_released) << what;  // NOLINT(bugprone-use-after-move)
}

// Closed, orientable, no Möbius edges, one component per expected entry.
void expect_closed_orientable(const Mesh& m, int32_t euler, size_t components) {
  TopologyReport r = topology(m);
  EXPECT_TRUE(r.is_closed);
  EXPECT_TRUE(r.is_orientable);
  EXPECT_FALSE(m.has_mobius_edges());
  EXPECT_EQ(r.euler_characteristic, euler);
  EXPECT_EQ(r.components.size(), components);
}

TEST(Offset, NewellNormals) {
  Mesh cube = build(testing::cube_soup());
  std::vector<glm::dvec3> n = face_normals(cube);
  EXPECT_EQ(n[0], glm::dvec3(0, 0, -1));
  EXPECT_EQ(n[1], glm::dvec3(0, 0, 1));
  EXPECT_EQ(n[5], glm::dvec3(1, 0, 0));
  VertexNormals vn = vertex_normals(cube, n);
  const double k = 1.0 / std::sqrt(3.0);
  EXPECT_NEAR(vn.normals[7].x, k, 1e-15);
  EXPECT_NEAR(vn.normals[0].z, -k, 1e-15);
  EXPECT_FALSE(cube.has_vertex_normals());
  assign_vertex_normals(cube);
  ASSERT_TRUE(cube.has_vertex_normals());
  EXPECT_EQ(cube.vertex_normal(VertexId(7)), vn.normals[7]);
  EXPECT_FALSE(cube.set_vertex_normals({glm::dvec3(0.0)}).has_value());
}

TEST(Offset, MobiusVertexNormalsUseTheCounter) {
  // On the seam of a Möbius band the neighbouring faces have opposite orientations; the
  // signed average must still be a unit vector close to the surface normal, and every
  // corner sign times the vertex normal must agree with its face normal.
  Mesh band = build(grid_soup(12, 2, Glue::Mobius));
  std::vector<glm::dvec3> fn = face_normals(band);
  VertexNormals vn = vertex_normals(band, fn);
  int mobius_vertices = 0;
  for (int32_t v = 0; v < band.vertex_count(); ++v) {
    EXPECT_NEAR(glm::length(vn.normals[v]), 1.0, 1e-12);
    mobius_vertices += vn.is_mobius_vertex[v];
    for (const VertexCorner& c : band.vertex_ring(VertexId(v))) {
      EXPECT_GT(vn.corner_signs[c.use.index] * glm::dot(vn.normals[v], fn[c.face.index]), 0.5);
    }
  }
  EXPECT_EQ(mobius_vertices, 3);  // the seam rung's three vertices
}

TEST(Offset, DiskBecomesSphere) {
  Mesh disk = build(grid_soup(3, 3, Glue::None));
  auto slab = offset(disk, {.distance = 0.1});
  ASSERT_TRUE(slab.has_value()) << slab.error().message;
  EXPECT_EQ(slab->mesh.vertex_count(), 2 * 16);
  EXPECT_EQ(slab->mesh.face_count(), 2 * 9 + 12);
  expect_closed_orientable(slab->mesh, 2, 1);
  EXPECT_EQ(slab->face_parents[9 + 4].kind, OffsetParent::Kind::NegativeFace);
  EXPECT_EQ(slab->face_parents[9 + 4].face, FaceId(4));
  EXPECT_EQ(slab->face_parents[18].kind, OffsetParent::Kind::Ribbon);
  // Every offset vertex is at the offset distance along the (planar) normal.
  for (int32_t v = 0; v < slab->mesh.vertex_count(); ++v) {
    const glm::dvec3 d = slab->mesh.position(VertexId(v)) - disk.position(slab->vertex_parents[v]);
    EXPECT_NEAR(glm::length(d), 0.1, 1e-12);
    EXPECT_NEAR(std::abs(d.z), 0.1, 1e-12);
  }
}

TEST(Offset, MobiusBandBecomesTorus) {
  Mesh band = build(grid_soup(12, 2, Glue::Mobius));
  ASSERT_FALSE(topology(band).is_orientable);
  auto slab = offset(band, {.distance = 0.05});
  ASSERT_TRUE(slab.has_value()) << slab.error().message;
  expect_closed_orientable(slab->mesh, 0, 1);
  EXPECT_EQ(topology(slab->mesh).components[0].genus, 1);
  EXPECT_EQ(slab->inconsistent_normal_count, 0);
  // 2V vertices, 2F faces plus one ribbon per border edge (24 border edges).
  EXPECT_EQ(slab->mesh.vertex_count(), 2 * 36);
  EXPECT_EQ(slab->mesh.face_count(), 2 * 24 + 24);
}

TEST(Offset, KleinBottleBecomesTorus) {
  Mesh klein = build(grid_soup(8, 6, Glue::Klein));
  auto slab = offset(klein, {.distance = 0.05});
  ASSERT_TRUE(slab.has_value()) << slab.error().message;
  expect_closed_orientable(slab->mesh, 0, 1);
  EXPECT_EQ(slab->mesh.face_count(), 2 * 48);
}

TEST(Offset, ClosedOrientableGivesTwoShells) {
  Mesh cube = build(testing::cube_soup());
  auto slab = offset(cube, {.distance = 0.1});
  ASSERT_TRUE(slab.has_value());
  expect_closed_orientable(slab->mesh, 4, 2);
  // The positive copy of vertex 7 moved outwards.
  EXPECT_GT(slab->mesh.position(VertexId(14)).x, 1.0);
}

TEST(Offset, AnnulusBecomesTorusAndSubdivides) {
  Mesh ring = build(grid_soup(8, 2, Glue::Cylinder));
  auto slab = offset(ring, {.distance = 0.1});
  ASSERT_TRUE(slab.has_value());
  expect_closed_orientable(slab->mesh, 0, 1);
  // §5.4: the slab is an ordinary closed mesh and can be subdivided again.
  auto levels = subdivide(slab->mesh, {.levels = 2});
  ASSERT_TRUE(levels.has_value());
  for (const SubdivisionLevel& level : *levels) {
    expect_closed_orientable(level.mesh, 0, 1);
  }
}

TEST(Offset, SubdividedMobiusBandOffsetsToTorus) {
  Mesh band = build(grid_soup(6, 1, Glue::Mobius));
  auto levels = subdivide(band, {.levels = 2});
  ASSERT_TRUE(levels.has_value());
  auto slab = offset(levels->back().mesh, {.distance = 0.02});
  ASSERT_TRUE(slab.has_value()) << slab.error().message;
  expect_closed_orientable(slab->mesh, 0, 1);
  EXPECT_EQ(slab->inconsistent_normal_count, 0);
}

TEST(Offset, ReversedFacesStillGiveOrientableShells) {
  // Reversing faces creates Möbius edges in an orientable surface; the counter handles
  // them and the slab is still two spheres... for the cube, and one sphere for a disk.
  PolygonSoup s = grid_soup(3, 3, Glue::None);
  std::reverse(s.face_vertices.begin() + 4, s.face_vertices.begin() + 8);
  std::reverse(s.face_vertices.begin() + 16, s.face_vertices.begin() + 20);
  Mesh disk = build(s);
  ASSERT_TRUE(disk.has_mobius_edges());
  auto slab = offset(disk, {.distance = 0.1});
  ASSERT_TRUE(slab.has_value());
  expect_closed_orientable(slab->mesh, 2, 1);
}

TEST(Offset, IsolatedVerticesAreDropped) {
  PolygonSoup s = grid_soup(1, 1, Glue::None);
  s.add_vertex({9, 9, 9});
  auto slab = offset(build(s), {.distance = 0.1});
  ASSERT_TRUE(slab.has_value());
  EXPECT_EQ(slab->mesh.vertex_count(), 8);  // a box around the single quad
  expect_closed_orientable(slab->mesh, 2, 1);
}

// The offset pairs its soup's edges from the input's instead of searching for them; the
// mesh must be exactly the one the searching builder makes of the same faces (edge
// numbering, wings, anchors, Möbius flags, sources), on borders, Möbius edges, mixed
// polygons, reversed faces and isolated vertices.
TEST(Offset, PairedBuildEqualsTheBuilder) {
  std::vector<PolygonSoup> inputs = {testing::cube_soup(), testing::tetra_soup(), testing::mixed_disk_soup(),
                                     grid_soup(4, 3, Glue::None), grid_soup(6, 3, Glue::Cylinder),
                                     grid_soup(9, 4, Glue::Mobius), grid_soup(6, 5, Glue::Torus),
                                     grid_soup(8, 6, Glue::Klein, 0.01), grid_soup(3, 3, Glue::None)};
  PolygonSoup& flipped = inputs.back();
  std::reverse(flipped.face_vertices.begin() + 4, flipped.face_vertices.begin() + 8);
  flipped.add_vertex({9, 9, 9});
  flipped.face_colors.assign(flipped.face_count(), glm::vec3(0.5f, 0.25f, 1.0f));
  std::vector<Mesh> meshes;
  for (const PolygonSoup& s : inputs) meshes.push_back(build(s));
  meshes.push_back(subdivide_once(build(grid_soup(5, 3, Glue::Mobius))).mesh);
  for (size_t i = 0; i < meshes.size(); ++i) {
    for (bool is_lattice : {false, true}) {
      auto r = is_lattice ? lattice(meshes[i], {.width = 0.1, .distance = 0.05}) : offset(meshes[i], {.distance = 0.1});
      ASSERT_TRUE(r.has_value()) << i;
      const Mesh rebuilt = build(to_soup(r->mesh));
      EXPECT_TRUE(has_same_topology(r->mesh, rebuilt)) << "input " << i << (is_lattice ? " (lattice)" : "");
      EXPECT_EQ(r->mesh.positions(), rebuilt.positions()) << i;
      if (!is_lattice) {
        int32_t borders = 0;
        for (int32_t e = 0; e < meshes[i].edge_count(); ++e) borders += meshes[i].is_boundary(EdgeId(e)) ? 1 : 0;
        EXPECT_EQ(r->mesh.face_count(), 2 * meshes[i].face_count() + borders) << i;
      }
    }
  }
}

// `offset` writes the slab's arrays directly; the reference construction rebuilds the
// same slab from its polygon soup with the builder. Both must give the same mesh (every
// array), parents and normal count, on borders, Möbius edges (positive corners pairing
// with negative ones), mixed polygons, colours, isolated vertices, and faces listed in a
// shuffled order from shuffled starting corners (so the twin of a corner comes before or
// after it in every combination). The plain inputs without Möbius edges read each corner's
// output vertex from the input's edge vertices; the shuffled ones, which have an isolated
// vertex, and the Möbius and Klein ones keep it in an array (`offset_direct`'s P).
TEST(Offset, DirectSlabEqualsTheReferenceConstruction) {
  std::vector<PolygonSoup> inputs = {testing::cube_soup(), testing::tetra_soup(), testing::mixed_disk_soup(),
                                     grid_soup(4, 3, Glue::None), grid_soup(6, 3, Glue::Cylinder),
                                     grid_soup(9, 4, Glue::Mobius), grid_soup(6, 5, Glue::Torus),
                                     grid_soup(8, 6, Glue::Klein, 0.01), grid_soup(7, 5, Glue::Klein)};
  uint32_t seed = 12345;
  const size_t plain = inputs.size();
  for (size_t k = 0; k < plain; ++k) {
    PolygonSoup shuffled = shuffled_soup(inputs[k], seed);
    shuffled.add_vertex({7, 7, 7});
    inputs.push_back(std::move(shuffled));
  }
  std::vector<Mesh> meshes;
  for (const PolygonSoup& s : inputs) meshes.push_back(build(s));
  meshes.push_back(subdivide_once(build(grid_soup(5, 3, Glue::Mobius))).mesh);
  meshes.push_back(subdivide_once(build(testing::mixed_disk_soup())).mesh);
  for (size_t i = 0; i < meshes.size(); ++i) expect_direct_equals_reference(meshes[i], 0.1, std::to_string(i));
}

// `count` closed n-gon prisms side by side (n quads and two n-gon caps each), every face
// with a source of its own. With n > 4 such a mesh has more edges than its slab has faces,
// so the offset keeps its per-edge slots in an array of their own instead of in the slab's
// unwritten face sources.
PolygonSoup prisms_soup(int count, int n) {
  PolygonSoup s;
  const double pi = std::numbers::pi;
  for (int k = 0; k < count; ++k) {
    const int first = s.vertex_count();
    for (int level = 0; level < 2; ++level) {
      for (int i = 0; i < n; ++i) {
        const double u = 2 * pi * i / n;
        s.add_vertex({3.0 * k + std::cos(u), std::sin(u), double(level)});
      }
    }
    std::vector<int32_t> bottom, top;
    for (int i = 0; i < n; ++i) {
      s.add_face({first + i, first + (i + 1) % n, first + n + (i + 1) % n, first + n + i});
      bottom.push_back(first + n - 1 - i);
      top.push_back(first + n + i);
    }
    s.add_face(bottom);
    s.add_face(top);
  }
  for (int32_t f = 0; f < s.face_count(); ++f) s.face_sources.push_back({f, 3});
  return s;
}

// The slots live in the slab's face sources while those are unwritten, when they have room
// (closed quad and triangle meshes, meshes with borders); closed meshes of larger polygons
// keep them in an array of their own. Both ways, on one thread and on two, and the
// sources written over the slots, must give the reference construction.
TEST(Offset, SlotsWithAndWithoutRoomInTheSourcesEqualTheReference) {
  struct Input {
    std::string what;
    PolygonSoup soup;
    bool has_own_slots;  // more edges than slab faces
  };
  const std::vector<Input> inputs = {
      {"one octagonal prism", prisms_soup(1, 8), true},      // 24 edges, 20 slab faces
      {"one square prism", prisms_soup(1, 4), false},        // 12 edges, 12 slab faces
      {"dodecagonal prisms", prisms_soup(2400, 12), true},   // 33,600 faces: two threads
      {"square prisms", prisms_soup(5500, 4), false}};       // 33,000 faces: two threads
  for (const auto& [what, soup, has_own_slots] : inputs) {
    const Mesh mesh = build(soup);
    const int64_t slab_faces = 2 * int64_t{mesh.face_count()};  // closed: no ribbons
    EXPECT_EQ(mesh.edge_count() > slab_faces, has_own_slots) << what;
    expect_direct_equals_reference(mesh, 0.05, what);
    auto slab = offset(mesh, {.distance = 0.05});
    ASSERT_TRUE(slab.has_value()) << what;
    for (int32_t f = 0; f < slab->mesh.face_count(); ++f) {
      ASSERT_EQ(slab->mesh.face_source(FaceId(f)).source_face, f % mesh.face_count()) << what << " face " << f;
    }
  }
}

// Without Möbius edges the positive and negative copies of a large mesh are made on two
// threads, the negative copies' edges numbered from the input's edge count on: on meshes
// above the threshold (32,768 faces) with borders, shuffled faces and starting corners (a
// corner's twin before or after it, in the same face or another), mixed polygons and the
// layout of a Catmull-Clark level, the slab must equal the reference construction. A
// Möbius grid of the same size (made on one thread) is the control.
TEST(Offset, ThreadedCopiesEqualTheReference) {
  uint32_t seed = 777;
  std::vector<std::pair<std::string, Mesh>> meshes;
  meshes.emplace_back("shuffled disk", build(shuffled_soup(grid_soup(200, 180, Glue::None), seed)));
  meshes.emplace_back("shuffled cylinder", build(shuffled_soup(grid_soup(190, 180, Glue::Cylinder), seed)));
  meshes.emplace_back("subdivided cylinder", subdivide_once(build(grid_soup(100, 90, Glue::Cylinder))).mesh);
  meshes.emplace_back("subdivided mixed disk", subdivide_last_level(build(testing::mixed_disk_soup()), {.levels = 6}).value());
  meshes.emplace_back("Möbius grid", build(grid_soup(200, 180, Glue::Mobius)));
  for (const auto& [what, mesh] : meshes) {
    ASSERT_GE(mesh.face_count(), 1 << 15) << what;
    expect_direct_equals_reference(mesh, 0.05, what);
  }
}

// A flat n x m grid with a hole at every cell (i, j) with i and j odd, inside the border:
// (n / 2)² border loops of four edges, no two of them sharing a vertex.
PolygonSoup holed_grid_soup(int n, int m) {
  PolygonSoup s;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= m; ++j) s.add_vertex({double(i), double(j), 0.0});
  }
  auto id = [&](int i, int j) { return i * (m + 1) + j; };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      if (i % 2 == 1 && j % 2 == 1 && i + 1 < n && j + 1 < m) continue;
      s.add_face({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return s;
}

// `count` separate quads, each its own component with one border loop.
PolygonSoup separate_quads_soup(int count) {
  PolygonSoup s;
  for (int k = 0; k < count; ++k) {
    const double x = 2.0 * (k % 128), y = 2.0 * (k / 128);
    const int a = s.add_vertex({x, y, 0.0});
    const int b = s.add_vertex({x + 1, y, 0.0});
    const int c = s.add_vertex({x + 1, y + 1, 0.1});
    const int d = s.add_vertex({x, y + 1, 0.0});
    s.add_face({a, b, c, d});
  }
  return s;
}

// Without Möbius edges, a mesh with many border edges (from 32,768) makes its ribbons on two
// threads, each half of the border edges on its own; the side edges a ribbon shares with its
// neighbours are numbered as one thread would number them, also when the neighbour lies in
// the other half. On many holes and many components, in the builder's face order, shuffled
// (so a side's first corner is a corner 1 or a corner 3, before or after the middle), and in
// the layout of Catmull-Clark levels, the slab must equal the reference construction.
TEST(Offset, ThreadedRibbonsEqualTheReference) {
  uint32_t seed = 4242;
  std::vector<std::pair<std::string, Mesh>> meshes;
  meshes.emplace_back("holed grid", build(holed_grid_soup(184, 184)));
  meshes.emplace_back("shuffled holed grid", build(shuffled_soup(holed_grid_soup(184, 184), seed)));
  meshes.emplace_back("shuffled separate quads", build(shuffled_soup(separate_quads_soup(8200), seed)));
  meshes.emplace_back("subdivided holed grid", subdivide_last_level(build(holed_grid_soup(100, 100)), {.levels = 2}).value());
  for (const auto& [what, mesh] : meshes) {
    int32_t border_edges = 0;
    for (int32_t e = 0; e < mesh.edge_count(); ++e) border_edges += mesh.is_boundary(EdgeId(e)) ? 1 : 0;
    ASSERT_GE(border_edges, 1 << 15) << what;
    ASSERT_FALSE(mesh.has_mobius_edges()) << what;
    expect_direct_equals_reference(mesh, 0.05, what);
    // A slab whose loops are wrong could send the walk below round a loop for ever.
    ASSERT_FALSE(HasFailure()) << what;
    TopologyReport r = topology(offset(mesh, {.distance = 0.05})->mesh);
    EXPECT_TRUE(r.is_closed) << what;
    EXPECT_TRUE(r.is_orientable) << what;
  }
}

// The direct slab computes its normals, offset positions and corner vertices in one walk
// per vertex, on two threads for large meshes (and counts inconsistent Möbius corners per
// thread): on meshes above the threading threshold, with borders, Möbius and Klein seams
// and folded geometry, it must still equal the reference construction.
TEST(Offset, DirectSlabEqualsTheReferenceOnThreadedSizes) {
  const std::vector<Mesh> meshes = {build(grid_soup(400, 100, Glue::Mobius, 0.02)),
                                    build(grid_soup(300, 120, Glue::Klein, 0.01)),
                                    build(grid_soup(256, 140, Glue::Torus)),
                                    build(grid_soup(200, 180, Glue::None))};
  int32_t inconsistent = 0;
  for (size_t i = 0; i < meshes.size(); ++i) {
    ASSERT_GE(meshes[i].vertex_count(), 1 << 15) << i;
    auto direct = offset(meshes[i], {.distance = 0.05});
    auto reference = offset_through_builder(meshes[i], {.distance = 0.05});
    ASSERT_TRUE(direct.has_value()) << i;
    ASSERT_TRUE(reference.has_value()) << i;
    EXPECT_TRUE(has_same_topology(direct->mesh, reference->mesh)) << i;
    EXPECT_EQ(direct->mesh.positions(), reference->mesh.positions()) << i;
    EXPECT_EQ(direct->vertex_parents, reference->vertex_parents) << i;
    EXPECT_EQ(direct->inconsistent_normal_count, reference->inconsistent_normal_count) << i;
    inconsistent += reference->inconsistent_normal_count;
  }
  RecordProperty("inconsistent_corners", inconsistent);
}

// Face and vertex normals of large meshes are computed on two threads (each half of the
// faces, and of the vertices, on its own); they must equal the one-thread computation
// written out here, on a Möbius grid large enough for the threads (flipped corners too).
TEST(Offset, ThreadedNormalsEqualOneThread) {
  const Mesh mesh = build(grid_soup(400, 100, Glue::Mobius, 0.02));
  ASSERT_GE(mesh.face_count(), 1 << 15);
  ASSERT_GE(mesh.vertex_count(), 1 << 15);
  const std::vector<glm::dvec3> fn = face_normals(mesh);
  ASSERT_EQ(fn.size(), size_t(mesh.face_count()));
  for (int32_t f = 0; f < mesh.face_count(); ++f) {
    std::vector<glm::dvec3> points;
    for (VertexId v : mesh.face_vertices(FaceId(f))) points.push_back(mesh.position(v));
    ASSERT_EQ(fn[f], newell_normal(points)) << "face " << f;
  }
  const VertexNormals vn = vertex_normals(mesh, fn);
  std::vector<int8_t> signs(2 * size_t(mesh.edge_count()), 0);
  int32_t mobius_vertices = 0;
  for (int32_t v = 0; v < mesh.vertex_count(); ++v) {
    glm::dvec3 sum(0.0);
    const std::vector<VertexCorner> ring = mesh.vertex_ring(VertexId(v));
    for (const VertexCorner& c : ring) {
      signs[c.use.index] = c.is_flipped ? -1 : 1;
      sum += double(c.is_flipped ? -1 : 1) * fn[c.face.index];
    }
    const double len = glm::length(sum);
    ASSERT_EQ(vn.normals[v], len > 1e-12 ? sum / len : fn[ring.front().face.index]) << "vertex " << v;
    mobius_vertices += vn.is_mobius_vertex[v];
  }
  EXPECT_EQ(vn.corner_signs, signs);
  EXPECT_GT(mobius_vertices, 0);
  EXPECT_NE(std::count(signs.begin(), signs.end(), int8_t(-1)), 0);
}

TEST(Offset, RejectsBadDistance) {
  Mesh cube = build(testing::cube_soup());
  auto r = offset(cube, {.distance = 0.0});
  ASSERT_FALSE(r.has_value());
  EXPECT_EQ(r.error().kind, KernelError::Kind::InvalidArgument);
  auto l = lattice(cube, {.width = -1, .distance = 0.1});
  ASSERT_FALSE(l.has_value());
}

TEST(Lattice, CubeFrameIsGenusFive) {
  Mesh cube = build(testing::cube_soup());
  auto slab = lattice(cube, {.width = 0.2, .distance = 0.05});
  ASSERT_TRUE(slab.has_value()) << slab.error().message;
  // Frame: 8 + 24 vertices, 24 quads; χ(frame) = 2 - 6 = -4, slab χ = -8.
  expect_closed_orientable(slab->mesh, -8, 1);
  EXPECT_EQ(topology(slab->mesh).components[0].genus, 5);
  EXPECT_EQ(slab->mesh.face_count(), 2 * 24 + 24);
  EXPECT_EQ(slab->face_parents[0].face, FaceId(0));
  EXPECT_EQ(slab->face_parents[23].face, FaceId(5));
}

TEST(Lattice, SubdividedLatticeStaysGenusFive) {
  // The usual NOME pipeline: a lattice of a subdivided cube, rounded by subdividing again.
  auto smooth = subdivide(build(testing::cube_soup()), {.levels = 1});
  ASSERT_TRUE(smooth.has_value());
  auto slab = lattice(smooth->back().mesh, {.width = 0.05, .distance = 0.02});
  ASSERT_TRUE(slab.has_value()) << slab.error().message;
  // χ = 2 (χ - F) = 2 (2 - 24) = -44: genus 23.
  expect_closed_orientable(slab->mesh, -44, 1);
  auto rounded = subdivide(slab->mesh, {.levels = 1});
  ASSERT_TRUE(rounded.has_value());
  expect_closed_orientable(rounded->back().mesh, -44, 1);
  EXPECT_EQ(topology(rounded->back().mesh).components[0].genus, 23);
}

TEST(Lattice, MobiusBandLattice) {
  Mesh band = build(grid_soup(6, 1, Glue::Mobius));
  auto slab = lattice(band, {.width = 0.1, .distance = 0.02});
  ASSERT_TRUE(slab.has_value()) << slab.error().message;
  // χ = 2 (0 - 6) = -12, one closed orientable surface.
  expect_closed_orientable(slab->mesh, -12, 1);
}

}  // namespace
}  // namespace nomec::kernel
