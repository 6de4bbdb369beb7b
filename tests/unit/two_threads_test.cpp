// run_two_parts (base/two_threads.h): both parts run, the second on another thread that is
// kept between calls; exceptions from either part reach the caller; callers at once, a
// part that itself splits, and a forked process each still get both parts run.
#include "base/two_threads.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <numeric>
#include <set>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

namespace nomec {
namespace {

TEST(TwoThreads, BothPartsRunAndTheirWritesAreSeenAfterwards) {
  std::vector<int> data(1 << 16);
  for (int round = 0; round < 200; ++round) {
    const size_t mid = data.size() / 2;
    auto fill = [&](int k) {
      const size_t b = k == 0 ? 0 : mid;
      const size_t e = k == 0 ? mid : data.size();
      for (size_t i = b; i < e; ++i) data[i] = static_cast<int>(i) + round;
    };
    if (round % 2 == 0) {
      run_two_parts(fill);  // a named part, passed by reference
    } else {
      run_two_parts(std::move(fill));
    }
    for (size_t i = 0; i < data.size(); ++i) ASSERT_EQ(data[i], static_cast<int>(i) + round) << i;
  }
}

// The kernel's thread id (a new thread gets a new one; `std::thread::id` may be reused).
pid_t thread_id() { return gettid(); }

TEST(TwoThreads, TheSecondPartRunsOnOneKeptThread) {
  const pid_t caller = thread_id();
  std::set<pid_t> seconds;
  for (int round = 0; round < 100; ++round) {
    pid_t first = 0, second = 0;
    run_two_parts([&](int k) { (k == 0 ? first : second) = thread_id(); });
    EXPECT_EQ(first, caller);
    EXPECT_NE(second, caller);
    seconds.insert(second);
  }
  EXPECT_EQ(seconds.size(), 1u) << "a thread was started per call";
}

TEST(TwoThreads, ExceptionsFromEitherPartReachTheCaller) {
  std::atomic<int> ran{0};
  EXPECT_THROW(run_two_parts([&](int k) {
                 ++ran;
                 if (k == 1) throw std::runtime_error("second");
               }),
               std::runtime_error);
  EXPECT_EQ(ran.load(), 2);
  ran = 0;
  try {
    run_two_parts([&](int k) {
      ++ran;
      throw std::runtime_error(k == 0 ? "first" : "second");
    });
    ADD_FAILURE() << "nothing thrown";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "first");  // the calling thread's
  }
  EXPECT_EQ(ran.load(), 2);
  // The helper is free again.
  int sum = 0;
  run_two_parts([&](int k) {
    if (k == 1) sum = 42;
  });
  EXPECT_EQ(sum, 42);
}

TEST(TwoThreads, CallersAtOnceAndNestedCallsRunEveryPart) {
  constexpr int kRounds = 300;
  std::atomic<long> total{0};
  auto caller = [&] {
    for (int r = 0; r < kRounds; ++r) {
      run_two_parts([&](int k) {
        total += k + 1;
        if (k == 0 && r % 10 == 0) {
          run_two_parts([&](int j) { total += 10 * (j + 1); });  // the helper is held: a thread of its own
        }
      });
    }
  };
  std::thread a(caller), b(caller);
  caller();
  a.join();
  b.join();
  EXPECT_EQ(total.load(), 3L * (kRounds * 3 + (kRounds / 10) * 30));
}

TEST(TwoThreads, AForkedProcessRunsBothParts) {
  int warm = 0;
  run_two_parts([&](int k) { warm += k; });  // the helper exists before the fork
  ASSERT_EQ(warm, 1);
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    std::atomic<int> parts{0};
    for (int r = 0; r < 20; ++r) run_two_parts([&](int) { ++parts; });
    _exit(parts.load() == 40 ? 0 : 1);
  }
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
}

}  // namespace
}  // namespace nomec
