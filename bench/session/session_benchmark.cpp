// Slider updates versus full rebuilds (issue 6), measured in one run: each case builds a
// backend::Session once; `BM_Update_<case>` moves one slider back and forth (every
// iteration is a real incremental update), `BM_Full_<case>` rebuilds the scene from
// scratch. The reporter prints update/full time ratios at the end. `BM_TclValue` times one
// re-evaluation of a SLIDE value only Tcl can compute.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <fmt/format.h>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "backend/session.h"
#include "frontend/check/check.h"

namespace {

using nomec::backend::PipelineOptions;
using nomec::backend::Session;
using nomec::backend::SessionOptions;

std::string read_example(const std::string& name) {
  std::ifstream in(std::string(NOMEC_SOURCE_DIR) + "/examples/" + name, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

enum class Layout { Flat, Group, Block };

// 240 funnels on a 16 x 15 grid; the first one's x is the slider `s.x`. Flat: 240
// top-level instances (240 output meshes); Group: one group instanced once (one output
// mesh); Block: the same inside a level-2 subdivision block.
std::string generated_scene(Layout layout) {
  std::string s = "bank s\n  set x 0 -1 1 0.1\nendbank\nfunnel f (8 0.4 0.3 0.3) endfunnel\n";
  if (layout == Layout::Group) s += "group field\n";
  if (layout == Layout::Block) s += "subdivision field type NOME_SD_CC_sharp subdivisions 2\n";
  for (int i = 0; i < 240; ++i) {
    std::string x = i == 0 ? "{expr $s_x}" : fmt::format("{}", (i % 16) * 3);
    s += fmt::format("  instance i{} f translate ({} {} 0) endinstance\n", i, x, (i / 16) * 3);
  }
  if (layout == Layout::Group) s += "endgroup\ninstance all field endinstance\n";
  if (layout == Layout::Block) s += "endsubdivision\ninstance all field endinstance\n";
  return s;
}

// The funnel cube with `fun1` on a slider of its own (`fp.z1`).
std::string one_funnel_cube() {
  std::string s = read_example("funnel_cube.nome");
  s.replace(s.find("endbank"), 7, "    set     z1      -0.8    -1.5     -0.1     0.1\nendbank");
  s.replace(s.find("instance fun1 fun translate (0 0 {expr $fp_z})"), 47,
            "instance fun1 fun translate (0 0 {expr $fp_z1})");
  return s;
}

struct Case {
  std::string text;
  PipelineOptions pipeline;
  std::string parameter;
  double a = 0, b = 0;  // the two values an update alternates between
};

PipelineOptions sd3_offset() {
  PipelineOptions p;
  p.is_merge = true;
  p.subdivide_levels = 3;
  p.offset_height = 0.02;
  return p;
}

std::map<std::string, Case> cases() {
  std::map<std::string, Case> c;
  c["FunnelCubeSd3Offset_z_all_six"] = {read_example("funnel_cube.nome"), sd3_offset(), "fp.z", -0.8, -0.7};
  c["FunnelCubeSd3Offset_n_generator"] = {read_example("funnel_cube.nome"), sd3_offset(), "fp.n", 8, 7};
  c["FunnelCubeSd3Offset_one_funnel"] = {one_funnel_cube(), sd3_offset(), "fp.z1", -0.8, -0.7};
  c["KleinBottle_t3_x"] = {read_example("klein_bottle.nome"), {}, "tp3.x", -2, -1.9};
  c["KleinBottle_tp1_h_generator"] = {read_example("klein_bottle.nome"), {}, "tp1.h", 1.5, 1.4};
  c["Generated240Flat_one_instance"] = {generated_scene(Layout::Flat), {}, "s.x", 0, 0.5};
  c["Generated240Group_one_instance"] = {generated_scene(Layout::Group), {}, "s.x", 0, 0.5};
  c["Generated240Sd2_one_instance"] = {generated_scene(Layout::Block), {}, "s.x", 0, 0.5};
  return c;
}

std::unique_ptr<Session> make_session(const Case& c) {
  nomec::SourceManager sources;
  nomec::DiagnosticEngine diags;
  nomec::CheckResult r = nomec::check_source(sources, "bench.nome", c.text, {}, diags);
  if (diags.error_count() > 0) return nullptr;
  SessionOptions o;
  o.pipeline = c.pipeline;
  return std::make_unique<Session>(std::move(r.module), o);
}

void BM_Full(benchmark::State& state, const Case& c) {
  auto s = make_session(c);
  if (!s) {
    state.SkipWithError("the scene does not check");
    return;
  }
  for (auto _ : state) {
    nomec::DiagnosticEngine d;
    s->build(d);
    benchmark::DoNotOptimize(s->outputs().data());
  }
}

void BM_Update(benchmark::State& state, const Case& c) {
  auto s = make_session(c);
  if (!s) {
    state.SkipWithError("the scene does not check");
    return;
  }
  nomec::DiagnosticEngine d;
  s->build(d);
  bool flip = false;
  int64_t generators = 0, instances = 0, ops = 0;
  for (auto _ : state) {
    nomec::backend::UpdateStats u = s->set_parameter(c.parameter, flip ? c.a : c.b, d);
    if (!u.ok()) {
      state.SkipWithError(u.error.c_str());
      return;
    }
    generators += u.generators_rerun;
    instances += u.instances_retransformed;
    ops += u.kernel_ops_rerun;
    flip = !flip;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["generators"] = static_cast<double>(generators) / n;
  state.counters["instances"] = static_cast<double>(instances) / n;
  state.counters["kernel_ops"] = static_cast<double>(ops) / n;
}

// One SLIDE value that only Tcl can compute (`lod {if …}`), re-evaluated through the
// module's Tcl evaluator: with the slider moved before each evaluation (the slider variable
// set, then the script run on the evaluator's thread), and with it unchanged.
void BM_TclValue(benchmark::State& state, bool move) {
  const std::string text = R"(tclinit {
  package require slideui
  set par_numS 2
  scale .n -from 0 -to 4 -resolution 1 -variable par_numS
}
point p ({if {$par_numS >= 2} {expr $SLF_FULL} else {expr $SLF_OFF}} 0 0) endpoint
)";
  nomec::SourceManager sources;
  nomec::DiagnosticEngine diags;
  nomec::CheckResult r = nomec::check_source(sources, "bench.slf", text, {}, diags);
  nomec::ir::ExprId live = nomec::ir::ExprId::None();
  for (size_t i = 0; i < r.module.exprs.size(); ++i) {
    if (r.module.exprs[i].kind == nomec::ir::ExprKind::External) live = nomec::ir::ExprId(static_cast<int32_t>(i));
  }
  const nomec::ir::NodeId num = r.module.find_param("par", "numS");
  if (!live.is_valid() || !num.is_valid()) {
    state.SkipWithError("no Tcl value");
    return;
  }
  bool flip = false;
  for (auto _ : state) {
    if (move) r.module.param(num).value = flip ? 1 : 3;
    flip = !flip;
    nomec::ir::EvalResult v = nomec::ir::evaluate(r.module, live);
    if (!v.ok) {
      state.SkipWithError(v.problem.c_str());
      return;
    }
    benchmark::DoNotOptimize(v.value);
  }
}

class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& run : runs) {
      if (run.run_type == Run::RT_Iteration && !run.error_occurred) {
        times_[run.benchmark_name()] = run.GetAdjustedRealTime();
      }
    }
  }
  void Finalize() override {
    ConsoleReporter::Finalize();
    std::printf("\nupdate / full rebuild, same run (goals: <= 0.10 touching one instance, <= 0.50 "
                "re-subdividing part of the scene)\n");
    for (const auto& [name, update] : times_) {
      const std::string prefix = "BM_Update/";
      if (name.rfind(prefix, 0) != 0) continue;
      const std::string rest = name.substr(prefix.size());
      auto full = times_.find("BM_Full/" + rest);
      if (full == times_.end() || full->second <= 0) continue;
      std::printf("  %-36s ratio %.4f\n", rest.c_str(), update / full->second);
    }
  }

 private:
  std::map<std::string, double> times_;
};

}  // namespace

int main(int argc, char** argv) {
  static const std::map<std::string, Case> all = cases();
  for (const auto& [name, c] : all) {
    benchmark::RegisterBenchmark(("BM_Full/" + name).c_str(), BM_Full, c)->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("BM_Update/" + name).c_str(), BM_Update, c)->Unit(benchmark::kMillisecond);
  }
  benchmark::RegisterBenchmark("BM_TclValue/slider_moved", BM_TclValue, true)->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("BM_TclValue/slider_unchanged", BM_TclValue, false)->Unit(benchmark::kMicrosecond);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();
  return 0;
}
