// Reproducers for front-end crashes and blow-ups found by the robustness hunt and the fuzzer.
// Each asserts today's wrong behaviour (the process dies) with a FIXME, so the test fails
// once the bug is fixed and must then be flipped into a plain "checks and returns" test.
//
// Limits are set inside the death-test child so the outcome does not depend on the
// caller's `ulimit`: an 8 MiB stack (the Linux default) and, for the memory blow-up, a
// 512 MiB address space.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <cstdio>
#include <cstdlib>
#include <new>
#include <string>

#include "frontend/check/check.h"

namespace {

void limit(int resource, rlim_t bytes) {
  struct rlimit rl {};
  getrlimit(resource, &rl);
  rl.rlim_cur = bytes;
  if (rl.rlim_max != RLIM_INFINITY && rl.rlim_max < bytes) rl.rlim_cur = rl.rlim_max;
  setrlimit(resource, &rl);
}

int check(const std::string& text) {
  nomec::SourceManager sources;
  nomec::DiagnosticEngine diags;
  nomec::check_source(sources, "repro.nome", text, nomec::CheckOptions{}, diags);
  return diags.error_count();
}

std::string repeat(std::string_view s, int n) {
  std::string out;
  out.reserve(s.size() * n);
  for (int i = 0; i < n; ++i) out += s;
  return out;
}

// Sizes that work today, so the reproducers below are about depth, not about the inputs.
TEST(Reproducers, ModerateDepthWorks) {
  EXPECT_EQ(check("point p (" + repeat("1+", 2000) + "1 0 0) endpoint\n"), 0);
  EXPECT_EQ(check("point p (" + repeat("-", 2000) + "1 0 0) endpoint\n"), 0);
  EXPECT_EQ(check("point p (" + repeat("(", 2000) + "1" + repeat(")", 2000) + " 0 0) endpoint\n"), 0);
  EXPECT_EQ(check(repeat("(*", 50) + repeat("*)", 50) + "\npoint p (0 0 0) endpoint\n"), 0);
}

// FIXME(issue 2): stack overflow. A flat sum of 20000 terms in a list (40 KB of
// `1+1+…`) builds a left-deep expression that Checker::to_ir_rec (frontend/check/check.cpp)
// walks recursively; at ~5800 frames the 8 MiB stack is exhausted (SIGSEGV).
TEST(ReproducersDeathTest, LongSumOverflowsTheStack) {
  std::string text = "point p (" + repeat("1+", 20000) + "1 0 0) endpoint\n";
  EXPECT_DEATH(
      {
        limit(RLIMIT_STACK, 8u << 20);
        check(text);
      },
      "");
}

// FIXME(issue 2): stack overflow. 20000 unary minus signs `(----…1 0 0)` recurse in
// Checker::to_ir_rec the same way.
TEST(ReproducersDeathTest, UnaryChainOverflowsTheStack) {
  std::string text = "point p (" + repeat("-", 20000) + "1 0 0) endpoint\n";
  EXPECT_DEATH(
      {
        limit(RLIMIT_STACK, 8u << 20);
        check(text);
      },
      "");
}

// FIXME(issue 2): stack overflow. 20000 nested parentheses `((((1))))` (parser and
// to_ir_rec recursion).
TEST(ReproducersDeathTest, NestedParenthesesOverflowTheStack) {
  std::string text = "point p (" + repeat("(", 20000) + "1" + repeat(")", 20000) + " 0 0) endpoint\n";
  EXPECT_DEATH(
      {
        limit(RLIMIT_STACK, 8u << 20);
        check(text);
      },
      "");
}

// FIXME(issue 2): quadratic time and memory in the lexer's nested BLOCK_COMMENT rule
// (grammar/Nome.g4). `(*` x N then `*)` x N takes, with nomec --check: N=300 1.2 s / 170 MB,
// N=1000 16 s / 1.7 GB (a 4 KB file); N=100000 ran out of memory after 700 s at 24 GB.
// Under a 512 MiB address-space limit N=1000 makes check_source throw std::bad_alloc.
TEST(ReproducersDeathTest, NestedCommentsExhaustMemory) {
  std::string text = repeat("(*", 1000) + repeat("*)", 1000) + "\npoint p (0 0 0) endpoint\n";
  EXPECT_EXIT(
      {
        limit(RLIMIT_AS, 512u << 20);
        try {
          check(text);
        } catch (const std::bad_alloc&) {
          std::fprintf(stderr, "check_source threw std::bad_alloc\n");
          std::_Exit(3);
        }
        std::_Exit(0);
      },
      ::testing::ExitedWithCode(3), "bad_alloc");
}

}  // namespace
