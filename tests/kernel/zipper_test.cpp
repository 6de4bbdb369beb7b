// Automatic zippering tests: quads between matching chains, the minimum number of
// triangles for unequal counts, annuli between closed loops, the triangle penalty, and
// invalid input.
#include "kernel/zipper.h"

#include <cmath>
#include <gtest/gtest.h>

#include "kernel/merge.h"
#include "kernel/topology.h"

namespace nomec::kernel {
namespace {

// n points evenly spaced from (0, y, 0) to (length, y, 0).
ZipperChain segment(int n, double y, double length = 3) {
  ZipperChain c;
  for (int i = 0; i < n; ++i) c.points.push_back({length * i / (n - 1), y, 0});
  return c;
}

ZipperChain ring(int n, double radius, double z, double phase = 0) {
  ZipperChain c;
  c.is_closed = true;
  for (int i = 0; i < n; ++i) {
    double t = 2 * M_PI * i / n + phase;
    c.points.push_back({radius * std::cos(t), radius * std::sin(t), z});
  }
  return c;
}

TopologyReport topo(const PolygonSoup& s) {
  auto m = build_mesh(s);
  EXPECT_TRUE(m.has_value()) << (m ? "" : m.error().message);
  return m ? topology(*m) : TopologyReport{};
}

TEST(Zipper, ParallelSegmentsOfEqualLengthGiveQuads) {
  auto r = zipper(segment(5, 0), segment(5, 1));
  ASSERT_TRUE(r.has_value()) << r.error().message;
  EXPECT_EQ(r->quad_count, 4);
  EXPECT_EQ(r->triangle_count, 0);
  EXPECT_EQ(r->soup.face_count(), 4);
  // The first quad joins a0 a1 b1 b0, traversing A against its chain order.
  std::vector<int32_t> first(r->soup.face_vertices.begin(), r->soup.face_vertices.begin() + 4);
  EXPECT_EQ(first, (std::vector<int32_t>{1, 0, 5, 6}));
  TopologyReport t = topo(r->soup);
  EXPECT_EQ(t.euler_characteristic, 1);
  EXPECT_EQ(t.border_loop_count, 1);
  EXPECT_TRUE(t.is_orientable);
}

TEST(Zipper, UnequalCountsGiveTwoTriangles) {
  auto r = zipper(segment(4, 0), segment(6, 1));
  ASSERT_TRUE(r.has_value()) << r.error().message;
  EXPECT_EQ(r->triangle_count, 2);
  EXPECT_EQ(r->quad_count, 3);
  TopologyReport t = topo(r->soup);
  EXPECT_EQ(t.euler_characteristic, 1);
  EXPECT_TRUE(t.is_orientable);
}

TEST(Zipper, ClosedLoopsOfEqualSizeGiveAnAnnulus) {
  // B starts half way round and runs the other way: the DP finds the aligned pairing.
  ZipperChain b = ring(8, 1.5, 1);
  std::reverse(b.points.begin(), b.points.end());
  std::rotate(b.points.begin(), b.points.begin() + 3, b.points.end());
  auto r = zipper(ring(8, 1, 0), b);
  ASSERT_TRUE(r.has_value()) << r.error().message;
  EXPECT_EQ(r->quad_count, 8);
  EXPECT_EQ(r->triangle_count, 0);
  EXPECT_TRUE(r->is_b_reversed);
  TopologyReport t = topo(r->soup);
  EXPECT_EQ(t.components.size(), 1u);
  EXPECT_EQ(t.euler_characteristic, 0);
  EXPECT_EQ(t.border_loop_count, 2);
  EXPECT_TRUE(t.is_orientable);
  EXPECT_EQ(t.vertex_count, 16);
  EXPECT_EQ(t.edge_count, 24);
}

TEST(Zipper, ClosedLoopsOfUnequalSize) {
  auto r = zipper(ring(8, 1, 0), ring(6, 1, 1));
  ASSERT_TRUE(r.has_value()) << r.error().message;
  EXPECT_EQ(r->triangle_count, 2);
  EXPECT_EQ(r->quad_count, 6);
  TopologyReport t = topo(r->soup);
  EXPECT_EQ(t.euler_characteristic, 0);
  EXPECT_EQ(t.border_loop_count, 2);
}

TEST(Zipper, OrientedAgainstChainAMergesWithoutMobiusEdges) {
  // A strip of quads whose top border runs a0..a3 in the direction its faces traverse it;
  // zippering above it and merging gives an orientable disc.
  PolygonSoup base;
  for (int i = 0; i < 4; ++i) base.add_vertex({double(i), -1, 0});
  for (int i = 0; i < 4; ++i) base.add_vertex({double(i), 0, 0});
  for (int i = 0; i < 3; ++i) base.add_face({i, i + 1, 4 + i + 1, 4 + i});
  // Face (i, i+1, 5+i, 4+i) traverses its top edge from 5+i to 4+i: chain A runs 3 → 0.
  ZipperChain a;
  for (int i = 3; i >= 0; --i) a.points.push_back({double(i), 0, 0});
  ZipperChain b;
  for (int i = 3; i >= 0; --i) b.points.push_back({double(i), 1, 0});
  auto r = zipper(a, b);
  ASSERT_TRUE(r.has_value()) << r.error().message;
  auto m1 = build_mesh(base);
  auto m2 = build_mesh(r->soup);
  ASSERT_TRUE(m1 && m2);
  std::vector<const Mesh*> parts{&*m1, &*m2};
  auto merged = merge(parts);
  ASSERT_TRUE(merged.has_value()) << merged.error().message;
  EXPECT_EQ(merged->joined_edge_count, 3);
  TopologyReport t = topology(merged->mesh);
  EXPECT_EQ(t.components.size(), 1u);
  EXPECT_TRUE(t.is_orientable);
  EXPECT_FALSE(merged->mesh.has_mobius_edges());
  EXPECT_EQ(t.euler_characteristic, 1);
}

TEST(Zipper, PenaltyControlsTriangleCount) {
  // B's points bunch up near its start, so quads are badly skewed: without a triangle
  // penalty the DP uses triangles to keep the chains in step; with a large one it uses
  // the fewest (|B| − |A| = 1).
  ZipperChain a = segment(5, 0, 4);
  ZipperChain b;
  b.points = {{0, 1, 0}, {0.3, 1, 0}, {0.4, 1, 0}, {0.6, 1, 0}, {1.4, 1, 0}, {4, 1, 0}};
  ZipperOptions cheap;
  cheap.penalty = 0;
  ZipperOptions dear;
  dear.penalty = 100;
  auto r0 = zipper(a, b, cheap);
  auto r1 = zipper(a, b, dear);
  ASSERT_TRUE(r0.has_value() && r1.has_value());
  EXPECT_EQ(r1->triangle_count, 1);
  EXPECT_EQ(r0->triangle_count, 3);
  EXPECT_EQ(topo(r0->soup).euler_characteristic, 1);
  EXPECT_EQ(topo(r1->soup).euler_characteristic, 1);
}

TEST(Zipper, InvalidInputIsAnError) {
  auto empty = zipper(ZipperChain{}, segment(3, 1));
  ASSERT_FALSE(empty.has_value());
  EXPECT_EQ(empty.error().kind, KernelError::Kind::InvalidArgument);
  EXPECT_FALSE(zipper(segment(3, 0), ZipperChain{}).has_value());
  EXPECT_FALSE(zipper(ring(4, 1, 0), segment(3, 1)).has_value());
  ZipperOptions negative;
  negative.penalty = -1;
  EXPECT_FALSE(zipper(segment(3, 0), segment(3, 1), negative).has_value());
}

}  // namespace
}  // namespace nomec::kernel
