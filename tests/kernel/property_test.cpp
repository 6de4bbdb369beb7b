// Deterministic property test: random manifold meshes (disks, annuli, Möbius bands,
// tori, Klein bottles; with random triangulation, fan splits and reversed faces) are cut
// into pieces with duplicated vertices, merged back, subdivided and offset. Invariants:
// the merge restores the exact counts and classification, Catmull-Clark keeps χ,
// orientability and borders, and the offset is a closed orientable 2-manifold without
// Möbius edges with χ = 2·χ(input).
#include <gtest/gtest.h>

#include <cstdint>

#include "kernel/merge.h"
#include "kernel/offset.h"
#include "kernel/subdivide.h"
#include "kernel/topology.h"
#include "tests/kernel/shapes.h"

namespace nomec::kernel {
namespace {

using testing::Glue;

// Small portable generator (identical on every platform, unlike std distributions).
struct Rng {
  uint64_t state;
  uint32_t next() {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return uint32_t(state >> 33);
  }
  int below(int n) { return int(next() % uint32_t(n)); }
};

struct Case {
  PolygonSoup soup;
  int32_t euler = 0;
  bool is_orientable = true;
  int32_t borders = 0;
  /// Grid row (i) of each emitted face; pieces are cut between rows.
  std::vector<int32_t> face_rows;
  int32_t rows = 0;
};

Case random_case(Rng& rng) {
  const Glue glues[] = {Glue::None, Glue::Cylinder, Glue::Mobius, Glue::Torus, Glue::Klein};
  const Glue glue = glues[rng.below(5)];
  const bool wrap_j = glue == Glue::Torus || glue == Glue::Klein;
  const int n = 3 + rng.below(5);
  const int m = wrap_j ? 3 + rng.below(3) : 1 + rng.below(4);
  PolygonSoup grid = testing::grid_soup(n, m, glue, 0.01);
  Case c;
  switch (glue) {
    case Glue::None:
      c = {{}, 1, true, 1, {}, n};
      break;
    case Glue::Cylinder:
      c = {{}, 0, true, 2, {}, n};
      break;
    case Glue::Mobius:
      c = {{}, 0, false, 1, {}, n};
      break;
    case Glue::Torus:
      c = {{}, 0, true, 0, {}, n};
      break;
    case Glue::Klein:
      c = {{}, 0, false, 0, {}, n};
      break;
  }
  // Re-emit faces: quads stay, split into two triangles, or fan-split around a new
  // centre vertex; each result may be reversed.
  c.soup.positions = grid.positions;
  int32_t row = 0;
  auto emit = [&](std::vector<int32_t> f) {
    if (rng.below(4) == 0) {
      std::reverse(f.begin(), f.end());
    }
    c.soup.add_face(f);
    c.face_rows.push_back(row);
  };
  for (int32_t f = 0; f < grid.face_count(); ++f) {
    row = f / m;
    const int32_t* q = grid.face_vertices.data() + 4 * f;
    switch (rng.below(4)) {
      case 0:
        emit({q[0], q[1], q[2]});
        emit({q[0], q[2], q[3]});
        break;
      case 1: {
        glm::dvec3 centre(0.0);
        for (int k = 0; k < 4; ++k) {
          centre += grid.positions[q[k]] / 4.0;
        }
        const int32_t mid = c.soup.add_vertex(centre + glm::dvec3(0.0, 0.0, 0.003));
        for (int k = 0; k < 4; ++k) {
          emit({q[k], q[(k + 1) % 4], mid});
        }
        break;
      }
      default:
        emit({q[0], q[1], q[2], q[3]});
    }
  }
  return c;
}

// Splits the case's soup into pieces with their own vertex copies: either every face
// alone, or runs of whole grid rows (strips or annuli, hence manifold).
PolygonSoup explode(const Case& c, Rng& rng) {
  const PolygonSoup& soup = c.soup;
  const bool is_every_face = rng.below(3) == 0;
  const int32_t F = soup.face_count();
  const int32_t pieces = 1 + rng.below(4);
  PolygonSoup out;
  std::vector<int32_t> copy(soup.vertex_count(), -1);
  std::vector<size_t> offsets(F + 1, 0);
  for (int32_t f = 0; f < F; ++f) {
    offsets[f + 1] = offsets[f] + soup.face_sizes[f];
  }
  int32_t piece = -1;
  for (int32_t f = 0; f < F; ++f) {
    const int32_t this_piece = is_every_face ? f : c.face_rows[f] * pieces / c.rows;
    if (this_piece != piece) {
      piece = this_piece;
      std::fill(copy.begin(), copy.end(), -1);
    }
    std::vector<int32_t> face;
    for (size_t i = offsets[f]; i < offsets[f + 1]; ++i) {
      const int32_t v = soup.face_vertices[i];
      if (copy[v] < 0) {
        copy[v] = out.add_vertex(soup.positions[v]);
      }
      face.push_back(copy[v]);
    }
    out.add_face(face);
  }
  return out;
}

TEST(Property, MergeSubdivideOffsetInvariants) {
  Rng rng{20261122};
  int mobius_inputs = 0;
  for (int trial = 0; trial < 200; ++trial) {
    SCOPED_TRACE(::testing::Message() << "trial " << trial);
    Case c = random_case(rng);
    auto whole = build_mesh(c.soup);
    ASSERT_TRUE(whole.has_value()) << whole.error().message;
    auto pieces = build_mesh(explode(c, rng));
    ASSERT_TRUE(pieces.has_value()) << pieces.error().message;

    auto merged = merge(*pieces, {.tolerance = 1e-7});
    ASSERT_TRUE(merged.has_value()) << merged.error().message;
    const Mesh& mesh = merged->mesh;
    TopologyReport r = topology(mesh);
    ASSERT_EQ(r.components.size(), 1u);
    EXPECT_EQ(r.vertex_count, whole->vertex_count());
    EXPECT_EQ(r.edge_count, whole->edge_count());
    EXPECT_EQ(r.face_count, whole->face_count());
    EXPECT_EQ(r.euler_characteristic, c.euler);
    EXPECT_EQ(r.is_orientable, c.is_orientable);
    EXPECT_EQ(r.border_loop_count, c.borders);
    mobius_inputs += mesh.has_mobius_edges() ? 1 : 0;

    auto levels = subdivide(mesh, {.levels = 1 + trial % 2});
    ASSERT_TRUE(levels.has_value());
    const Mesh& smooth = levels->back().mesh;
    TopologyReport rs = topology(smooth);
    EXPECT_EQ(rs.euler_characteristic, c.euler);
    EXPECT_EQ(rs.is_orientable, c.is_orientable);
    EXPECT_EQ(rs.border_loop_count, c.borders);

    auto slab = offset(smooth, {.distance = 0.01});
    ASSERT_TRUE(slab.has_value()) << slab.error().message;
    TopologyReport ro = topology(slab->mesh);
    EXPECT_TRUE(ro.is_closed);
    EXPECT_TRUE(ro.is_orientable);
    EXPECT_FALSE(slab->mesh.has_mobius_edges());
    EXPECT_EQ(ro.euler_characteristic, 2 * c.euler);
    const bool is_two_shells = c.is_orientable && c.borders == 0;
    EXPECT_EQ(ro.components.size(), is_two_shells ? 2u : 1u);

    // §5.4: the slab subdivides as an ordinary closed surface.
    SubdivisionLevel rounded = subdivide_once(slab->mesh);
    TopologyReport rr = topology(rounded.mesh);
    EXPECT_TRUE(rr.is_closed && rr.is_orientable);
    EXPECT_EQ(rr.euler_characteristic, 2 * c.euler);
  }
  // The generator must actually exercise Möbius edges.
  EXPECT_GT(mobius_inputs, 100);
}

}  // namespace
}  // namespace nomec::kernel
