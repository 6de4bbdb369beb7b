// bench_lsp: what a sculptor feels in the editor (issue 5), measured through the in-process
// language server (`nomec::lsp::Server`, debounce 0, background geometry off). Each
// keystroke is one `textDocument/didChange` with a one-character incremental edit — digits
// typed into a parameter value and deleted again, then characters typed into a name and
// deleted again — and is timed from `handle()` until its first `publishDiagnostics` was
// sent: those of an incremental check of the statements the edit touched (frontend/check/
// incremental.h) when the server could make one, else those of the full check (parse
// through the document's ParseCache, check, diagnostics to JSON, sink; the index is built
// afterwards). key_incremental_share, key_incremental_p50_ms and key_incremental_checked_p50
// say how many keystrokes were published incrementally, their CPU time and the statements
// checked; NOMEC_BENCH_LSP_INCREMENTAL=0 turns incremental checks off for comparison. Hover is timed from the request to its response on a checked document.
// Inputs: the generated scene of bench/common (64 KiB, 512 KiB, 1 MiB) and every corpus
// file. Counters: diag_p50_ms, diag_p90_ms, diag_max_ms, diag_cpu_p50_ms (process CPU time
// per keystroke, all threads), hover_p50_ms, and open_p50_ms (didOpen -> diagnostics, the
// text parsed in one piece) in milliseconds; and where the server says the time went
// (open_* and key_*_p50_ms, Server::analysis_times: thread CPU time per step). With
// NOMEC_BENCH_LSP_ROUNDS=N (N >= 2) the session is typed N times after one didOpen, and
// diag_p50_later_ms / diag_p90_later_ms give the keystrokes of the rounds after the first:
// the first round's keystrokes share the cores with what follows didOpen (the parse cache's
// fill, the first index), the later ones do not.
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <time.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "base/file_io.h"
#include "frontend/source/file_kinds.h"
#include "frontend/source/source_manager.h"
#include "bench/common/generated_scene.h"
#include "lsp/server.h"
#include "tools/allocator.h"

// The same allocator options as `nomec` (see tools/allocator.h).
NOMEC_JEMALLOC_CONFIG();

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// CPU time of the whole process (every server thread), in milliseconds: on a shared,
// loaded machine it shows the work a keystroke costs apart from waiting for a core.
double process_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) / 1e6;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  size_t k = std::min(v.size() - 1, static_cast<size_t>(p * static_cast<double>(v.size() - 1) + 0.5));
  return v[k];
}

// A JSON string literal (the texts are ASCII NOME; escape what JSON requires).
std::string quote(std::string_view s) {
  std::string out = "\"";
  for (char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          out += fmt::format("\\u{:04x}", static_cast<unsigned>(c));
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

// An LSP position of a byte offset (the texts are ASCII, so UTF-16 = bytes).
struct Pos {
  size_t line = 0, character = 0;
};
Pos position(const std::string& text, size_t offset) {
  Pos p;
  size_t line_start = 0;
  for (size_t i = 0; i < offset; ++i) {
    if (text[i] == '\n') {
      ++p.line;
      line_start = i + 1;
    }
  }
  p.character = offset - line_start;
  return p;
}

// One edit: insert `text` at `offset`, or delete one character there when `text` is empty.
struct Edit {
  size_t offset = 0;
  std::string text;
};

// The session: four digits typed after a number near the middle and deleted again, then
// three characters typed after the first letter of a name at a quarter, each deleted again.
std::vector<Edit> session(const std::string& text) {
  std::vector<Edit> edits;
  size_t num = text.find_first_of("0123456789", text.size() / 2);
  while (num != std::string::npos && num > 0 &&
         (std::isalpha(static_cast<unsigned char>(text[num - 1])) || text[num - 1] == '_')) {
    num = text.find_first_of("0123456789", text.find_first_not_of("0123456789", num));
  }
  if (num != std::string::npos) {
    size_t end = text.find_first_not_of("0123456789.", num);
    if (end == std::string::npos) end = text.size();
    for (char d : std::string("2571")) edits.push_back({end++, std::string(1, d)});
    for (int k = 0; k < 4; ++k) edits.push_back({--end, ""});
  }
  size_t at = text.find(' ', text.size() / 4);
  size_t name = at == std::string::npos ? at : text.find_first_of("abcdefghijklmnopqrstuvwxyz", at);
  if (name != std::string::npos) {
    for (char c : std::string("xyz")) {
      edits.push_back({name + 1, std::string(1, c)});
      edits.push_back({name + 1, ""});
    }
  }
  return edits;
}

// Names worth hovering: the first letters of identifiers after spaces, spread over the file.
std::vector<size_t> hover_offsets(const std::string& text, int count) {
  std::vector<size_t> out;
  for (int k = 0; k < count; ++k) {
    size_t at = text.find(' ', text.size() * static_cast<size_t>(k) / static_cast<size_t>(count));
    if (at == std::string::npos) continue;
    size_t name = text.find_first_of("abcdefghijklmnopqrstuvwxyz", at);
    if (name != std::string::npos) out.push_back(name);
  }
  return out;
}

// An in-process server with a sink that remembers which responses arrived.
class Session {
 public:
  Session()
      : server_([this](std::string m) { receive(std::move(m)); }, [] {
          nomec::lsp::ServerOptions o;
          o.debounce_ms = 0;
          o.geometry = false;
          // NOMEC_BENCH_LSP_INCREMENTAL=0: every keystroke checked in full, for comparison.
          const char* incremental = std::getenv("NOMEC_BENCH_LSP_INCREMENTAL");
          o.incremental = incremental == nullptr || std::string_view(incremental) != "0";
          return o;
        }()) {
    request("initialize", R"({"processId":null,"rootUri":null,"capabilities":{}})");
    server_.handle(R"({"jsonrpc":"2.0","method":"initialized","params":{}})");
  }

  // Sends a request and waits for its response; returns the milliseconds it took.
  double request(const std::string& method, const std::string& params) {
    int id = next_id_++;
    auto t0 = Clock::now();
    server_.handle(fmt::format(R"({{"jsonrpc":"2.0","id":{},"method":"{}","params":{}}})", id, method, params));
    std::unique_lock lock(mu_);
    cv_.wait(lock, [&] { return answered_ >= id; });
    return ms_since(t0);
  }
  void notify(const std::string& method, const std::string& params) {
    server_.handle(fmt::format(R"({{"jsonrpc":"2.0","method":"{}","params":{}}})", method, params));
  }
  void handle(const std::string& message) { server_.handle(message); }
  bool wait_diagnostics(const std::string& uri, int64_t version) {
    return server_.wait_for_diagnostics(uri, version, std::chrono::seconds(60));
  }
  // What the editor shows first: an incremental check's diagnostics, when the server made one.
  bool wait_first_diagnostics(const std::string& uri, int64_t version) {
    return server_.wait_for_first_diagnostics(uri, version, std::chrono::seconds(60));
  }
  nomec::lsp::AnalysisTimes times(const std::string& uri) const {
    return server_.analysis_times(uri).value_or(nomec::lsp::AnalysisTimes{});
  }

 private:
  void receive(std::string m) {
    // Responses carry "id" and no "method"; requests are answered in order.
    if (m.find("\"method\"") != std::string::npos) return;
    size_t at = m.find("\"id\":");
    if (at == std::string::npos) return;
    int id = std::atoi(m.c_str() + at + 5);
    {
      std::lock_guard lock(mu_);
      answered_ = std::max(answered_, id);
    }
    cv_.notify_all();
  }

  std::mutex mu_;
  std::condition_variable cv_;
  int answered_ = 0;
  int next_id_ = 1;
  nomec::lsp::Server server_;  // last: destroyed first
};

// Where the server says the time went (Server::analysis_times), per phase, for didOpen and
// for the keystrokes.
struct Phases {
  std::vector<double> parse, check, diagnostics, publish, index, incremental, incremental_checked;
  void add(const nomec::lsp::AnalysisTimes& t) {
    if (t.incremental_ms > 0) {  // published from an incremental check; its full check follows
      incremental.push_back(t.incremental_ms);
      incremental_checked.push_back(static_cast<double>(t.incremental_checked));
      return;
    }
    parse.push_back(t.parse_ms);
    check.push_back(t.check_ms);
    diagnostics.push_back(t.diagnostics_ms);
    publish.push_back(t.publish_ms);
  }
};

// Runs the keystroke session over `text` (as document `uri`) and then hovers; appends the
// latencies in milliseconds.
void run(const std::string& uri, const std::string& original, std::vector<double>& open_ms,
         std::vector<double>& diag_ms, std::vector<double>& later_ms, std::vector<double>& cpu_ms,
         std::vector<double>& hover_ms, Phases& open_phases, Phases& key_phases) {
  Session s;
  std::string text = original;
  int64_t version = 1;
  auto t_open = Clock::now();
  s.notify("textDocument/didOpen",
           fmt::format(R"({{"textDocument":{{"uri":"{}","languageId":"nome","version":1,"text":{}}}}})", uri,
                       quote(text)));
  if (!s.wait_diagnostics(uri, version)) throw std::runtime_error("no diagnostics after didOpen");
  open_ms.push_back(ms_since(t_open));
  open_phases.add(s.times(uri));
  // The session leaves the text as it found it, so it can be replayed (for profiling the
  // keystrokes rather than didOpen: NOMEC_BENCH_LSP_ROUNDS=20).
  const char* rounds_env = std::getenv("NOMEC_BENCH_LSP_ROUNDS");
  const int rounds = rounds_env != nullptr ? std::max(1, std::atoi(rounds_env)) : 1;
  std::vector<Edit> edits;
  size_t first_round = 0;  // keystrokes in the first round
  for (int r = 0; r < rounds; ++r) {
    std::vector<Edit> one = session(original);
    if (r == 0) first_round = one.size();
    edits.insert(edits.end(), one.begin(), one.end());
  }
  for (size_t k = 0; k < edits.size(); ++k) {
    const Edit& e = edits[k];
    Pos b = position(text, e.offset);
    Pos end = e.text.empty() ? Pos{b.line, b.character + 1} : b;
    std::string msg = fmt::format(
        R"({{"jsonrpc":"2.0","method":"textDocument/didChange","params":{{"textDocument":{{"uri":"{}","version":{}}},)"
        R"("contentChanges":[{{"range":{{"start":{{"line":{},"character":{}}},"end":{{"line":{},"character":{}}}}},"text":{}}}]}}}})",
        uri, ++version, b.line, b.character, end.line, end.character, quote(e.text));
    if (e.text.empty()) {
      text.erase(e.offset, 1);
    } else {
      text.insert(e.offset, e.text);
    }
    // The index of the version before, built after its diagnostics were published (if the
    // background thread got to it before this keystroke).
    if (double index_ms = s.times(uri).index_ms; index_ms > 0) key_phases.index.push_back(index_ms);
    double cpu0 = process_cpu_ms();
    auto t0 = Clock::now();
    s.handle(msg);
    if (!s.wait_first_diagnostics(uri, version)) throw std::runtime_error("no diagnostics after didChange");
    diag_ms.push_back(ms_since(t0));
    if (k >= first_round) later_ms.push_back(diag_ms.back());
    cpu_ms.push_back(process_cpu_ms() - cpu0);
    key_phases.add(s.times(uri));
    if (std::getenv("NOMEC_BENCH_LSP_VERBOSE") != nullptr) {
      const nomec::lsp::AnalysisTimes t = s.times(uri);
      fmt::print(stderr,
                 "keystroke {:>3} `{}` at {}: {:.1f} ms (cpu {:.1f}): incremental {:.1f} ({} statements) or parse {:.1f} "
                 "check {:.1f} diagnostics {:.1f}\n",
                 version, e.text.empty() ? "<del>" : e.text, e.offset, diag_ms.back(), cpu_ms.back(), t.incremental_ms,
                 t.incremental_checked, t.parse_ms, t.check_ms, t.diagnostics_ms);
    }
  }
  for (size_t off : hover_offsets(text, 20)) {
    Pos p = position(text, off);
    hover_ms.push_back(s.request(
        "textDocument/hover",
        fmt::format(R"({{"textDocument":{{"uri":"{}"}},"position":{{"line":{},"character":{}}}}})", uri, p.line,
                    p.character)));
  }
}

void report(benchmark::State& state, const std::vector<double>& open_ms, const std::vector<double>& diag_ms,
            const std::vector<double>& later_ms, const std::vector<double>& cpu_ms, const std::vector<double>& hover_ms,
            const Phases& open_phases, const Phases& key_phases, size_t bytes) {
  state.counters["open_parse_ms"] = percentile(open_phases.parse, 0.5);
  state.counters["open_check_ms"] = percentile(open_phases.check, 0.5);
  state.counters["open_diags_ms"] = percentile(open_phases.diagnostics, 0.5);
  state.counters["key_parse_p50_ms"] = percentile(key_phases.parse, 0.5);
  state.counters["key_check_p50_ms"] = percentile(key_phases.check, 0.5);
  state.counters["key_diags_p50_ms"] = percentile(key_phases.diagnostics, 0.5);
  state.counters["key_index_p50_ms"] = percentile(key_phases.index, 0.5);
  // Keystrokes published from an incremental check: their share, CPU time and statements checked.
  const size_t keys = key_phases.incremental.size() + key_phases.check.size();
  state.counters["key_incremental_share"] =
      keys == 0 ? 0 : static_cast<double>(key_phases.incremental.size()) / static_cast<double>(keys);
  state.counters["key_incremental_p50_ms"] = percentile(key_phases.incremental, 0.5);
  state.counters["key_incremental_checked_p50"] = percentile(key_phases.incremental_checked, 0.5);
  state.counters["open_p50_ms"] = percentile(open_ms, 0.5);
  state.counters["diag_p50_ms"] = percentile(diag_ms, 0.5);
  state.counters["diag_p90_ms"] = percentile(diag_ms, 0.9);
  if (!later_ms.empty()) {
    state.counters["diag_p50_later_ms"] = percentile(later_ms, 0.5);
    state.counters["diag_p90_later_ms"] = percentile(later_ms, 0.9);
  }
  state.counters["diag_max_ms"] = diag_ms.empty() ? 0 : *std::max_element(diag_ms.begin(), diag_ms.end());
  state.counters["diag_cpu_p50_ms"] = percentile(cpu_ms, 0.5);
  state.counters["hover_p50_ms"] = percentile(hover_ms, 0.5);
  state.counters["keystrokes"] = static_cast<double>(diag_ms.size());
  state.counters["file_bytes"] = static_cast<double>(bytes);
}

// One session per iteration; the iteration time is the mean keystroke latency.
void measure(benchmark::State& state, const std::string& uri, const std::string& text) {
  std::vector<double> open_ms, diag_ms, later_ms, cpu_ms, hover_ms;
  Phases open_phases, key_phases;
  for (auto _ : state) {
    size_t before = diag_ms.size();
    try {
      run(uri, text, open_ms, diag_ms, later_ms, cpu_ms, hover_ms, open_phases, key_phases);
    } catch (const std::exception& e) {
      state.SkipWithError(e.what());
      return;
    }
    double sum = 0;
    for (size_t k = before; k < diag_ms.size(); ++k) sum += diag_ms[k];
    state.SetIterationTime(sum / 1000.0 / static_cast<double>(std::max<size_t>(1, diag_ms.size() - before)));
  }
  report(state, open_ms, diag_ms, later_ms, cpu_ms, hover_ms, open_phases, key_phases, text.size());
}

// The generated scene of range(0) bytes.
void BM_LspKeystroke(benchmark::State& state) {
  static std::map<int64_t, std::string> scenes;
  auto it = scenes.find(state.range(0));
  if (it == scenes.end()) {
    it = scenes.emplace(state.range(0), nomec::bench::generate_scene(static_cast<size_t>(state.range(0)))).first;
  }
  measure(state, "file:///tmp/bench_lsp/scene.nome", it->second);
}
BENCHMARK(BM_LspKeystroke)->Arg(64 << 10)->Arg(512 << 10)->Arg(1 << 20)->UseManualTime()->Unit(benchmark::kMillisecond);

std::string read_file(const std::filesystem::path& p) { return nomec::read_file_bytes(p.string()).value(); }

// One benchmark per corpus file, `BM_LspKeystrokeCorpus/<path under the corpus>`; its URI is
// the file's real path so includes and `.anom` bases resolve as in the editor.
void register_corpus() {
  std::error_code ec;
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::recursive_directory_iterator(NOMEC_CORPUS_DIR, ec)) {
    if (e.is_regular_file() && nomec::is_scene_path(e.path().string())) files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  for (const auto& f : files) {
    std::string name = "BM_LspKeystrokeCorpus/" + std::filesystem::relative(f, NOMEC_CORPUS_DIR).string();
    std::string uri = "file://" + std::filesystem::absolute(f).string();
    benchmark::RegisterBenchmark(name.c_str(), [uri, path = f](benchmark::State& state) {
      measure(state, uri, read_file(path));
    })->UseManualTime()->Unit(benchmark::kMillisecond);
  }
}

}  // namespace

int main(int argc, char** argv) {
  register_corpus();
  benchmark::AddCustomContext("allocator", std::string(nomec::allocator_name()));
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
