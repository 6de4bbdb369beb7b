// Oracle test: our Catmull-Clark levels 1-3 against OpenSubdiv's Far refinement
// (Catmark, edge-only boundary interpolation, uniform creasing) vertex for vertex within
// 1e-9, on orientable meshes with borders, creases (integer and fractional sharpness)
// and triangles/quads/pentagons. Vertices are matched through OpenSubdiv's own
// parent→child relations (face/edge/vertex child vertex), so the check does not depend
// on either side's numbering of edges.
#include <gtest/gtest.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <map>

#include "kernel/subdivide.h"
#include "tests/kernel/shapes.h"

namespace nomec::kernel {
namespace {

using namespace OpenSubdiv;
using testing::Glue;
using testing::grid_soup;

struct Point {
  double p[3];
  void Clear() { p[0] = p[1] = p[2] = 0; }
  void AddWithWeight(const Point& src, double w) {
    p[0] += w * src.p[0];
    p[1] += w * src.p[1];
    p[2] += w * src.p[2];
  }
};

// Runs both refiners to `max_level` and compares every vertex of every level.
void expect_matches_opensubdiv(const PolygonSoup& soup, int max_level) {
  auto built = build_mesh(soup);
  ASSERT_TRUE(built.has_value()) << built.error().message;
  auto ours = subdivide(*built, {.levels = max_level});
  ASSERT_TRUE(ours.has_value());

  Far::TopologyDescriptor desc;
  desc.numVertices = soup.vertex_count();
  desc.numFaces = soup.face_count();
  desc.numVertsPerFace = soup.face_sizes.data();
  desc.vertIndicesPerFace = soup.face_vertices.data();
  std::vector<int> crease_pairs;
  std::vector<float> crease_weights;
  for (const PolygonSoup::Crease& c : soup.creases) {
    crease_pairs.push_back(c.a);
    crease_pairs.push_back(c.b);
    crease_weights.push_back(std::isinf(c.sharpness) ? Sdc::Crease::SHARPNESS_INFINITE
                                                     : c.sharpness);
  }
  desc.numCreases = static_cast<int>(crease_weights.size());
  desc.creaseVertexIndexPairs = crease_pairs.data();
  desc.creaseWeights = crease_weights.data();
  std::vector<int> corner_vertices;
  std::vector<float> corner_weights;
  for (const PolygonSoup::Corner& c : soup.corners) {
    corner_vertices.push_back(c.vertex);
    corner_weights.push_back(std::isinf(c.sharpness) ? Sdc::Crease::SHARPNESS_INFINITE
                                                     : c.sharpness);
  }
  desc.numCorners = static_cast<int>(corner_weights.size());
  desc.cornerVertexIndices = corner_vertices.data();
  desc.cornerWeights = corner_weights.data();
  Sdc::Options sdc;
  sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
  sdc.SetCreasingMethod(Sdc::Options::CREASE_UNIFORM);
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  std::unique_ptr<Far::TopologyRefiner> refiner(
      Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, sdc)));
  ASSERT_TRUE(refiner);
  Far::TopologyRefiner::UniformOptions uniform(max_level);
  uniform.fullTopologyInLastLevel = true;
  refiner->RefineUniform(uniform);

  std::vector<Point> osd(refiner->GetNumVerticesTotal());
  for (int v = 0; v < soup.vertex_count(); ++v) {
    osd[v] = {{soup.positions[v].x, soup.positions[v].y, soup.positions[v].z}};
  }
  Far::PrimvarRefinerReal<double> primvar(*refiner);
  std::vector<int> level_start{0};
  for (int level = 1; level <= max_level; ++level) {
    level_start.push_back(level_start.back() + refiner->GetLevel(level - 1).GetNumVertices());
    Point* src = &osd[level_start[level - 1]];
    Point* dst = &osd[level_start[level]];
    primvar.Interpolate(level, src, dst);
  }

  // osd vertex -> our vertex, per level. Level 0 is the identity.
  std::vector<int32_t> vmap(soup.vertex_count());
  for (int v = 0; v < soup.vertex_count(); ++v) {
    vmap[v] = v;
  }
  const Mesh* parent = &*built;
  for (int level = 1; level <= max_level; ++level) {
    const Far::TopologyLevel& pl = refiner->GetLevel(level - 1);
    const Far::TopologyLevel& cl = refiner->GetLevel(level);
    const SubdivisionLevel& child = (*ours)[level - 1];
    ASSERT_EQ(cl.GetNumVertices(), child.mesh.vertex_count()) << "level " << level;
    ASSERT_EQ(cl.GetNumFaces(), child.mesh.face_count());
    ASSERT_EQ(cl.GetNumEdges(), child.mesh.edge_count());
    std::vector<int32_t> next(cl.GetNumVertices(), -1);
    const int32_t F = parent->face_count(), E = parent->edge_count();
    // Faces are numbered identically at level 0 only; match faces through their vertex
    // sets in general.
    std::map<std::vector<int32_t>, int32_t> our_faces;
    for (int32_t f = 0; f < F; ++f) {
      std::vector<int32_t> key;
      for (VertexId v : parent->face_vertices(FaceId(f))) {
        key.push_back(v.index);
      }
      std::sort(key.begin(), key.end());
      our_faces[key] = f;
    }
    for (int f = 0; f < pl.GetNumFaces(); ++f) {
      std::vector<int32_t> key;
      for (int v : pl.GetFaceVertices(f)) {
        key.push_back(vmap[v]);
      }
      std::sort(key.begin(), key.end());
      auto it = our_faces.find(key);
      ASSERT_NE(it, our_faces.end());
      next[pl.GetFaceChildVertex(f)] = it->second;
    }
    for (int e = 0; e < pl.GetNumEdges(); ++e) {
      auto ev = pl.GetEdgeVertices(e);
      EdgeId ours_e = parent->find_edge(VertexId(vmap[ev[0]]), VertexId(vmap[ev[1]]));
      ASSERT_TRUE(ours_e.is_valid());
      next[pl.GetEdgeChildVertex(e)] = F + ours_e.index;
    }
    for (int v = 0; v < pl.GetNumVertices(); ++v) {
      next[pl.GetVertexChildVertex(v)] = F + E + vmap[v];
    }
    for (int v = 0; v < cl.GetNumVertices(); ++v) {
      ASSERT_GE(next[v], 0);
      const Point& o = osd[level_start[level] + v];
      const glm::dvec3& p = child.mesh.position(VertexId(next[v]));
      ASSERT_NEAR(p.x, o.p[0], 1e-9) << "level " << level << " vertex " << next[v];
      ASSERT_NEAR(p.y, o.p[1], 1e-9) << "level " << level << " vertex " << next[v];
      ASSERT_NEAR(p.z, o.p[2], 1e-9) << "level " << level << " vertex " << next[v];
    }
    vmap = std::move(next);
    parent = &child.mesh;
  }
}

TEST(OpenSubdivOracle, Cube) { expect_matches_opensubdiv(testing::cube_soup(), 3); }

TEST(OpenSubdivOracle, CubeWithCreases) {
  PolygonSoup s = testing::cube_soup();
  s.creases.push_back({0, 2, 2.0f});
  s.creases.push_back({2, 3, 1.0f});
  s.creases.push_back({3, 1, kInfiniteSharpness});
  s.creases.push_back({4, 5, 0.5f});
  s.creases.push_back({5, 7, 1.7f});
  s.creases.push_back({6, 7, 3.0f});
  s.creases.push_back({4, 6, 3.0f});
  s.creases.push_back({0, 4, 3.0f});  // vertex 4 has three sharp edges: corner
  expect_matches_opensubdiv(s, 3);
}

TEST(OpenSubdivOracle, CubeWithSharpCorners) {
  // Vertex sharpness: integer (decays over two levels), fractional (blends), infinite,
  // and a sharp corner on a crease.
  PolygonSoup s = testing::cube_soup();
  s.corners.push_back({0, 2.0f});
  s.corners.push_back({3, 0.6f});
  s.corners.push_back({5, kInfiniteSharpness});
  s.corners.push_back({6, 1.4f});
  s.creases.push_back({6, 7, 1.0f});
  s.creases.push_back({6, 4, 2.5f});
  expect_matches_opensubdiv(s, 3);
}

TEST(OpenSubdivOracle, GridWithInteriorCorner) {
  PolygonSoup s = grid_soup(4, 4, Glue::None);
  s.corners.push_back({12, 1.5f});  // interior vertex (2,2)
  s.corners.push_back({1, 3.0f});   // border vertex
  expect_matches_opensubdiv(s, 3);
}

TEST(OpenSubdivOracle, OpenGridWithBorder) {
  PolygonSoup s = grid_soup(4, 3, Glue::None);
  for (size_t i = 0; i < s.positions.size(); ++i) {
    s.positions[i].z = std::sin(0.7 * i);
  }
  expect_matches_opensubdiv(s, 3);
}

TEST(OpenSubdivOracle, AnnulusTwoBorders) {
  expect_matches_opensubdiv(grid_soup(6, 2, Glue::Cylinder), 3);
}

TEST(OpenSubdivOracle, TorusWithCreaseLoop) {
  PolygonSoup s = grid_soup(6, 4, Glue::Torus);
  for (int i = 0; i < 6; ++i) {  // sharpness-1.5 loop around the tube at j = 0
    s.creases.push_back({i * 4, ((i + 1) % 6) * 4, 1.5f});
  }
  expect_matches_opensubdiv(s, 3);
}

TEST(OpenSubdivOracle, MixedTrianglesQuadsPentagons) {
  expect_matches_opensubdiv(testing::mixed_disk_soup(), 3);
}

// The face pass splits quads a block of 64 at a time and walks any other face on its own:
// 9 x 14 cells give 147 faces, so the blocks are not all full, and the triangles and
// pentagons fall inside blocks of quads at level 0 (every face after it is a quad).
TEST(OpenSubdivOracle, MixedTorusAcrossBlocksOfQuads) {
  const PolygonSoup s =
      testing::mixed_torus_from(testing::grid_soup(9, 14, testing::Glue::Torus, 0.05), 9, 14);
  ASSERT_GT(s.face_count(), 128);
  ASSERT_NE(s.face_count() % 64, 0);
  expect_matches_opensubdiv(s, 3);
}

TEST(OpenSubdivOracle, MixedWithCreases) {
  PolygonSoup s = testing::mixed_disk_soup();
  s.creases.push_back({0, 1, 2.0f});
  s.creases.push_back({1, 2, 0.3f});
  s.creases.push_back({2, 3, kInfiniteSharpness});
  expect_matches_opensubdiv(s, 3);
}

TEST(OpenSubdivOracle, TetrahedronAndPentagonalPrism) {
  PolygonSoup tet;
  tet.add_vertex({1, 1, 1});
  tet.add_vertex({-1, -1, 1});
  tet.add_vertex({-1, 1, -1});
  tet.add_vertex({1, -1, -1});
  tet.add_face({0, 1, 2});
  tet.add_face({0, 3, 1});
  tet.add_face({0, 2, 3});
  tet.add_face({1, 3, 2});
  expect_matches_opensubdiv(tet, 3);

  PolygonSoup prism;
  for (int k = 0; k < 2; ++k) {
    for (int i = 0; i < 5; ++i) {
      prism.add_vertex({std::cos(1.2566 * i), std::sin(1.2566 * i), double(k) * 1.3});
    }
  }
  prism.add_face({4, 3, 2, 1, 0});
  prism.add_face({5, 6, 7, 8, 9});
  for (int i = 0; i < 5; ++i) {
    prism.add_face({i, (i + 1) % 5, 5 + (i + 1) % 5, 5 + i});
  }
  expect_matches_opensubdiv(prism, 3);
}

}  // namespace
}  // namespace nomec::kernel
