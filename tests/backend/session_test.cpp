// Tests of the editing session (backend/session.h): exact re-evaluation counts on the
// funnel cube (a transform-only change re-places the six instances and runs no funnel, a
// generator change runs the funnel once, an unused slider re-evaluates nothing; a handle's
// slider re-runs the handle only), reuse of
// unchanged components in pipeline blocks, and a seeded property test: after random
// slider sequences, every output equals a fresh build with those values given as -D
// overrides (summaries and vertex data), on examples and corpus files.
#include <gtest/gtest.h>

#include <cmath>
#include <fmt/format.h>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <thread>

#include "backend/session.h"
#include "frontend/check/check.h"
#include "frontend/check/tcl_live.h"

namespace nomec::backend {
namespace {

std::string read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string example(const std::string& name) { return read(std::string(NOMEC_SOURCE_DIR) + "/examples/" + name); }

struct Checked {
  SourceManager sources;
  DiagnosticEngine diags;
  CheckResult check;
};

std::unique_ptr<Checked> check(const std::string& path, const std::string& text,
                               std::vector<std::pair<std::string, double>> overrides = {}) {
  auto c = std::make_unique<Checked>();
  CheckOptions o;
  o.overrides = std::move(overrides);
  o.allow_out_of_range = true;
  o.read_file = [](const std::string& p) -> std::optional<std::string> {
    std::ifstream in(p, std::ios::binary);
    if (!in) return std::nullopt;
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  c->check = check_source(c->sources, path, text, o, c->diags);
  return c;
}

std::vector<int32_t> affected(const ir::Module& m, std::string_view bank, std::string_view name) {
  std::vector<int32_t> out;
  for (ir::NodeId n : m.deps.affected_by(m.find_param(bank, name))) out.push_back(n.index);
  std::sort(out.begin(), out.end());
  return out;
}

TEST(Session, FunnelCubeTransformChangeRunsNoGenerator) {
  auto c = check("funnel_cube.nome", example("funnel_cube.nome"));
  ASSERT_EQ(c->diags.error_count(), 0);
  const std::vector<int32_t> expected = affected(c->check.module, "fp", "z");
  Session s(std::move(c->check.module));
  DiagnosticEngine d;
  UpdateStats full = s.build(d);
  EXPECT_EQ(full.generators_rerun, 1);
  EXPECT_EQ(full.instances_retransformed, 6);
  EXPECT_EQ(full.nodes_in_graph, 24u);
  const auto before = s.outputs();
  UpdateStats u = s.set_parameter("fp.z", -0.5, d);
  ASSERT_TRUE(u.ok()) << u.error;
  EXPECT_EQ(d.error_count(), 0);
  EXPECT_EQ(u.parameter, "fp.z");
  EXPECT_EQ(u.generators_rerun, 0);
  EXPECT_EQ(u.instances_retransformed, 6);
  EXPECT_EQ(u.kernel_ops_rerun, 0);
  // Six translate values, six instances, the group and `cf`: exactly the nodes the
  // dependency graph says depend on fp.z.
  EXPECT_EQ(u.nodes_reevaluated, 14u);
  EXPECT_EQ(u.reevaluated, expected);
  EXPECT_EQ(u.changed_outputs, std::vector<std::string>{"cf"});
  ASSERT_EQ(s.outputs().size(), 1u);
  EXPECT_NE(s.outputs()[0], before[0]);
}

// A SLIDE slider is a Tk `scale` made by `CreateScale` in the file's Tcl (issue 15): moving
// `swp.q0x` re-evaluates only what the dependency graph says reads it (the profile point q0
// and the curve and sweep built on it), not the whole scene.
TEST(Session, SlideSliderMadeByTclReevaluatesOnlyItsDependents) {
  const std::string path = std::string(NOMEC_CORPUS_DIR) + "/slide/BellShape.slf";
  auto c = check(path, read(path));
  ASSERT_EQ(c->diags.error_count(), 0);
  const ir::NodeId q0x = c->check.module.find_param("swp", "q0x");
  ASSERT_TRUE(q0x.is_valid());
  EXPECT_DOUBLE_EQ(c->check.module.param(q0x).value, 0.9);  // CreateScale's default
  EXPECT_DOUBLE_EQ(c->check.module.param(q0x).max, 2);
  const std::vector<int32_t> expected = affected(c->check.module, "swp", "q0x");
  Session s(std::move(c->check.module));
  DiagnosticEngine d;
  UpdateStats full = s.build(d);
  UpdateStats u = s.set_parameter("swp_q0x", 0.5, d);
  ASSERT_TRUE(u.ok()) << u.error;
  EXPECT_EQ(u.parameter, "swp.q0x");
  // Only dependents of the slider (of those, what the scene draws).
  EXPECT_FALSE(u.reevaluated.empty());
  for (int32_t n : u.reevaluated) EXPECT_TRUE(std::binary_search(expected.begin(), expected.end(), n)) << n;
  EXPECT_LT(u.nodes_reevaluated, full.nodes_reevaluated);
  EXPECT_LT(u.generators_rerun, full.generators_rerun);  // `profile1`, drawn nowhere, is not rerun
  // A slider no geometry reads changes nothing.
  UpdateStats none = s.set_parameter("swp.drawControls", 0, d);
  ASSERT_TRUE(none.ok()) << none.error;
  EXPECT_EQ(none.generators_rerun, 0);
}

// SLIDE values Tcl computes in a way nomec's expressions cannot repeat follow their sliders
// (issue 15): as in the corpus's spiral.slf, `par.numS` switches bands on and off through
// `lod {if {$par_numS >= k} {expr $SLF_FULL} else {expr $SLF_OFF}}`.
const char* kBands = R"(tclinit {
  source SLIDEUI.tcl
  set root .slfWindow.par
  toplevel $root
  CreateScale par $root numS "Shells" 2 0 3 1 1 horizontal
  CreateScale par $root gr "Grow" 1.5 1 2 0.1 1 horizontal
}
point p0 (0 0 0) endpoint
point p1 (1 0 0) endpoint
point p2 (0 1 0) endpoint
face f (p0 p1 p2) endface
object band (f) endobject
group shell
  instance band id b1 lod {if {$par_numS >= 1} {expr $SLF_FULL} else {expr $SLF_OFF}} endinstance
  instance band id b2 lod {if {$par_numS >= 2} {expr $SLF_FULL} else {expr $SLF_OFF}} translate ({expr $par_gr} 0 0) endinstance
  instance band id b3 lod {if {$par_numS >= 3} {expr $SLF_FULL} else {expr $SLF_OFF}} translate ({expr 2*$par_gr} 0 0) endinstance
endgroup
instance shell endinstance
)";

int32_t faces(const Session& s) {
  int32_t n = 0;
  for (const auto& o : s.outputs()) n += o->soup.face_count();
  return n;
}

TEST(Session, TclLodSwitchesInstancesOnAndOff) {
  auto c = check("/nonexistent/bands.slf", kBands);
  ASSERT_EQ(c->diags.error_count(), 0);
  for (const Diagnostic& x : c->diags.diagnostics()) EXPECT_NE(x.kind, DiagKind::TclValueFixed) << x.message;
  ASSERT_NE(c->check.module.external, nullptr);
  const std::vector<int32_t> by_num = affected(c->check.module, "par", "numS");
  const std::vector<int32_t> by_gr = affected(c->check.module, "par", "gr");
  Session s(std::move(c->check.module));
  DiagnosticEngine d;
  const UpdateStats full = s.build(d);
  EXPECT_EQ(faces(s), 2);  // numS = 2: two bands
  UpdateStats three = s.set_parameter("par.numS", 3, d);
  ASSERT_TRUE(three.ok()) << three.error;
  EXPECT_EQ(faces(s), 3);
  // What depends on numS, and the third band's translation, computed for the first time.
  for (int32_t n : three.reevaluated) {
    const bool before = std::find(full.reevaluated.begin(), full.reevaluated.end(), n) != full.reevaluated.end();
    EXPECT_TRUE(std::binary_search(by_num.begin(), by_num.end(), n) || !before) << n;
  }
  EXPECT_LT(three.nodes_reevaluated, full.nodes_reevaluated);
  UpdateStats one = s.set_parameter("par.numS", 1, d);
  ASSERT_TRUE(one.ok()) << one.error;
  EXPECT_EQ(faces(s), 1);
  EXPECT_EQ(s.set_parameter("par.numS", 0, d).ok(), true);
  EXPECT_EQ(faces(s), 0);
  EXPECT_EQ(d.error_count(), 0);
  // `par.gr` moves the bands; the `lod` values, which read only `par.numS`, are not
  // re-evaluated.
  s.set_parameter("par.numS", 3, d);
  UpdateStats gr = s.set_parameter("par.gr", 1.2, d);
  ASSERT_TRUE(gr.ok()) << gr.error;
  EXPECT_EQ(faces(s), 3);
  EXPECT_FALSE(gr.reevaluated.empty());
  for (int32_t n : gr.reevaluated) {
    EXPECT_TRUE(std::binary_search(by_gr.begin(), by_gr.end(), n)) << n;
    EXPECT_FALSE(s.module().node(ir::NodeId(n)).name.ends_with(".lod")) << s.module().node(ir::NodeId(n)).name;
  }
}

// A value reading what a `tclupdate` block computes from a slider follows that slider; the
// block runs once per change of slider values, not once per value.
TEST(Session, TclUpdateValueFollowsItsSlider) {
  const std::string text = R"(tclinit {
  package require slideui
  set par_a 1
  set par_b 1
  scale .a -from 0 -to 4 -resolution 0.5 -variable par_a
  scale .b -from 0 -to 4 -resolution 1 -variable par_b
}
tclupdate { set r [expr {$par_a * 2}] }
point p0 (0 0 0) endpoint
point p1 ({expr $r} 0 0) endpoint
point p2 (0 {expr $r + 1} 0) endpoint
face f (p0 p1 p2) endface
object o (f) endobject
instance o endinstance
)";
  auto c = check("/nonexistent/update.slf", text);
  ASSERT_EQ(c->diags.error_count(), 0);
  const std::vector<int32_t> by_a = affected(c->check.module, "par", "a");
  const std::vector<int32_t> by_b = affected(c->check.module, "par", "b");
  EXPECT_FALSE(by_a.empty());
  EXPECT_TRUE(by_b.empty());  // nothing reads `par.b`
  auto* ev = dynamic_cast<const check::TclEvaluator*>(c->check.module.external.get());
  ASSERT_NE(ev, nullptr);
  Session s(std::move(c->check.module));
  DiagnosticEngine d;
  s.build(d);
  ASSERT_EQ(s.outputs().size(), 1u);
  auto max_x = [&] {
    double m = 0;
    for (const glm::dvec3& p : s.outputs()[0]->soup.positions) m = std::max(m, p.x);
    return m;
  };
  auto max_y = [&] {
    double m = 0;
    for (const glm::dvec3& p : s.outputs()[0]->soup.positions) m = std::max(m, p.y);
    return m;
  };
  EXPECT_DOUBLE_EQ(max_x(), 2);
  EXPECT_DOUBLE_EQ(max_y(), 3);
  const int runs = ev->update_runs();
  UpdateStats u = s.set_parameter("par.a", 1.5, d);
  ASSERT_TRUE(u.ok()) << u.error;
  EXPECT_DOUBLE_EQ(max_x(), 3);
  EXPECT_DOUBLE_EQ(max_y(), 4);
  EXPECT_EQ(ev->update_runs(), runs + 1);  // two values read `r`: one run
  for (int32_t n : u.reevaluated) EXPECT_TRUE(std::binary_search(by_a.begin(), by_a.end(), n)) << n;
  EXPECT_EQ(d.error_count(), 0);
}

// A Tcl error for some slider values only (Tcl's integer division by zero at a = 2) is an
// evaluation error at the value, not a crash; the value recovers when the slider moves on.
TEST(Session, TclErrorAtSomeSliderValuesIsAnErrorAtTheValue) {
  const std::string text = R"(tclinit {
  package require slideui
  set par_a 1
  scale .a -from 0 -to 4 -resolution 1 -variable par_a
}
point p0 (0 0 0) endpoint
point p1 ({if {$par_a >= 0} {expr 6/($par_a - 2)} else {expr 0}} 0 0) endpoint
point p2 (0 1 0) endpoint
face f (p0 p1 p2) endface
object o (f) endobject
instance o endinstance
)";
  auto c = check("/nonexistent/divide.slf", text);
  ASSERT_EQ(c->diags.error_count(), 0);
  Session s(std::move(c->check.module));
  DiagnosticEngine d;
  s.build(d);
  DiagnosticEngine bad;
  UpdateStats u = s.set_parameter("par.a", 2, bad);
  ASSERT_TRUE(u.ok()) << u.error;
  ASSERT_EQ(bad.error_count(), 1);
  const Diagnostic& e = bad.diagnostics().front();
  EXPECT_EQ(e.kind, DiagKind::GeometryFailed);
  EXPECT_NE(e.message.find("divide by zero"), std::string::npos) << e.message;
  const size_t at = text.find("{if {$par_a >= 0}");
  EXPECT_EQ(e.range.begin, at);
  EXPECT_EQ(e.range.end, text.find(" 0 0) endpoint", at));
  DiagnosticEngine good;
  ASSERT_TRUE(s.set_parameter("par.a", 3, good).ok());
  EXPECT_EQ(good.error_count(), 0);
  double x = 0;
  for (const glm::dvec3& p : s.outputs()[0]->soup.positions) x = std::max(x, p.x);
  EXPECT_DOUBLE_EQ(x, 6);  // 6 / (3 - 2)
}

// The interpreter belongs to the evaluator's own thread: evaluating from other threads (the
// language server's) gives the right values.
TEST(Session, TclValueEvaluatesFromAnotherThread) {
  auto c = check("/nonexistent/bands.slf", kBands);
  ASSERT_EQ(c->diags.error_count(), 0);
  ir::Module& m = c->check.module;
  ir::ExprId lod3 = ir::ExprId::None();
  for (size_t i = 0; i < m.exprs.size(); ++i) {
    if (m.exprs[i].kind == ir::ExprKind::External && m.external_script(m.exprs[i]).value == 0) lod3 = ir::ExprId(static_cast<int32_t>(i));
  }
  ASSERT_TRUE(lod3.is_valid());  // `par_numS >= 3` is off at 2
  m.param(m.find_param("par", "numS")).value = 3;
  ir::EvalResult there;
  std::thread t([&] { there = ir::evaluate(m, lod3); });
  t.join();
  ASSERT_TRUE(there.ok) << there.problem;
  EXPECT_EQ(there.value, 3);  // SLF_FULL
  m.param(m.find_param("par", "numS")).value = 2;
  std::vector<ir::EvalResult> many(4);
  std::vector<std::thread> threads;
  for (auto& r : many) threads.emplace_back([&m, &r, lod3] { r = ir::evaluate(m, lod3); });
  for (auto& th : threads) th.join();
  for (const auto& r : many) EXPECT_EQ(r.value, 0);
}

TEST(Session, FunnelCubeGeneratorChangeRunsItOnce) {
  auto c = check("funnel_cube.nome", example("funnel_cube.nome"));
  const std::vector<int32_t> expected = affected(c->check.module, "fp", "n");
  Session s(std::move(c->check.module));
  DiagnosticEngine d;
  s.build(d);
  EXPECT_EQ(s.outputs()[0]->soup.face_count(), 6 * 8);  // one ring of n = 8 quads per funnel
  UpdateStats u = s.set_parameter("fp_n", 5, d);  // the 2016 spelling
  ASSERT_TRUE(u.ok()) << u.error;
  EXPECT_EQ(u.parameter, "fp.n");
  EXPECT_EQ(u.generators_rerun, 1);
  EXPECT_EQ(u.instances_retransformed, 6);
  EXPECT_EQ(u.nodes_reevaluated, 10u);
  EXPECT_EQ(u.reevaluated, expected);
  EXPECT_EQ(s.outputs()[0]->soup.face_count(), 6 * 5);
}

TEST(Session, UnusedParameterReevaluatesNothing) {
  std::string text = example("funnel_cube.nome");
  text.replace(text.find("endbank"), 7, "    set unused 1 0 2 1\nendbank");
  auto c = check("funnel_cube.nome", text);
  ASSERT_EQ(c->diags.error_count(), 0);
  Session s(std::move(c->check.module));
  DiagnosticEngine d;
  s.build(d);
  const auto before = s.outputs();
  UpdateStats u = s.set_parameter("fp.unused", 2, d);
  ASSERT_TRUE(u.ok()) << u.error;
  EXPECT_EQ(u.nodes_reevaluated, 0u);
  EXPECT_EQ(u.generators_rerun, 0);
  EXPECT_EQ(u.instances_retransformed, 0);
  EXPECT_EQ(u.kernel_ops_rerun, 0);
  EXPECT_TRUE(u.changed_outputs.empty());
  EXPECT_EQ(s.outputs(), before);  // the very same mesh objects
}

TEST(Session, HandleSliderRerunsTheHandleNotTheFunnels) {
  // examples/handle_funnels.nome: `tw.twist` is read by the handle block only. Moving it
  // runs no generator and places no instance again; the block's kernel operations (the
  // merge of its input and the handle) run again and its output changes, with the same
  // counts (a twist changes positions only).
  auto c = check("handle_funnels.nome", example("handle_funnels.nome"));
  ASSERT_EQ(c->diags.error_count(), 0);
  Session s(std::move(c->check.module));
  DiagnosticEngine d;
  UpdateStats full = s.build(d);
  EXPECT_EQ(d.error_count(), 0);
  EXPECT_EQ(full.generators_rerun, 1);
  const auto before = s.outputs();
  ASSERT_EQ(before.size(), 1u);
  UpdateStats u = s.set_parameter("tw.twist", 2, d);
  ASSERT_TRUE(u.ok()) << u.error;
  EXPECT_EQ(d.error_count(), 0);
  EXPECT_EQ(u.generators_rerun, 0);
  EXPECT_EQ(u.instances_retransformed, 0);
  EXPECT_EQ(u.kernel_ops_rerun, 2);
  ASSERT_EQ(s.outputs().size(), 1u);
  EXPECT_NE(s.outputs()[0], before[0]);
  EXPECT_EQ(s.outputs()[0]->soup.face_count(), before[0]->soup.face_count());
  EXPECT_NE(s.outputs()[0]->soup.positions, before[0]->soup.positions);
  // The segments slider changes the handle's counts: 10 → 4 segments, 6 rings fewer.
  u = s.set_parameter("tw.segments", 4, d);
  ASSERT_TRUE(u.ok()) << u.error;
  EXPECT_EQ(u.generators_rerun, 0);
  EXPECT_EQ(s.outputs()[0]->soup.face_count(), before[0]->soup.face_count() - 6 * 4);
}

TEST(Session, RefusesUnknownAndOutOfRangeSliders) {
  auto c = check("funnel_cube.nome", example("funnel_cube.nome"));
  Session s(std::move(c->check.module));
  DiagnosticEngine d;
  s.build(d);
  UpdateStats u = s.set_parameter("fp.nope", 1, d);
  EXPECT_FALSE(u.ok());
  EXPECT_NE(u.error.find("no slider `fp.nope`"), std::string::npos);
  u = s.set_parameter("fp.n", 11, d);
  EXPECT_FALSE(u.ok());
  EXPECT_NE(u.error.find("outside the range [3, 10]"), std::string::npos);
  EXPECT_EQ(s.module().param(s.find_parameter("fp.n")).value, 8);
}

// A slider never takes a value that is not finite, even where out-of-range values are
// allowed (`nome/setParameter` with JSON's `1e999`, which reads as infinity); a finite value
// whose expressions overflow is an error at the operation, and no output is made of it.
TEST(Session, RefusesValuesThatAreNotFinite) {
  const std::string text =
      "bank b\n  set x 1 0 10 1\nendbank\n"
      "point p ({expr $b_x * 1e300} 0 0) endpoint\npoint q (0 1 0) endpoint\npoint r (0 0 1) endpoint\n"
      "mesh m\n  face f (p q r) endface\nendmesh\ninstance i m endinstance\n";
  auto c = check("overflow.nome", text);
  ASSERT_EQ(c->diags.error_count(), 0);
  SessionOptions options;
  options.allow_out_of_range = true;
  Session s(std::move(c->check.module), options);
  DiagnosticEngine d;
  s.build(d);
  ASSERT_EQ(d.error_count(), 0);
  for (double bad : {std::nan(""), HUGE_VAL, -HUGE_VAL}) {
    UpdateStats u = s.set_parameter("b.x", bad, d);
    EXPECT_FALSE(u.ok());
    EXPECT_NE(u.error.find("is not a finite number; slider `b.x` keeps 1"), std::string::npos) << u.error;
    EXPECT_EQ(s.module().param(s.find_parameter("b.x")).value, 1);
  }
  EXPECT_EQ(d.error_count(), 0);
  UpdateStats u = s.set_parameter("b.x", 1e10, d);  // allowed, but 1e10 * 1e300 overflows
  EXPECT_TRUE(u.ok());
  ASSERT_EQ(d.error_count(), 1);
  EXPECT_EQ(d.diagnostics()[0].kind, DiagKind::GeometryFailed);
  EXPECT_EQ(d.diagnostics()[0].message,
            "cannot evaluate `position`: 10000000000 * 1e+300 is too large: numbers stop near 1.8e308");
  EXPECT_EQ(d.diagnostics()[0].range.begin, text.find("$b_x * 1e300"));
}

// Every array of two outputs, soup and built mesh, is equal (a patched or reused result
// must be exactly what a fresh build makes).
void expect_identical(const OutputMesh& a, const OutputMesh& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.curve_count, b.curve_count);
  const kernel::PolygonSoup& pa = a.soup;
  const kernel::PolygonSoup& pb = b.soup;
  EXPECT_EQ(pa.positions, pb.positions);
  EXPECT_EQ(pa.names, pb.names);
  EXPECT_EQ(pa.face_sizes, pb.face_sizes);
  EXPECT_EQ(pa.face_vertices, pb.face_vertices);
  EXPECT_EQ(pa.face_sources, pb.face_sources);
  EXPECT_EQ(pa.face_colors, pb.face_colors);
  ASSERT_EQ(pa.creases.size(), pb.creases.size());
  for (size_t i = 0; i < pa.creases.size(); ++i) {
    EXPECT_EQ(pa.creases[i].a, pb.creases[i].a);
    EXPECT_EQ(pa.creases[i].b, pb.creases[i].b);
    EXPECT_EQ(pa.creases[i].sharpness, pb.creases[i].sharpness);
  }
  EXPECT_EQ(pa.corners.size(), pb.corners.size());
  EXPECT_TRUE(kernel::has_same_topology(a.mesh, b.mesh));
  EXPECT_EQ(a.mesh.positions(), b.mesh.positions());
}

// `count` funnels in a group (one output mesh); the first one's x is slider `s.x`, the
// second's x scale is slider `s.k` (a negative value mirrors it, reversing its faces).
std::string funnel_field(int count, bool in_block) {
  std::string s = "bank s\n  set x 0 -1 1 0.1\n  set k 1 -1 1 0.1\n  set n 6 3 9 1\nendbank\n"
                  "funnel f ({expr $s_n} 0.4 0.3 0.3) endfunnel\nfunnel g (5 0.4 0.3 0.3) endfunnel\n";
  s += in_block ? "subdivision field type NOME_SD_CC_sharp subdivisions 1\n" : "group field\n";
  for (int i = 0; i < count; ++i) {
    std::string x = i == 0 ? "{expr $s_x}" : std::to_string((i % 4) * 3);
    std::string scale = i == 1 ? " scale ({expr $s_k} 1 1)" : "";
    s += fmt::format("  instance i{} {}{} translate ({} {} 0) endinstance\n", i, i == 2 ? "f" : "g", scale, x,
                     (i / 4) * 3);
  }
  s += in_block ? "endsubdivision\n" : "endgroup\n";
  s += "instance all field endinstance\n";
  return s;
}

// Builds a fresh session of `text` with `overrides` and checks `s` equals it exactly.
void expect_fresh_equal(const Session& s, const std::string& text,
                        std::vector<std::pair<std::string, double>> overrides) {
  auto c = check("field.nome", text, std::move(overrides));
  ASSERT_EQ(c->diags.error_count(), 0);
  Session f(std::move(c->check.module));
  DiagnosticEngine d;
  f.build(d);
  ASSERT_EQ(f.outputs().size(), s.outputs().size());
  for (size_t i = 0; i < f.outputs().size(); ++i) expect_identical(*s.outputs()[i], *f.outputs()[i]);
}

// Moving one instance of a group overwrites only its vertex range in the previous output
// (one output, one part patched); a change of topology (a mirroring scale, another side
// count) reassembles instead. Every result equals a fresh build.
TEST(Session, GroupEntryPatchesOnlyTheMovedInstance) {
  const std::string text = funnel_field(12, false);
  auto c = check("field.nome", text);
  ASSERT_EQ(c->diags.error_count(), 0) << c->diags.diagnostics()[0].message;
  Session s(std::move(c->check.module));
  DiagnosticEngine d;
  UpdateStats full = s.build(d);
  EXPECT_EQ(full.outputs_patched, 0);
  UpdateStats u = s.set_parameter("s.x", 0.5, d);
  EXPECT_EQ(u.instances_retransformed, 1);
  EXPECT_EQ(u.outputs_patched, 1);
  EXPECT_EQ(u.parts_patched, 1);
  EXPECT_EQ(u.changed_outputs, std::vector<std::string>{"all"});
  expect_fresh_equal(s, text, {{"s.x", 0.5}});
  u = s.set_parameter("s.x", -0.3, d);
  EXPECT_EQ(u.outputs_patched, 1);
  EXPECT_EQ(u.parts_patched, 1);
  expect_fresh_equal(s, text, {{"s.x", -0.3}});
  // A positive scale keeps the faces' orientation: a patch.
  u = s.set_parameter("s.k", 0.5, d);
  EXPECT_EQ(u.outputs_patched, 1);
  expect_fresh_equal(s, text, {{"s.x", -0.3}, {"s.k", 0.5}});
  // A negative one reverses its faces: reassembled.
  u = s.set_parameter("s.k", -1, d);
  EXPECT_EQ(u.instances_retransformed, 1);
  EXPECT_EQ(u.outputs_patched, 0);
  expect_fresh_equal(s, text, {{"s.x", -0.3}, {"s.k", -1}});
  // Another side count: new faces, reassembled; the generator runs once.
  u = s.set_parameter("s.n", 4, d);
  EXPECT_EQ(u.generators_rerun, 1);
  EXPECT_EQ(u.outputs_patched, 0);
  expect_fresh_equal(s, text, {{"s.x", -0.3}, {"s.k", -1}, {"s.n", 4}});
  // After a reassembly the next move patches again.
  u = s.set_parameter("s.x", 0.2, d);
  EXPECT_EQ(u.outputs_patched, 1);
  expect_fresh_equal(s, text, {{"s.x", 0.2}, {"s.k", -1}, {"s.n", 4}});
  EXPECT_EQ(d.error_count(), 0);
}

// An output a client still holds is never modified by a later update (the patch copies
// it instead of taking over its storage).
TEST(Session, PatchLeavesHeldOutputsIntact) {
  const std::string text = funnel_field(8, false);
  auto c = check("field.nome", text);
  Session s(std::move(c->check.module));
  DiagnosticEngine d;
  s.build(d);
  const std::shared_ptr<const OutputMesh> held = s.outputs()[0];
  const std::vector<glm::dvec3> soup_before = held->soup.positions;
  const auto mesh_before = held->mesh.positions();
  UpdateStats u = s.set_parameter("s.x", 0.7, d);
  EXPECT_EQ(u.outputs_patched, 1);
  EXPECT_NE(s.outputs()[0], held);
  EXPECT_EQ(held->soup.positions, soup_before);
  EXPECT_EQ(held->mesh.positions(), mesh_before);
  EXPECT_NE(s.outputs()[0]->soup.positions, soup_before);
  expect_fresh_equal(s, text, {{"s.x", 0.7}});
}

// Three separate funnels in one subdivision block: each is a cluster of its own (their
// borders are far apart), merged and subdivided separately. Moving the middle one (the
// block's bounding box, hence the merge tolerance, stays the same) re-merges and
// re-subdivides only its cluster; the other two clusters' results are reused whole, and
// the entry patches the moved cluster's vertices. Moving it past the others grows the box,
// so every cluster is merged again, but the unchanged components' subdivisions are still
// reused by content. Every result equals a fresh build.
TEST(Session, SubdivisionBlockReusesUnchangedClusters) {
  const std::string text =
      "bank b\n  set x 0 -9 9 0.1\nendbank\n"
      "funnel f (6 0.5 0.5 0.5) endfunnel\n"
      "subdivision s type NOME_SD_CC_sharp subdivisions 2\n"
      "  instance d f translate (-5 0 0) endinstance\n"
      "  instance a f translate ({expr $b_x} 0 0) endinstance\n"
      "  instance c f translate (5 0 0) endinstance\n"
      "endsubdivision\n"
      "instance top s endinstance\n";
  auto c = check("blocks.nome", text);
  ASSERT_EQ(c->diags.error_count(), 0) << c->diags.diagnostics()[0].message;
  Session s(std::move(c->check.module));
  DiagnosticEngine d;
  UpdateStats full = s.build(d);
  ASSERT_EQ(d.error_count(), 0);
  EXPECT_EQ(full.kernel_ops_rerun, 3 + 3);  // a merge and a subdivision per cluster
  EXPECT_EQ(full.clusters_reused, 0);
  UpdateStats u = s.set_parameter("b.x", 0.5, d);
  ASSERT_EQ(d.error_count(), 0);
  EXPECT_EQ(u.generators_rerun, 0);
  EXPECT_EQ(u.instances_retransformed, 1);
  EXPECT_EQ(u.kernel_ops_rerun, 1 + 1);  // the moved funnel's merge and subdivision
  EXPECT_EQ(u.clusters_reused, 2);
  EXPECT_EQ(u.outputs_patched, 1);
  EXPECT_EQ(u.parts_patched, 1);
  expect_fresh_equal(s, text, {{"b.x", 0.5}});
  u = s.set_parameter("b.x", 8, d);  // past `c`: a larger box, another tolerance
  EXPECT_EQ(u.kernel_ops_rerun, 3 + 1);
  EXPECT_EQ(u.clusters_reused, 0);
  expect_fresh_equal(s, text, {{"b.x", 8}});
  EXPECT_EQ(d.error_count(), 0);
  // Onto `c`: the coinciding rims cannot be merged; the failing cluster falls back to the
  // whole input, which reports exactly what a fresh build reports.
  DiagnosticEngine ud;
  s.set_parameter("b.x", 5, ud);
  EXPECT_GT(ud.error_count(), 0);
  auto fresh = check("blocks.nome", text, {{"b.x", 5}});
  Session f(std::move(fresh->check.module));
  DiagnosticEngine fd;
  f.build(fd);
  EXPECT_EQ(ud.error_count(), fd.error_count());
  ASSERT_EQ(ud.diagnostics().size(), fd.diagnostics().size());
  for (size_t i = 0; i < ud.diagnostics().size(); ++i) EXPECT_EQ(ud.diagnostics()[i].message, fd.diagnostics()[i].message);
  EXPECT_EQ(s.outputs().size(), f.outputs().size());
  // And back: clusters again, equal to a fresh build.
  u = s.set_parameter("b.x", 0.5, d);
  EXPECT_EQ(d.error_count(), 0);
  expect_fresh_equal(s, text, {{"b.x", 0.5}});
}

void expect_same_outputs(const Session& a, const Session& b, const std::string& where) {
  ASSERT_EQ(a.outputs().size(), b.outputs().size()) << where;
  std::vector<MeshSummary> sa = a.summary(), sb = b.summary();
  for (size_t i = 0; i < sa.size(); ++i) {
    SCOPED_TRACE(where + " mesh " + sa[i].name);
    EXPECT_EQ(sa[i].name, sb[i].name);
    EXPECT_EQ(sa[i].vertices, sb[i].vertices);
    EXPECT_EQ(sa[i].edges, sb[i].edges);
    EXPECT_EQ(sa[i].faces, sb[i].faces);
    EXPECT_EQ(sa[i].euler, sb[i].euler);
    EXPECT_EQ(sa[i].is_orientable, sb[i].is_orientable);
    EXPECT_EQ(sa[i].border_loops, sb[i].border_loops);
    EXPECT_EQ(sa[i].genus, sb[i].genus);
    EXPECT_EQ(sa[i].position_hash, sb[i].position_hash);
    const kernel::PolygonSoup& pa = a.outputs()[i]->soup;
    const kernel::PolygonSoup& pb = b.outputs()[i]->soup;
    EXPECT_EQ(pa.positions, pb.positions);
    EXPECT_EQ(pa.face_sizes, pb.face_sizes);
    EXPECT_EQ(pa.face_vertices, pb.face_vertices);
    EXPECT_EQ(pa.face_sources, pb.face_sources);
    EXPECT_EQ(pa.face_colors, pb.face_colors);
  }
}

struct PropertyCase {
  std::string path;
  PipelineOptions pipeline;
};

void run_property(const PropertyCase& pc, uint32_t seed, int steps, std::string text = {}) {
  SCOPED_TRACE(pc.path);
  if (text.empty()) text = read(pc.path);
  ASSERT_FALSE(text.empty()) << "cannot read " << pc.path;
  auto c = check(pc.path, text);
  ASSERT_EQ(c->diags.error_count(), 0);
  std::vector<ir::NodeId> params = c->check.module.params();
  ASSERT_FALSE(params.empty());
  SessionOptions so;
  so.pipeline = pc.pipeline;
  so.allow_out_of_range = true;
  Session s(std::move(c->check.module), so);
  DiagnosticEngine d;
  s.build(d);
  std::mt19937 rng(seed);
  std::map<std::string, double> values;
  for (int i = 0; i < steps; ++i) {
    const ir::NodeId pid = params[rng() % params.size()];
    const ir::ParamData& p = s.module().param(pid);
    const std::string& name = s.module().node(pid).name;
    double lo = std::min(p.min, p.max), hi = std::max(p.min, p.max);
    double v = lo + (hi - lo) * std::uniform_real_distribution<double>(0, 1)(rng);
    if (p.step > 0) v = std::min(hi, lo + std::round((v - lo) / p.step) * p.step);
    DiagnosticEngine ud;
    UpdateStats u = s.set_parameter(name, v, ud);
    ASSERT_TRUE(u.ok()) << u.error;
    values[name] = v;
    std::vector<std::pair<std::string, double>> overrides(values.begin(), values.end());
    auto fresh = check(pc.path, text, overrides);
    Session f(std::move(fresh->check.module), so);
    DiagnosticEngine fd;
    f.build(fd);
    EXPECT_EQ(ud.error_count(), fd.error_count()) << "after " << name << "=" << v;
    expect_same_outputs(s, f, fmt::format("step {}: {}={}", i, name, v));
    // Also the one-shot evaluate_scene path (element order may differ in blocks that work
    // per component, so compare the order-independent summaries).
    if (!pc.pipeline.any()) {
      DiagnosticEngine ed;
      std::vector<OutputMesh> oneshot = evaluate_scene(f.module(), ed);
      ASSERT_EQ(oneshot.size(), s.outputs().size());
      for (size_t k = 0; k < oneshot.size(); ++k) {
        MeshSummary a = summarize(oneshot[k]), b = summarize(*s.outputs()[k]);
        EXPECT_EQ(a.faces, b.faces);
        EXPECT_EQ(a.vertices, b.vertices);
        EXPECT_EQ(a.position_hash, b.position_hash);
      }
    }
  }
}

TEST(SessionProperty, RandomSliderSequencesMatchFreshBuilds) {
  const std::string ex = std::string(NOMEC_SOURCE_DIR) + "/examples/";
  const std::string corpus = std::string(NOMEC_CORPUS_DIR) + "/";
  PipelineOptions sub_offset;
  sub_offset.is_merge = true;
  sub_offset.subdivide_levels = 1;
  sub_offset.offset_height = 0.05;
  std::vector<PropertyCase> cases = {
      {ex + "funnel_cube.nome", {}},
      {ex + "funnel_cube.nome", sub_offset},
      {ex + "klein_bottle.nome", {}},
      {ex + "klein_bottle_zipped.nome", {}},
      {ex + "handle_cube.nome", {}},
      {ex + "handle_funnels.nome", {}},
      {ex + "sierpinski_tetrahedron.nome", {}},
      {ex + "menger_sponge.nome", {}},
      {ex + "rind_sphere.nome", {}},
      {ex + "mobius_handle.nome", {}},
      {corpus + "nome1/funnelCube/funnelCube.nom", {}},
      {corpus + "nome1/kleinbottle/kleinbottle.nom", {}},
      {corpus + "nome3/bank_sphere.nom", {}},
      {corpus + "nome3/sweeps.nom", {}},
      {corpus + "nome3/torusknot.nom", {}},
      {corpus + "nome3/cubocta_jitterbug.nom", {}},
      {corpus + "nome3/tetra_sculpture.nom", {}},
  };
  uint32_t seed = 20261122;
  for (const PropertyCase& pc : cases) run_property(pc, seed++, 6);
  // Corpus files with pipeline blocks, and generated fields in a group and in a block
  // (patched entries, clusters of the block's input). The SLIDE files' sliders are made by
  // their Tcl (`subdivision.slf` is left out: its meshes come from SLIDE's lost `slideui`
  // package, so its scene has nothing to subdivide).
  for (const char* f : {"nome3/sharp_specs.nom", "nome3/hello_cube.nom", "nome3/light_test.nom",
                        "slide/minSubdiv.slf", "slide/spiral.slf", "slide/CHS_Merge-Saddle.slf"}) {
    const std::string path = corpus + f;
    auto c = check(path, read(path));
    if (c->diags.error_count() == 0 && !c->check.module.params().empty()) run_property({path, {}}, seed++, 4);
  }
  run_property({"group_field.nome", {}}, seed++, 8, funnel_field(12, false));
  run_property({"block_field.nome", {}}, seed++, 8, funnel_field(12, true));
}

}  // namespace
}  // namespace nomec::backend
