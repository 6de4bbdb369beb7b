// The large-array helpers: exact reservation keeps the contents, `resize_large`
// value-initialises, and huge-page advice is only a hint (small, empty or large buffers
// keep their data, whether or not the system honours it).
#include "kernel/large_arrays.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <numeric>
#include <vector>

#include "kernel/ids.h"

namespace nomec::kernel {
namespace {

TEST(LargeArrays, ReserveKeepsContentsAndNeverShrinks) {
  std::vector<int32_t> v{1, 2, 3};
  reserve_large(v, 100);
  EXPECT_GE(v.capacity(), 100u);
  EXPECT_EQ(v, (std::vector<int32_t>{1, 2, 3}));
  const int32_t* data = v.data();
  reserve_large(v, 10);  // already large enough: no reallocation
  EXPECT_EQ(v.data(), data);
}

TEST(LargeArrays, ResizeValueInitialisesAboveTheAdviceSize) {
  const size_t n = kHugePageAdviceBytes / sizeof(EdgeUse) + 12345;
  std::vector<EdgeUse> uses;
  resize_large(uses, n);
  ASSERT_EQ(uses.size(), n);
  EXPECT_EQ(uses.front(), EdgeUse::None());
  EXPECT_EQ(uses.back(), EdgeUse::None());
  std::vector<int64_t> values;
  resize_large(values, kHugePageAdviceBytes / sizeof(int64_t) * 3);
  std::iota(values.begin(), values.end(), int64_t{0});
  EXPECT_EQ(values[values.size() - 1], int64_t(values.size() - 1));
}

TEST(LargeArrays, AdviceLeavesDataAlone) {
  advise_huge_pages(nullptr, 0);
  advise_huge_pages(nullptr, kHugePageAdviceBytes * 2);
  int32_t small[4] = {4, 3, 2, 1};
  advise_huge_pages(small, sizeof(small));
  EXPECT_EQ(small[0] + small[3], 5);
  std::vector<double> big(kHugePageAdviceBytes / sizeof(double) + 7, 2.5);
  advise_huge_pages(big.data() + 3, (big.size() - 3) * sizeof(double));
  for (size_t i = 0; i < big.size(); i += 4096) EXPECT_EQ(big[i], 2.5);
  EXPECT_EQ(big.back(), 2.5);
}

}  // namespace
}  // namespace nomec::kernel
