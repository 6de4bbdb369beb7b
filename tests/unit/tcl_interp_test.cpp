// SLIDE's Tcl (frontend/tcl): Tk stubs and sliders, the `slide` command, `source` next to
// the scene with nomec's own helper files as fallback, the refused commands, read traces,
// and the command-count and time limits — each test run twice: on the engine in this
// process (`Engine`) and through nomec's handle on a Tcl worker process (`Interp`), which
// must carry everything the engine records across the process boundary.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>

#include <type_traits>

#include "frontend/tcl/engine.h"
#include "frontend/tcl/interp.h"

namespace nomec::tcl {
namespace {

template <typename T>
class TclInterp : public ::testing::Test {};
using Implementations = ::testing::Types<Engine, Interp>;
TYPED_TEST_SUITE(TclInterp, Implementations);

template <typename T>
T make(std::map<std::string, std::string> files = {}, Limits limits = {}) {
  return T("scene/", [files](const std::string& p) -> std::optional<std::string> {
    auto it = files.find(p);
    if (it == files.end()) return std::nullopt;
    return it->second;
  }, limits);
}

TYPED_TEST(TclInterp, ScaleBoundToAVariableIsASlider) {
  TypeParam in = make<TypeParam>();
  Outcome o = in.run("set par_r 0.5\nframe .w\nscale .w.r -from 0 -to 2 -resolution 0.1 -var par_r\nscale .w.n\n");
  ASSERT_TRUE(o.ok) << o.result;
  ASSERT_EQ(in.sliders().size(), 1u);  // the scale without a variable is no slider
  const Slider& s = in.sliders()[0];
  EXPECT_EQ(s.variable, "par_r");
  EXPECT_DOUBLE_EQ(s.value, 0.5);
  EXPECT_DOUBLE_EQ(s.from, 0);
  EXPECT_DOUBLE_EQ(s.to, 2);
  EXPECT_DOUBLE_EQ(s.resolution, 0.1);
}

// What a `tclupdate` block sets (an existing global, a new one, an array element) and which
// watched variables it reads are recorded; untouched globals are not.
TYPED_TEST(TclInterp, TracksWhatAScriptWritesAndReads) {
  TypeParam in = make<TypeParam>();
  ASSERT_TRUE(in.run("set par_a 2; set keep 1; set r 0; array set arr {x 1}").ok);
  in.watch("par_a");
  Outcome o = in.run_tracking_writes("set r [expr {$par_a * 2}]; set fresh $keep; set arr(x) 5");
  ASSERT_TRUE(o.ok) << (o.problems.empty() ? "" : o.problems[0].message);
  std::sort(o.writes.begin(), o.writes.end());
  EXPECT_EQ(o.writes, (std::vector<std::string>{"arr", "fresh", "r"}));
  EXPECT_EQ(o.reads, std::vector<std::string>{"par_a"});
  // Afterwards writes are no longer traced.
  Outcome later = in.run("set r 1");
  EXPECT_TRUE(later.writes.empty());
  EXPECT_EQ(in.get("r").value_or(""), "1");
}

TYPED_TEST(TclInterp, ScaleRoundsAndClampsLikeTk) {
  TypeParam in = make<TypeParam>();
  ASSERT_TRUE(in.run("set a 0.707\nscale .a -from 0.5 -to 2 -resolution 0.1 -variable a\n"
                     "set b 0\nscale .b -from 0.1 -to 1.0 -resolution 0.01 -variable b\n"
                     "scale .c -from 3 -to 9 -variable c\n").ok);
  EXPECT_EQ(in.get("a"), "0.7");
  EXPECT_EQ(in.get("b"), "0.10");
  EXPECT_EQ(in.get("c"), "3");  // a missing variable is made with the scale's start
  EXPECT_TRUE(in.sliders()[0].rounded);
}

TYPED_TEST(TclInterp, TkStubsDoNothingAndReturnPaths) {
  TypeParam in = make<TypeParam>();
  Outcome o = in.run("toplevel .slfWindow.ui\npack [label .x -text hi] -side top\nwm geometry .x +1+1\n"
                     "bind .x <1> {puts hi}\ngrid .x\ncheckbutton .c -variable writeRib\nradiobutton .r -variable rv\n"
                     "entry .e -textvariable ev\n.x conf -bg red\nset w [frame .f]\nwinfo exists .f");
  ASSERT_TRUE(o.ok) << o.result;
  EXPECT_EQ(o.result, "0");
  EXPECT_EQ(in.get("w"), ".f");
  EXPECT_EQ(in.get("writeRib"), "0");
  EXPECT_EQ(in.get("rv"), "");
  EXPECT_EQ(in.get("ev"), "");
}

TYPED_TEST(TclInterp, SlideCreateIsRecorded) {
  TypeParam in = make<TypeParam>();
  ASSERT_TRUE(in.run("slide create point p1 {1 2 3}\nslide create face f {p1 p2 p3} -surface s\n").ok);
  ASSERT_EQ(in.slide_calls().size(), 2u);
  EXPECT_EQ(in.slide_calls()[0].words, (std::vector<std::string>{"create", "point", "p1", "1 2 3"}));
  EXPECT_FALSE(in.run("slide frobnicate x").ok);
}

TYPED_TEST(TclInterp, SourceReadsFilesNextToTheScene) {
  TypeParam in = make<TypeParam>({{"scene/lib.tcl", "proc Twice {x} { expr {2*$x} }"}});
  Outcome o = in.run("source lib.tcl\nTwice 4");
  ASSERT_TRUE(o.ok) << o.result;
  EXPECT_EQ(o.result, "8");
  Outcome missing = in.run("source nothere.tcl");
  ASSERT_FALSE(missing.ok);
  EXPECT_EQ(missing.problems[0].kind, ProblemKind::MissingSource);
  Outcome outside = in.run("source ../secret.tcl");
  ASSERT_FALSE(outside.ok);
  EXPECT_EQ(outside.problems[0].kind, ProblemKind::Refused);
}

TYPED_TEST(TclInterp, MissingHelperFilesUseNomecsOwn) {
  TypeParam in = make<TypeParam>();
  Outcome o = in.run("source SLIDEUI.tcl\nCreateScale par .w thick Thickness 0.25 0 1 0.05 4 horizontal\n"
                     "CreateGroupUI .slfWindow gRoot\nDegToRad 180");
  ASSERT_TRUE(o.ok) << o.result;
  EXPECT_NEAR(std::stod(o.result), 3.14159265358979, 1e-12);
  EXPECT_EQ(in.get("par_thick"), "0.25");
  EXPECT_EQ(in.get("gRoot_lod"), "3");
  EXPECT_EQ(in.get("gRoot_shading"), "0");
  ASSERT_EQ(in.sliders().size(), 1u);
  std::vector<Problem> notes = in.take_notes();
  ASSERT_EQ(notes.size(), 3u);  // SLIDEUI.tcl and the two files it sources
  EXPECT_EQ(notes[0].kind, ProblemKind::Fallback);
}

TYPED_TEST(TclInterp, SlideuiPackageObjectsAndSliders) {
  TypeParam in = make<TypeParam>();
  ASSERT_TRUE(in.run("package require slideui\nCreateSLIDESubdivisionObject oS\nCreateSLIDESubdivisionUI .u oS\n").ok);
  EXPECT_EQ(in.get("oS(subdivisions)"), "2");
  ASSERT_EQ(in.sliders().size(), 1u);
  EXPECT_EQ(in.sliders()[0].variable, "oS(subdivisions)");
}

TYPED_TEST(TclInterp, EveryWorldTouchingCommandIsRefused) {
  for (std::string_view cmd : refused_commands()) {
    TypeParam in = make<TypeParam>();
    std::string script = std::string(cmd) + (cmd == "open" ? " /tmp/x w" : " x");
    Outcome o = in.run(script);
    ASSERT_FALSE(o.ok) << cmd;
    ASSERT_EQ(o.problems.size(), 1u) << cmd;
    EXPECT_EQ(o.problems[0].kind, ProblemKind::Refused) << cmd;
    EXPECT_NE(o.problems[0].message.find("not available"), std::string::npos) << cmd;
  }
  // Nor can a script get them back.
  TypeParam in = make<TypeParam>();
  EXPECT_FALSE(in.run("interp expose {} exec").ok);
  EXPECT_FALSE(in.run("rename exec {}; exec ls").ok);
}

TYPED_TEST(TclInterp, ValuesRecordTheWatchedVariablesTheyRead) {
  TypeParam in = make<TypeParam>();
  ASSERT_TRUE(in.run("set a 2\nset b 3\nset c 4\nproc viaB {} { global b; return $b }").ok);
  in.watch("a");
  in.watch("b");
  Outcome o = in.value("expr {$a * [viaB] + $c}");
  ASSERT_TRUE(o.ok) << o.result;
  EXPECT_DOUBLE_EQ(o.number, 10);
  EXPECT_EQ(o.reads, (std::vector<std::string>{"a", "b"}));
  Outcome nan = in.value("set x hello");
  EXPECT_FALSE(nan.ok);
  Outcome div = in.value("expr {7/2}");  // Tcl's integer division
  EXPECT_DOUBLE_EQ(div.number, 3);
}

TYPED_TEST(TclInterp, ErrorsCarryTheirLine) {
  TypeParam in = make<TypeParam>();
  Outcome o = in.run("set a 1\n\nset b [expr {$a +}]\n");
  ASSERT_FALSE(o.ok);
  EXPECT_EQ(o.problems[0].kind, ProblemKind::Error);
  EXPECT_EQ(o.problems[0].line, 3);
  Outcome p = in.run("proc f {} {\n  error boom\n}\nset x 1\nf\n");
  ASSERT_FALSE(p.ok);
  EXPECT_EQ(p.problems[0].line, 5);
  EXPECT_NE(p.problems[0].trace.find("(procedure \"f\" line 2)"), std::string::npos);
}

TYPED_TEST(TclInterp, RunawayScriptsStopAtTheTimeLimit) {
  // An empty loop body runs no commands: only the time limit stops it.
  TypeParam in = make<TypeParam>({}, Limits{int64_t{1} << 40, 200});
  Outcome o = in.run("while 1 {}");
  ASSERT_FALSE(o.ok);
  EXPECT_EQ(o.problems[0].kind, ProblemKind::Limit);
  EXPECT_NE(o.problems[0].message.find("time"), std::string::npos) << o.problems[0].message;
  if constexpr (std::is_same_v<TypeParam, Engine>) {
    // The engine's limit is per script: the next one has a fresh one.
    Outcome after = in.run("set x 5");
    EXPECT_TRUE(after.ok) << after.result;
  } else {
    // Through a worker the limit is a budget for all of the scene's Tcl: it is spent, and
    // the one problem of it was the script's; nothing more runs.
    Outcome after = in.run("set x 5");
    ASSERT_FALSE(after.ok);
    EXPECT_EQ(after.problems[0].kind, ProblemKind::Stopped);
    EXPECT_NE(after.problems[0].message.find("whole 0.2 s"), std::string::npos) << after.problems[0].message;
  }
}

TYPED_TEST(TclInterp, RunawayLoopsStopAtTheCommandLimit) {
  // Loops whose body Tcl compiles (at top level and in a procedure) count their commands.
  for (const char* script : {"set i 0; while 1 {incr i}", "proc p {} {while 1 {set x 1}}; p",
                             "for {set i 0} {1} {incr i} {set y [expr {$i * 2}]}"}) {
    TypeParam in = make<TypeParam>({}, Limits{100000, 60000});
    Outcome o = in.run(script);
    ASSERT_FALSE(o.ok) << script;
    EXPECT_EQ(o.problems[0].kind, ProblemKind::Limit) << script;
    EXPECT_NE(o.problems[0].message.find("command count"), std::string::npos) << o.problems[0].message;
    EXPECT_TRUE(in.run("set after 1").ok) << script;
  }
}

TYPED_TEST(TclInterp, ValuesPastTheBoundsAreRefusedBeforeTheyAreBuilt) {
  for (const char* script : {
           "string repeat x 1000000000",
           "string repeat abc 400000000",
           "lrepeat 1000000000 a",
           "format %1000000000s x",
           "format %.1000000000f 1.0",
           "format %*s 1000000000 x",
           "binary format x1000000000",
           "binary format a1000000000 x",
           "set s x; while 1 {append s $s}",
           "set l a; while 1 {lappend l {*}$l}",
           "set s x; while 1 {set s $s$s}",
           "set s x; while 1 {set s \"$s$s$s\"}",
           "set s x; while 1 {set s [string cat $s $s]}",
           "set l a; while 1 {set l [concat $l $l]}",
           "set l a; while 1 {set l [list {*}$l {*}$l]}",
           "string map {a xxxxxxxxxx} [string repeat a 3000000]",
           "regsub -all a [string repeat a 3000] {&&&&}",
           "join [lrepeat 3000 [string repeat x 3000]]",
           "proc grow {s} {return $s$s}; set s x; while 1 {set s [grow $s]}",
       }) {
    TypeParam in = make<TypeParam>({}, Limits{int64_t{1} << 40, 60000});
    Outcome o = in.run(script);
    ASSERT_FALSE(o.ok) << script;
    EXPECT_EQ(o.problems[0].kind, ProblemKind::Memory) << script << ": " << o.problems[0].message;
    EXPECT_NE(o.problems[0].message.find("at most"), std::string::npos) << o.problems[0].message;
    // A refusal is an ordinary Tcl error: `catch` sees it, and the interpreter goes on.
    EXPECT_TRUE(in.run("set after 1").ok) << script;
  }
}

// Tcl computes huge whole numbers quickly but prints them in quadratic time (200,000 digits
// take about 20 s inside one command, which no limit interrupts): they are refused before
// any command gets them and as a script's result, and their text is never built.
TYPED_TEST(TclInterp, HugeWholeNumbersAreRefusedBeforeTheyArePrinted) {
  for (const char* script : {
           "expr {10**200000}",
           "set x [expr {10**200000}]",
           "set x [expr {2**40000}]; string length $x",
           "proc f {} {return [expr {7**50000}]}; f",
           "set x 1; while 1 {set x [expr {$x * 1000}]}",
       }) {
    TypeParam in = make<TypeParam>({}, Limits{int64_t{1} << 40, 60000});
    Outcome o = in.run(script);
    ASSERT_FALSE(o.ok) << script;
    EXPECT_EQ(o.problems[0].kind, ProblemKind::Memory) << script << ": " << o.problems[0].message;
    EXPECT_NE(o.problems[0].message.find("at most 10000 digits"), std::string::npos) << o.problems[0].message;
    EXPECT_TRUE(in.run("set after 1").ok) << script;
  }
  TypeParam in = make<TypeParam>();
  Outcome v = in.value("expr {10**20000}");
  ASSERT_FALSE(v.ok);
  EXPECT_EQ(v.problems[0].kind, ProblemKind::Memory);
  // Whole numbers of ordinary size, bignums included, are untouched.
  Outcome big = in.run("set b [expr {2**100}]");
  ASSERT_TRUE(big.ok) << big.result;
  EXPECT_EQ(in.get("b"), "1267650600228229401496703205376");
  Outcome w = in.value("expr {10**300 / 10**298}");
  ASSERT_TRUE(w.ok);
  EXPECT_DOUBLE_EQ(w.number, 100.0);
}

TYPED_TEST(TclInterp, OrdinaryUseOfTheGuardedCommandsStillWorks) {
  TypeParam in = make<TypeParam>();
  Outcome o = in.run(
      "set s [string repeat ab 3]; append s c; lappend l 1 2; set f [format %5.2f 3.14159];"
      "set r [lrepeat 2 x]; set j [join {a b} -]; set m [string map {a A} abc]; regsub -all b abab B g;"
      "set c [concat {1 2} 3]; set b [binary format a3 xyz]; set k [string cat $s $f]");
  ASSERT_TRUE(o.ok) << o.result;
  EXPECT_EQ(in.get("s"), "abababc");
  EXPECT_EQ(in.get("f"), " 3.14");
  EXPECT_EQ(in.get("r"), "x x");
  EXPECT_EQ(in.get("j"), "a-b");
  EXPECT_EQ(in.get("m"), "Abc");
  EXPECT_EQ(in.get("g"), "aBaB");
  EXPECT_EQ(in.get("c"), "1 2 3");
  EXPECT_EQ(in.get("k"), "abababc 3.14");
}

TYPED_TEST(TclInterp, ATclPanicStopsTheScenesTclInsteadOfTheProcess) {
  // One word joining 720 copies of a 3-million-character value passes Tcl's 2 GB limit for
  // a value, which Tcl answers by aborting the process; nomec turns that into a problem.
  std::string script = "set s [string repeat x 3000000]; set t ";
  for (int i = 0; i < 720; ++i) script += "$s";
  TypeParam in = make<TypeParam>();
  Outcome o = in.run(script);
  ASSERT_FALSE(o.ok);
  EXPECT_EQ(o.problems[0].kind, ProblemKind::Memory);
  EXPECT_NE(o.problems[0].message.find("Tcl gave up"), std::string::npos) << o.problems[0].message;
  // The abandoned interpreter runs nothing more, and says so.
  Outcome after = in.run("set x 1");
  ASSERT_FALSE(after.ok);
  EXPECT_EQ(after.problems[0].kind, ProblemKind::Memory);
  EXPECT_FALSE(in.get("s").has_value());
  // Other interpreters are not affected.
  TypeParam other = make<TypeParam>();
  EXPECT_TRUE(other.run("set y [string repeat y 3]").ok);
  EXPECT_EQ(other.get("y"), "yyy");
}

TYPED_TEST(TclInterp, NormalizesCarriageReturns) {
  EXPECT_EQ(normalize_newlines("a \\\r\r\nb\rc"), "a \\\nb\nc");
  TypeParam in = make<TypeParam>();
  Outcome o = in.run("set x [expr 1 + \\\r\r\n 2]");
  ASSERT_TRUE(o.ok) << o.result;
  EXPECT_EQ(in.get("x"), "3");
}

TYPED_TEST(TclInterp, TwoInterpretersAreIndependent) {
  TypeParam a = make<TypeParam>(), b = make<TypeParam>();
  ASSERT_TRUE(a.run("set v 1").ok);
  EXPECT_FALSE(b.get("v").has_value());
}

}  // namespace
}  // namespace nomec::tcl
