// bench_frontend: parse + check throughput of the front end, and parse alone, on generated
// NOME 2016 scenes swept from 64 KiB to 4 MiB (banks, points with `{expr}` values, meshes
// with faces, funnels, groups and instances; every reference resolves, so the checker does
// its full work), plus the whole corpus as one realistic mix. Reports bytes/s.
// Keystroke benchmarks (issue 5): an editor's keystroke -> diagnostics through
// `check_source` with a `ParseCache` kept per document, over a ≥ 0.5 MB generated scene and
// over each corpus file: typing digits into a parameter value, typing inside a name, and
// inserting then deleting a whole statement; p50/p90 per keystroke are reported as counters
// (milliseconds). BM_KeystrokeParse times the same keystrokes' parse step alone. Before
// timing anything, main() checks that the generated scene has no errors.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <fmt/format.h>
#include <iostream>
#include <algorithm>
#include <chrono>
#include <map>
#include <string>
#include <vector>

#include "base/file_io.h"
#include "frontend/source/file_kinds.h"
#include "frontend/source/source_manager.h"
#include "frontend/check/check.h"
#include "frontend/index/index.h"
#include "bench/common/generated_scene.h"
#include "frontend/parse/parse.h"
#include "tools/allocator.h"

// The same allocator and options as `nomec` (see tools/allocator.h), so the figures are those
// of the program users run.
NOMEC_JEMALLOC_CONFIG();

namespace {

using nomec::bench::generate_scene;

const std::string& scene(size_t bytes) {
  static std::map<size_t, std::string> cache;
  auto it = cache.find(bytes);
  if (it == cache.end()) it = cache.emplace(bytes, generate_scene(bytes)).first;
  return it->second;
}

int check_errors(const std::string& text, std::string* first) {
  nomec::SourceManager sources;
  nomec::DiagnosticEngine diags;
  nomec::check_source(sources, "bench.nome", text, nomec::CheckOptions{}, diags);
  for (const auto& d : diags.diagnostics()) {
    if (d.severity != nomec::Severity::Note) {
      *first = nomec::render_text(sources, d, false, false);
      break;
    }
  }
  return diags.error_count() + diags.warning_count();
}

// Parse + check of the generated scene of `state.range(0)` bytes with `options`: MB/s, the
// file's size and the IR's nodes.
void run_parse_check(benchmark::State& state, const nomec::CheckOptions& options) {
  const std::string& text = scene(static_cast<size_t>(state.range(0)));
  size_t nodes = 0;
  for (auto _ : state) {
    nomec::SourceManager sources;
    nomec::DiagnosticEngine diags;
    nomec::CheckResult r = nomec::check_source(sources, "bench.nome", text, options, diags);
    nodes = r.module.nodes.size();
    benchmark::DoNotOptimize(nodes);
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(text.size()));
  state.counters["file_bytes"] = static_cast<double>(text.size());
  state.counters["ir_nodes"] = static_cast<double>(nodes);
}

void BM_ParseCheck(benchmark::State& state) { run_parse_check(state, nomec::CheckOptions{}); }

// The command line's check (CheckOptions::piece_bytes): the file parsed in pieces, each
// piece's tree freed, and the free memory given back, once its statements are checked.
// Against BM_ParseCheck in the same run: what the lower peak memory costs in time.
void BM_ParseCheckInPieces(benchmark::State& state) {
  nomec::CheckOptions options;
  options.piece_bytes = nomec::kCheckPieceBytes;
  run_parse_check(state, options);
}

// The fixed cost of one check (what each fuzzer input pays before its size matters): a
// one-statement file, a kilobyte of typical statements with a few mistakes, and that
// kilobyte with syntax errors.
void BM_CheckSmallFile(benchmark::State& state) {
  static const std::string kTiny = "point p (0 0 0) endpoint\n";
  static const std::string kKilobyte =
      "bank fp set n 8 3 16 1 set ro 0.4 0.1 1 0.1 endbank\n"
      "funnel fun ({expr $fp_n} {expr $fp_ro} -0.2 0.2) endfunnel\n"
      "point p1 (0 0 0) endpoint point p2 (1 0 0) endpoint point p3 (0 1 0) endpoint\n"
      "mesh m face f (p1 p2 p3) endface endmesh\n"
      "group g instance a fun translate (0 0 1) rotate (0 0 1) (90) endinstance\n"
      "  instance b m scale (2 2 2) endinstance endgroup\n"
      "instance top g endinstance\n"
      "torus t (1 0.3 360 0 360 12 8) endtorus\n"
      "circle c (1 16) endcircle\n"
      "funel typo (8 1 0 1) endfunel\n"
      "instance bad nothere endinstance\n"
      "point q (1 2) endpoint\n"
      "genparametricsurf s funcX [cos(u)*v] funcY [sin(u)*v] funcZ [v] (0 6.28 0 1 16 4) endgenparametricsurf\n"
      "subdivision sd type NOME_SD_CC subdivisions 1 instance i2 top endinstance endsubdivision\n";
  // The same kilobyte with syntax errors (an end keyword missing, a stray bracket): what
  // nearly every fuzzer input is, parsed a second time with error recovery.
  static const std::string kBroken = [] {
    std::string t = kKilobyte;
    t.replace(t.find("endpoint point p2"), 8, "");
    t.insert(t.find("circle c"), ") ");
    return t;
  }();
  const std::string& text = state.range(0) == 0 ? kTiny : state.range(0) == 1 ? kKilobyte : kBroken;
  for (auto _ : state) {
    nomec::SourceManager sources;
    nomec::DiagnosticEngine diags;
    nomec::CheckResult r = nomec::check_source(sources, "small.nome", text, nomec::CheckOptions{}, diags);
    benchmark::DoNotOptimize(r.module.nodes.size());
  }
  state.counters["file_bytes"] = static_cast<double>(text.size());
}

// A small SLIDE file (the front-end fuzzer's third kind of input): without Tcl, with one
// `{expr}` value, and with an (empty) `tclinit` block. The interpreter is made only when the
// file uses Tcl, so the first pays no interpreter; the difference is its cost.
void BM_CheckSmallSlideFile(benchmark::State& state) {
  static const std::string kTexts[] = {
      "sphere s radius 2 endsphere\ngroup g instance s endinstance endgroup\n",
      "sphere s radius {expr 2} endsphere\ngroup g instance s endinstance endgroup\n",
      "tclinit { }\nsphere s radius 2 endsphere\ngroup g instance s endinstance endgroup\n",
  };
  const std::string& text = kTexts[state.range(0)];
  for (auto _ : state) {
    nomec::SourceManager sources;
    nomec::DiagnosticEngine diags;
    nomec::CheckResult r = nomec::check_source(sources, "small.slf", text, nomec::CheckOptions{}, diags);
    benchmark::DoNotOptimize(r.module.nodes.size());
  }
}
BENCHMARK(BM_CheckSmallSlideFile)->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);

// Second argument: 1 parses on one thread, 2 on two (a large text is cut in two and the
// halves parsed at once), 0 as `parse_file` chooses (two threads from 128 KiB).
void BM_ParseOnly(benchmark::State& state) {
  const std::string& text = scene(static_cast<size_t>(state.range(0)));
  const nomec::ParseThreads threads = state.range(1) == 1   ? nomec::ParseThreads::One
                                      : state.range(1) == 2 ? nomec::ParseThreads::Two
                                                            : nomec::ParseThreads::Automatic;
  size_t stmts = 0;
  for (auto _ : state) {
    nomec::SourceManager sources;
    nomec::DiagnosticEngine diags;
    nomec::FileId f = sources.add_file("bench.nome", text);
    nomec::ast::Ast ast = nomec::parse_file(sources, f, diags, threads);
    stmts = ast.stmts.size();
    benchmark::DoNotOptimize(stmts);
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(text.size()));
  state.counters["file_bytes"] = static_cast<double>(text.size());
  state.counters["statements"] = static_cast<double>(stmts);
}

nomec::CheckOptions corpus_options() {
  nomec::CheckOptions options;
  options.read_file = nomec::read_file_bytes;
  options.list_folder = nomec::list_folder;
  return options;
}

struct CorpusFile {
  std::string path, text;
};

const std::vector<CorpusFile>& corpus_files() {
  static const std::vector<CorpusFile> files = [] {
    std::vector<CorpusFile> v;
    std::error_code ec;
    for (const char* folder : {"nome1", "nome3", "slide"}) {
      for (const auto& e : std::filesystem::recursive_directory_iterator(
               std::filesystem::path(NOMEC_CORPUS_DIR) / folder, ec)) {
        if (!e.is_regular_file() || !nomec::is_scene_path(e.path().string())) continue;
        v.push_back({e.path().string(), nomec::read_file_bytes(e.path().string()).value()});
      }
    }
    std::sort(v.begin(), v.end(), [](const CorpusFile& a, const CorpusFile& b) { return a.path < b.path; });
    return v;
  }();
  return files;
}

// Every corpus file (except `.sif` meshes) checked once per iteration: real files with
// their real mix of dialects, Tcl blocks and errors.
void BM_ParseCheckCorpus(benchmark::State& state) {
  const std::vector<CorpusFile>& inputs = corpus_files();
  int64_t bytes = 0;
  for (const CorpusFile& in : inputs) bytes += static_cast<int64_t>(in.text.size());
  nomec::CheckOptions options = corpus_options();
  for (auto _ : state) {
    for (const CorpusFile& in : inputs) {
      nomec::SourceManager sources;
      nomec::DiagnosticEngine diags;
      nomec::CheckResult r = nomec::check_source(sources, in.path, in.text, options, diags);
      benchmark::DoNotOptimize(r.module.nodes.size());
    }
  }
  state.SetBytesProcessed(state.iterations() * bytes);
  state.counters["files"] = static_cast<double>(inputs.size());
  state.counters["corpus_bytes"] = static_cast<double>(bytes);
}

// The language index (frontend/index): building it from a check result recorded with
// `record_names` (what the LSP adds per keystroke on top of parse + check), and the
// per-request features on the same file.
void BM_IndexBuild(benchmark::State& state) {
  const std::string& text = scene(static_cast<size_t>(state.range(0)));
  auto sources = std::make_shared<nomec::SourceManager>();
  nomec::DiagnosticEngine diags;
  nomec::CheckOptions options;
  options.record_names = true;
  auto check = std::make_shared<const nomec::CheckResult>(nomec::check_source(*sources, "bench.nome", text, options, diags));
  size_t symbols = 0;
  for (auto _ : state) {
    auto ix = nomec::index::build(sources, check);
    symbols = ix->symbols().size();
    benchmark::DoNotOptimize(symbols);
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(text.size()));
  state.counters["file_bytes"] = static_cast<double>(text.size());
  state.counters["symbols"] = static_cast<double>(symbols);
}

void BM_IndexFeatures(benchmark::State& state) {
  const std::string& text = scene(static_cast<size_t>(state.range(0)));
  nomec::DiagnosticEngine diags;
  nomec::index::Analysis a = nomec::index::analyze("bench.nome", text, nomec::CheckOptions{}, diags);
  const nomec::index::Index& ix = *a.index;
  auto mid = static_cast<uint32_t>(text.find("$b", text.size() / 2) + 2);
  auto end = static_cast<uint32_t>(text.size());
  for (auto _ : state) {
    switch (state.range(1)) {
      case 0: benchmark::DoNotOptimize(ix.hover(a.file, mid)); break;
      case 1: benchmark::DoNotOptimize(ix.semantic_tokens(a.file).size()); break;
      case 2: benchmark::DoNotOptimize(ix.complete(a.file, end).size()); break;
      case 3: benchmark::DoNotOptimize(ix.folding_ranges(a.file).size()); break;
      default: benchmark::DoNotOptimize(ix.references(ix.occurrence_at(a.file, mid)->symbol, true).size()); break;
    }
  }
  static const char* names[] = {"hover", "semantic_tokens", "complete", "folding_ranges", "references"};
  state.SetLabel(names[state.range(1)]);
}

BENCHMARK(BM_IndexBuild)->Arg(64 << 10)->Arg(512 << 10)->Arg(4 << 20)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_IndexFeatures)->ArgsProduct({{512 << 10}, {0, 1, 2, 3, 4}})->Unit(benchmark::kMillisecond);
// ---------------------------------------------------------------------------------------
// Keystrokes: a scripted editing session over one document. Each step is the document's
// full text after one keystroke; the session types a digit into a parameter value, types
// a name character by character, and inserts and deletes a whole statement (paste/undo).
std::vector<std::string> keystrokes(const std::string& text) {
  std::vector<std::string> steps;
  std::string cur = text;
  // 1. Typing into a number near the middle: append digits, then delete them again.
  size_t mid = text.size() / 2;
  size_t num = cur.find_first_of("0123456789", mid);
  if (num == std::string::npos) num = cur.find_first_of("0123456789");
  if (num != std::string::npos) {
    size_t end = cur.find_first_not_of("0123456789.", num);
    if (end == std::string::npos) end = cur.size();
    for (char d : std::string("2571")) {
      cur.insert(end++, 1, d);
      steps.push_back(cur);
    }
    for (int k = 0; k < 4; ++k) {
      cur.erase(--end, 1);
      steps.push_back(cur);
    }
  }
  // 2. Typing inside a name at a quarter of the file (the name becomes unknown, then known).
  size_t at = cur.find(' ', cur.size() / 4);
  if (at != std::string::npos) {
    size_t name = cur.find_first_of("abcdefghijklmnopqrstuvwxyz", at);
    if (name != std::string::npos) {
      for (char c : std::string("xyz")) {
        cur.insert(name + 1, 1, c);
        steps.push_back(cur);
        cur.erase(name + 1, 1);
        steps.push_back(cur);
      }
    }
  }
  // 3. Pasting a statement at a line start at three quarters, then undoing it.
  size_t line = cur.find('\n', cur.size() * 3 / 4);
  if (line != std::string::npos) {
    std::string stmt = "point pasted (1 2 3) endpoint\n";
    cur.insert(line + 1, stmt);
    steps.push_back(cur);
    cur.erase(line + 1, stmt.size());
    steps.push_back(cur);
  }
  return steps;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  size_t k = std::min(v.size() - 1, static_cast<size_t>(p * static_cast<double>(v.size() - 1) + 0.5));
  return v[k];
}

// Times each keystroke of `steps` (check_source through one cache, as the server does) and
// records every latency in `out` (milliseconds).
void run_session(const std::string& path, const std::string& text,
                 const std::vector<std::string>& steps, const nomec::CheckOptions& options,
                 std::vector<double>& out) {
  nomec::ParseCache cache;
  {
    nomec::SourceManager sources;
    nomec::DiagnosticEngine diags;
    nomec::check_source(sources, path, text, options, diags, &cache);  // didOpen
  }
  for (const std::string& step : steps) {
    auto t0 = std::chrono::steady_clock::now();
    nomec::SourceManager sources;
    nomec::DiagnosticEngine diags;
    nomec::CheckResult r = nomec::check_source(sources, path, step, options, diags, &cache);
    diags.sort_and_dedupe();
    benchmark::DoNotOptimize(r.module.nodes.size());
    auto t1 = std::chrono::steady_clock::now();
    out.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
  }
}

void report(benchmark::State& state, const std::vector<double>& ms) {
  state.counters["p50_ms"] = percentile(ms, 0.5);
  state.counters["p90_ms"] = percentile(ms, 0.9);
  state.counters["max_ms"] = ms.empty() ? 0 : *std::max_element(ms.begin(), ms.end());
  state.counters["keystrokes"] = static_cast<double>(ms.size());
}

// Keystroke -> diagnostics on the generated scene of range(0) bytes.
void BM_Keystroke(benchmark::State& state) {
  const std::string& text = scene(static_cast<size_t>(state.range(0)));
  std::vector<std::string> steps = keystrokes(text);
  std::vector<double> ms;
  for (auto _ : state) {
    std::vector<double> session;
    auto t0 = std::chrono::steady_clock::now();
    run_session("bench.nome", text, steps, nomec::CheckOptions{}, session);
    auto t1 = std::chrono::steady_clock::now();
    state.SetIterationTime(std::chrono::duration<double>(t1 - t0).count() /
                           static_cast<double>(steps.size()));
    ms.insert(ms.end(), session.begin(), session.end());
  }
  report(state, ms);
  state.counters["file_bytes"] = static_cast<double>(text.size());
}

// The parse step alone of each keystroke (ParseCache::parse, as the server calls it after
// an edit) on the generated scene of range(0) bytes; the AST is freed outside the timing.
void BM_KeystrokeParse(benchmark::State& state) {
  const std::string& text = scene(static_cast<size_t>(state.range(0)));
  std::vector<std::string> steps = keystrokes(text);
  std::vector<double> ms;
  std::vector<double> fill_ms;
  for (auto _ : state) {
    nomec::ParseCache cache;
    {
      nomec::SourceManager sources;
      nomec::DiagnosticEngine diags;
      nomec::FileId f = sources.add_file("bench.nome", text);
      auto t0 = std::chrono::steady_clock::now();
      nomec::ast::Ast open = cache.parse(sources, f, diags);  // filling the cache after didOpen
      fill_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    double total = 0;
    for (const std::string& step : steps) {
      nomec::SourceManager sources;
      nomec::DiagnosticEngine diags;
      nomec::FileId f = sources.add_file("bench.nome", step);
      auto t0 = std::chrono::steady_clock::now();
      nomec::ast::Ast a = cache.parse(sources, f, diags);
      auto t1 = std::chrono::steady_clock::now();
      benchmark::DoNotOptimize(a.stmts.size());
      double t = std::chrono::duration<double, std::milli>(t1 - t0).count();
      ms.push_back(t);
      total += t;
    }
    state.SetIterationTime(total / 1000.0 / static_cast<double>(steps.size()));
  }
  report(state, ms);
  std::sort(fill_ms.begin(), fill_ms.end());
  state.counters["fill_p50_ms"] = fill_ms[fill_ms.size() / 2];
  state.counters["file_bytes"] = static_cast<double>(text.size());
}

// Keystroke -> diagnostics over every corpus file (one session per file); the counters
// pool every keystroke of every file.
void BM_KeystrokeCorpus(benchmark::State& state) {
  nomec::CheckOptions options = corpus_options();
  std::vector<std::vector<std::string>> steps;
  size_t total = 0;
  for (const CorpusFile& f : corpus_files()) {
    steps.push_back(keystrokes(f.text));
    total += steps.back().size();
  }
  std::vector<double> ms;
  for (auto _ : state) {
    auto t0 = std::chrono::steady_clock::now();
    for (size_t k = 0; k < corpus_files().size(); ++k) {
      run_session(corpus_files()[k].path, corpus_files()[k].text, steps[k], options, ms);
    }
    auto t1 = std::chrono::steady_clock::now();
    state.SetIterationTime(std::chrono::duration<double>(t1 - t0).count() /
                           static_cast<double>(std::max<size_t>(1, total)));
  }
  report(state, ms);
  state.counters["files"] = static_cast<double>(corpus_files().size());
}

// The largest corpus file alone, for the worst real case.
void BM_KeystrokeLargestCorpusFile(benchmark::State& state) {
  const auto& files = corpus_files();
  if (files.empty()) {
    state.SkipWithError("no corpus files");
    return;
  }
  const CorpusFile& f = *std::max_element(files.begin(), files.end(), [](const auto& a, const auto& b) {
    return a.text.size() < b.text.size();
  });
  std::vector<std::string> steps = keystrokes(f.text);
  std::vector<double> ms;
  nomec::CheckOptions options = corpus_options();
  for (auto _ : state) {
    auto t0 = std::chrono::steady_clock::now();
    run_session(f.path, f.text, steps, options, ms);
    auto t1 = std::chrono::steady_clock::now();
    state.SetIterationTime(std::chrono::duration<double>(t1 - t0).count() / static_cast<double>(steps.size()));
  }
  report(state, ms);
  state.counters["file_bytes"] = static_cast<double>(f.text.size());
}

BENCHMARK(BM_Keystroke)->Arg(64 << 10)->Arg(512 << 10)->Arg(1 << 20)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_KeystrokeParse)->Arg(512 << 10)->Arg(1 << 20)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_KeystrokeCorpus)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_KeystrokeLargestCorpusFile)->UseManualTime()->Unit(benchmark::kMillisecond);
// A document's first parse in the editor: a new ParseCache parses every chunk (one
// top-level statement each) and assembles them, on range(1) threads (1 or 2), against
// BM_ParseOnly's one piece.
void BM_FirstCacheParse(benchmark::State& state) {
  const std::string& text = scene(static_cast<size_t>(state.range(0)));
  const nomec::ParseThreads threads = state.range(1) == 1 ? nomec::ParseThreads::One : nomec::ParseThreads::Two;
  size_t pieces = 0;
  for (auto _ : state) {
    nomec::ParseCache cache(threads);
    nomec::SourceManager sources;
    nomec::DiagnosticEngine diags;
    nomec::FileId f = sources.add_file("bench.nome", text);
    nomec::ast::Ast ast = cache.parse(sources, f, diags);
    pieces = cache.last_stats().pieces;
    benchmark::DoNotOptimize(ast.stmts.size());
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(text.size()));
  state.counters["pieces"] = static_cast<double>(pieces);
}
BENCHMARK(BM_FirstCacheParse)->Args({1 << 20, 1})->Args({1 << 20, 2})->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();

// Wall time (bytes per second from it) and the whole process's CPU time: a large text is
// parsed on two threads.
BENCHMARK(BM_ParseCheck)->Arg(64 << 10)->Arg(512 << 10)->Arg(256 << 10)->Arg(1 << 20)->Arg(4 << 20)->Unit(benchmark::kMillisecond)
    ->UseRealTime()->MeasureProcessCPUTime();
BENCHMARK(BM_ParseCheckInPieces)->Arg(1 << 20)->Arg(4 << 20)->Unit(benchmark::kMillisecond)->UseRealTime()
    ->MeasureProcessCPUTime();
BENCHMARK(BM_ParseOnly)
    ->ArgsProduct({{64 << 10, 256 << 10, 512 << 10, 1 << 20, 4 << 20}, {0}})
    ->Args({1 << 20, 1})
    ->Args({1 << 20, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MeasureProcessCPUTime();
BENCHMARK(BM_ParseCheckCorpus)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CheckSmallFile)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond);

}  // namespace

int main(int argc, char** argv) {
  // The generated scene must be valid, or the checker would stop doing real work early.
  std::string first;
  if (int problems = check_errors(scene(64 << 10), &first); problems > 0) {
    std::cerr << "bench_frontend: the generated scene has " << problems
              << " errors/warnings; the first:\n" << first;
    return 1;
  }
  benchmark::Initialize(&argc, argv);
  benchmark::AddCustomContext("allocator", std::string(nomec::allocator_name()));
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
