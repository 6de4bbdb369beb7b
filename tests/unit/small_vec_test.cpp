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

// The heap block's address shares the inline room: a vector is its size, its capacity and
// the larger of the room and a pointer (a large document has tens of thousands of them).
TEST(SmallVec, HeapPointerSharesTheInlineRoom) {
  static_assert(sizeof(SmallVec<NodeId, 4>) == 8 + 16);
  static_assert(sizeof(SmallVec<NodeId, 1>) == 8 + 8);
  static_assert(sizeof(SmallVec<double, 16>) == 8 + 128);
  // A vector emptied by a move, or spilled and then assigned from an inline one, keeps
  // working in both states.
  SmallVec<NodeId, 2> spilled;
  for (int32_t i = 0; i < 5; ++i) spilled.push_back(NodeId(i));
  SmallVec<NodeId, 2> taker(std::move(spilled));
  ASSERT_EQ(taker.size(), 5u);
  spilled.push_back(NodeId(40));
  spilled.push_back(NodeId(41));
  spilled.push_back(NodeId(42));  // spills again after the move took its block
  ASSERT_EQ(spilled.size(), 3u);
  EXPECT_EQ(spilled[2].index, 42);
  SmallVec<NodeId, 2> small{NodeId(9)};
  taker = small;  // a heap vector assigned an inline one's elements
  ASSERT_EQ(taker.size(), 1u);
  EXPECT_EQ(taker[0].index, 9);
  taker = std::move(spilled);  // and then given a heap block
  ASSERT_EQ(taker.size(), 3u);
  EXPECT_EQ(taker[0].index, 40);
  EXPECT_EQ(taker[2].index, 42);
}

}  // namespace
}  // namespace nomec
