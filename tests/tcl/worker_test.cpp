// SLIDE's Tcl in its worker process (frontend/tcl/interp.h): what no limit inside Tcl can
// stop — a C-stack overflow or panic in Tcl's own commands, one command Tcl cannot
// interrupt, a scene that redefines what nomec calls, traces that run the scene's code while
// nomec reads or sets variables, pipes, memory — ends the worker, never nomec, within the
// budget, as one problem; the operations after it run nothing; a new interpreter works.
#include <gtest/gtest.h>

#include <chrono>
#include <map>
#include <string>
#include <thread>

#include "frontend/tcl/interp.h"

namespace nomec::tcl {
namespace {

using Clock = std::chrono::steady_clock;

Interp make(int milliseconds = 10000, std::map<std::string, std::string> files = {}) {
  Limits limits;
  limits.milliseconds = milliseconds;
  return Interp("scene/", [files](const std::string& p) -> std::optional<std::string> {
    auto it = files.find(p);
    if (it == files.end()) return std::nullopt;
    return it->second;
  }, limits);
}

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// A script that overflows the C stack inside Tcl's own code: nested brackets that Tcl's
// parser and compiler recurse into, deeper than any stack.
std::string deep_nesting() {
  std::string s = "set x ";
  for (int i = 0; i < 1'000'000; ++i) s += "[";
  return s;
}

TEST(TclWorker, ACrashInTclIsAProblemOfTheScene) {
  Interp in = make();
  ASSERT_TRUE(in.run("set kept 1").ok);
  Outcome o = in.run(deep_nesting());
  ASSERT_FALSE(o.ok);
  ASSERT_EQ(o.problems.size(), 1u);
  EXPECT_EQ(o.problems[0].kind, ProblemKind::Crashed) << o.problems[0].message;
  EXPECT_NE(o.problems[0].message.find("SIGSEGV"), std::string::npos) << o.problems[0].message;
  EXPECT_TRUE(in.stopped());
  // Nothing runs after it, and saying so is not a second crash.
  Outcome after = in.run("set y 2");
  ASSERT_FALSE(after.ok);
  EXPECT_EQ(after.problems[0].kind, ProblemKind::Stopped);
  EXPECT_FALSE(in.get("kept").has_value());
  EXPECT_TRUE(in.take_notes().empty());  // the crash was reported by `run`, once
  // A new interpreter is a new worker.
  Interp fresh = make();
  EXPECT_TRUE(fresh.run("set z 3").ok);
  EXPECT_EQ(fresh.get("z"), "3");
}

TEST(TclWorker, OneCommandTclCannotInterruptIsStoppedAtTheBudget) {
  // Huge bignum arithmetic and a `string match` that backtracks over a long text each run
  // inside one command, where Tcl's own limits are never checked.
  for (const char* script : {"set x [expr {10**100000000 + 1}]; string length x",
                             "string match [string repeat *a 40]b [string repeat a 3000000]"}) {
    Interp in = make(500);
    const auto start = Clock::now();
    Outcome o = in.run(script);
    EXPECT_LT(seconds_since(start), 5.0) << script;
    ASSERT_FALSE(o.ok) << script;
    EXPECT_EQ(o.problems[0].kind, ProblemKind::Limit) << script << ": " << o.problems[0].message;
    EXPECT_TRUE(in.stopped());
  }
}

TEST(TclWorker, TheBudgetIsForAllOfTheScenesTcl) {
  // Eight blocks that each loop forever take the one budget in all, not eight times it.
  Interp in = make(400);
  const auto start = Clock::now();
  int limited = 0, not_run = 0;
  for (int i = 0; i < 8; ++i) {
    Outcome o = in.run("while 1 {}");
    ASSERT_FALSE(o.ok);
    if (o.problems[0].kind == ProblemKind::Limit) ++limited;
    if (o.problems[0].kind == ProblemKind::Stopped) ++not_run;
  }
  EXPECT_LT(seconds_since(start), 3.0);
  EXPECT_GE(limited, 1);
  EXPECT_EQ(limited + not_run, 8);
}

TEST(TclWorker, BudgetsCanBeShared) {
  auto budget = std::make_shared<Budget>(300);
  Interp a = make(), b = make();
  a.use_budget(budget);
  b.use_budget(budget);
  EXPECT_FALSE(a.run("while 1 {}").ok);
  Outcome o = b.run("set x 1");  // `a` spent it
  ASSERT_FALSE(o.ok);
  EXPECT_EQ(o.problems[0].kind, ProblemKind::Limit);
  EXPECT_NE(o.problems[0].message.find("whole 0.3 s"), std::string::npos) << o.problems[0].message;
}

TEST(TclWorker, ARedefinedInfoDoesNotDisarmTheLimits) {
  // nomec reads Tcl's command count to set the command limit; a scene's own `info` is not
  // what it calls.
  Interp in = make(2000);
  ASSERT_TRUE(in.run("rename info hidden_info; proc info args { while 1 {} }").ok);
  Outcome o = in.run("set i 0; while 1 {incr i}");
  ASSERT_FALSE(o.ok);
  EXPECT_EQ(o.problems[0].kind, ProblemKind::Limit);
  EXPECT_NE(o.problems[0].message.find("command count"), std::string::npos) << o.problems[0].message;
  EXPECT_TRUE(in.run("set after 1").ok);
}

TEST(TclWorker, TracesRunWithinTheLimits) {
  // A read trace on ::errorInfo runs when nomec reads the error; a write trace on a slider's
  // variable runs when nomec moves the slider; a read trace when nomec reads a value.
  Interp in = make(1000);
  ASSERT_TRUE(in.run("trace add variable ::errorInfo {read write} {apply {args {while 1 {}}}}\n"
                     "set par_x 1; trace add variable par_x write {apply {args {while 1 {}}}}\n"
                     "set par_y 1; trace add variable par_y read {apply {args {while 1 {}}}}")
                  .ok);
  const auto start = Clock::now();
  EXPECT_FALSE(in.run("error boom").ok);
  in.set("par_x", "2");
  (void)in.get("par_y");
  EXPECT_LT(seconds_since(start), 5.0);
}

TEST(TclWorker, PipesAreRefused) {
  Interp in = make();
  for (const char* script : {"chan pipe", "lassign [chan pipe] r w; read $r",
                             "for {set i 0} {$i < 10000} {incr i} {lappend p [chan pipe]}"}) {
    Outcome o = in.run(script);
    ASSERT_FALSE(o.ok) << script;
    EXPECT_EQ(o.problems[0].kind, ProblemKind::Refused) << script << ": " << o.problems[0].message;
    EXPECT_NE(o.problems[0].message.find("chan pipe"), std::string::npos) << o.problems[0].message;
  }
  EXPECT_TRUE(in.run("set ok 1").ok);
}

TEST(TclWorker, MemoryIsBoundedInTheWorker) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "under AddressSanitizer the worker has no address-space limit and each large allocation is a "
                  "fresh mapping: the scene runs into its time budget first (the release build holds the bound)";
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
  GTEST_SKIP() << "under AddressSanitizer the worker has no address-space limit and each large allocation is a "
                  "fresh mapping: the scene runs into its time budget first (the release build holds the bound)";
#endif
#endif
  // Inflating a small deflated text again and again: each value is within the bounds, their
  // sum is not. The guard's count of the heap (or the address-space limit) stops it.
  Interp in = make(20000);
  Outcome o = in.run(
      "set d [zlib deflate [string repeat x 4000000]]\n"
      "for {set i 0} {$i < 2000} {incr i} {lappend keep [zlib inflate $d]}");
  ASSERT_FALSE(o.ok);
  EXPECT_TRUE(o.problems[0].kind == ProblemKind::Memory || o.problems[0].kind == ProblemKind::Crashed)
      << o.problems[0].message;
}

TEST(TclWorker, FilesAndPresetsAreAskedOfNomec) {
  std::vector<std::string> asked;
  Limits limits;
  Interp in("dir/", [&asked](const std::string& p) -> std::optional<std::string> {
    asked.push_back(p);
    if (p == "dir/lib.tcl") return std::string("set from_lib 7");
    return std::nullopt;
  }, limits, [](const std::string& var, double, double) -> std::optional<double> {
    if (var == "par_r") return 1.5;
    return std::nullopt;
  });
  Outcome o = in.run("source lib.tcl\nset par_r 0.5\nscale .r -from 0 -to 2 -resolution 0.1 -variable par_r\n"
                     "set have [slide import m mesh.stl]");
  ASSERT_TRUE(o.ok) << o.result;
  EXPECT_EQ(in.get("from_lib"), "7");
  EXPECT_EQ(in.get("par_r"), "1.5");  // the `-D` value nomec gave
  EXPECT_EQ(in.get("have"), "0");
  EXPECT_EQ(asked, (std::vector<std::string>{"dir/lib.tcl", "dir/mesh.stl"}));
  ASSERT_EQ(in.sliders().size(), 1u);
  EXPECT_EQ(in.sliders()[0].value, 1.5);
}

TEST(TclWorker, InterpretersOnManyThreadsAreIndependent) {
  std::vector<std::thread> threads;
  std::vector<int> ok(6, 0);
  for (int t = 0; t < 6; ++t) {
    threads.emplace_back([t, &ok] {
      Interp in = make();
      for (int i = 0; i < 20; ++i) {
        Outcome o = in.value("expr {" + std::to_string(t) + " * 100 + " + std::to_string(i) + "}");
        if (o.ok && o.number == t * 100 + i) ++ok[t];
      }
    });
  }
  for (std::thread& t : threads) t.join();
  for (int n : ok) EXPECT_EQ(n, 20);
}

}  // namespace
}  // namespace nomec::tcl
