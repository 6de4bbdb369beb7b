// The page policy of nomec's allocator (tools/allocator.h), read from the kernel's own
// account of this process's mappings: large allocations are on 4 KiB pages (jemalloc's
// `thp:never`, so that the pages a check gives back leave the process) until
// `use_huge_pages_from_now`, after which new mappings may be backed by huge pages.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "tools/allocator.h"

NOMEC_JEMALLOC_CONFIG();

namespace {

// The `VmFlags` line of the mapping that holds `p` in /proc/self/smaps ("" if none).
std::string vm_flags_of(const void* p) {
  const auto at = reinterpret_cast<uintptr_t>(p);
  std::ifstream smaps("/proc/self/smaps");
  std::string line;
  bool inside = false;
  while (std::getline(smaps, line)) {
    uintptr_t lo = 0, hi = 0;
    char dash = 0;
    std::istringstream head(line);
    if (head >> std::hex >> lo >> dash >> hi && dash == '-' && line.find(':') > line.find(' ')) {
      inside = lo <= at && at < hi;
      continue;
    }
    if (inside && line.rfind("VmFlags:", 0) == 0) return line;
  }
  return "";
}

bool has_flag(const std::string& flags, const char* flag) {
  std::istringstream in(flags.substr(std::strlen("VmFlags:")));
  std::string f;
  while (in >> f) {
    if (f == flag) return true;
  }
  return false;
}

// 64 MiB, more than the allocator keeps mapped ahead, written so it is resident.
std::unique_ptr<char[]> touched_block() {
  constexpr size_t kBytes = size_t{64} << 20;
  auto block = std::make_unique<char[]>(kBytes);
  for (size_t i = 0; i < kBytes; i += 4096) block[i] = 1;
  return block;
}

TEST(Allocator, LargeAllocationsUseSmallPagesUntilHugePagesAreAsked) {
  if (nomec::allocator_name() != "jemalloc") {
    EXPECT_FALSE(nomec::use_huge_pages_from_now());  // the C library's malloc: nothing to ask
    GTEST_SKIP() << "built without jemalloc";
  }
  auto before = touched_block();
  const std::string flags_before = vm_flags_of(before.get());
  ASSERT_FALSE(flags_before.empty());
  EXPECT_TRUE(has_flag(flags_before, "nh")) << flags_before;  // no huge pages (`thp:never`)
  EXPECT_FALSE(has_flag(flags_before, "hg")) << flags_before;

  ASSERT_TRUE(nomec::use_huge_pages_from_now());
  EXPECT_TRUE(nomec::use_huge_pages_from_now());  // asking twice is harmless
  auto after = touched_block();
  const std::string flags_after = vm_flags_of(after.get());
  ASSERT_FALSE(flags_after.empty());
  EXPECT_TRUE(has_flag(flags_after, "hg")) << flags_after;  // huge pages advised
  // The block allocated before keeps its pages.
  EXPECT_FALSE(has_flag(vm_flags_of(before.get()), "hg"));
}

}  // namespace
