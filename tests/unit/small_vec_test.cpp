// SmallVec: elements kept inline up to N, then on the heap; copies, moves and truncation
// keep every element. Its inline room is raw storage, so an element type whose default
// constructor sets a value (an `Id` is None until set) must read back exactly what was
// stored, never a default, on both sides of the spill.
#include <gtest/gtest.h>

#include <cstdint>
#include <utility>

#include "base/small_vec.h"
#include "ir/ids.h"

namespace nomec {
namespace {

using ir::NodeId;

TEST(SmallVec, IdsReadBackWhatWasStoredInlineAndOnTheHeap) {
  SmallVec<NodeId, 4> v;
  EXPECT_TRUE(v.empty());
  for (int32_t i = 0; i < 11; ++i) {
    v.push_back(NodeId(i * 3));
    ASSERT_EQ(v.size(), static_cast<uint32_t>(i + 1));
    for (int32_t k = 0; k <= i; ++k) EXPECT_EQ(v[k].index, k * 3) << "after " << i + 1 << " pushes";
  }
  v.truncate(2);
  EXPECT_EQ(v.size(), 2u);
  EXPECT_EQ(v.back().index, 3);
}

TEST(SmallVec, CopiesAndMovesKeepTheElements) {
  for (int32_t n : {0, 1, 4, 5, 9}) {
    SmallVec<NodeId, 4> a;
    for (int32_t i = 0; i < n; ++i) a.push_back(NodeId(100 + i));
    SmallVec<NodeId, 4> copy(a);
    EXPECT_TRUE(copy == a);
    SmallVec<NodeId, 4> moved(std::move(copy));
    EXPECT_TRUE(moved == a);
    EXPECT_TRUE(copy.empty());
    SmallVec<NodeId, 4> assigned;
    assigned.push_back(NodeId(7));
    assigned = a;
    EXPECT_TRUE(assigned == a);
    SmallVec<NodeId, 4> move_assigned;
    move_assigned = std::move(assigned);
    EXPECT_TRUE(move_assigned == a);
    int32_t expect = 100;
    for (NodeId id : move_assigned) EXPECT_EQ(id.index, expect++);
  }
}

TEST(SmallVec, InitializerListAndPushOfOwnElement) {
  SmallVec<NodeId, 2> v{NodeId(1), NodeId(2)};
  v.push_back(v[0]);  // grows while reading its own element
  ASSERT_EQ(v.size(), 3u);
  EXPECT_EQ(v[0].index, 1);
  EXPECT_EQ(v[1].index, 2);
  EXPECT_EQ(v[2].index, 1);
}

}  // namespace
}  // namespace nomec
