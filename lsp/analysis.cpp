// Checking one document version for the language server (the same `check_source` as
// `nomec --check`), turning its diagnostics into LSP form, and the background scene
// evaluation that yields geometry diagnostics and per-node geometry facts for hover.
#include <chrono>
#include <fstream>
#include <sstream>

#include "base/file_io.h"
#include "base/read_beneath.h"
#include "backend/evaluate.h"
#include "backend/summary.h"
#include "lsp/server_impl.h"

namespace nomec::lsp {

namespace {

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

int lsp_severity(Severity s) {
  switch (s) {
    case Severity::Error: return 1;
    case Severity::Warning: return 2;
    case Severity::Note: return 3;
  }
  return 3;
}

// How a text of `bytes` was just parsed: through `cache`, or in one piece without one.
ParseStats parse_stats_of(const ParseCache* cache, size_t bytes) {
  if (cache == nullptr) return {1, 1, bytes};
  const ParseCache::Stats& s = cache->last_stats();
  return {s.pieces, s.parsed, s.parsed_bytes};
}

}  // namespace

std::string path_to_uri(std::string_view path) {
  static const char* kHex = "0123456789ABCDEF";
  std::string out = "file://";
  for (unsigned char c : path) {
    if (std::isalnum(c) || c == '/' || c == '-' || c == '_' || c == '.' || c == '~') {
      out += static_cast<char>(c);
    } else {
      out += '%';
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  return out;
}

std::optional<std::string> uri_to_path(std::string_view uri) {
  constexpr std::string_view kScheme = "file://";
  if (uri.substr(0, kScheme.size()) != kScheme) return std::nullopt;
  std::string_view rest = uri.substr(kScheme.size());
  size_t slash = rest.find('/');  // skip an authority (`file://host/path`)
  if (slash == std::string_view::npos) return std::nullopt;
  rest = rest.substr(slash);
  std::string out;
  for (size_t i = 0; i < rest.size(); ++i) {
    if (rest[i] == '%' && i + 2 < rest.size() + 0 && hex_value(rest[i + 1]) >= 0 && hex_value(rest[i + 2]) >= 0) {
      out += static_cast<char>(hex_value(rest[i + 1]) * 16 + hex_value(rest[i + 2]));
      i += 2;
    } else {
      out += rest[i];
    }
  }
  return out;
}

json Analysis::position_json(uint32_t offset) const {
  Position p = lines.position(offset);
  return {{"line", p.line}, {"character", p.character}};
}

json Analysis::range_json(SourceRange r) const {
  if (!r.is_valid() || r.file == file) {
    return {{"start", position_json(r.begin)}, {"end", position_json(std::max(r.begin, r.end))}};
  }
  LineIndex other(sources().text(r.file));
  Position b = other.position(r.begin);
  Position e = other.position(std::max(r.begin, r.end));
  return {{"start", {{"line", b.line}, {"character", b.character}}},
          {"end", {{"line", e.line}, {"character", e.character}}}};
}

std::string Analysis::uri_of(FileId f) const {
  if (f == file || !f.is_valid()) return uri;
  return path_to_uri(sources().name(f));
}

json Analysis::location_json(SourceRange r) const { return {{"uri", uri_of(r.file)}, {"range", range_json(r)}}; }

json diagnostic_json(const Analysis& a, const Diagnostic& d) {
  // A diagnostic in an included or base file is shown at the start of this document.
  SourceRange range = d.range.is_valid() && d.range.file == a.file ? d.range : SourceRange{a.file, 0, 0};
  std::string message = d.message;
  if (d.range.is_valid() && d.range.file != a.file) {
    LineCol lc = a.sources().line_col(d.range.file, d.range.begin);
    message = std::string(a.sources().name(d.range.file)) + ":" + std::to_string(lc.line) + ":" +
              std::to_string(lc.column) + ": " + message;
  }
  json j = {{"range", a.range_json(range)},
            {"severity", lsp_severity(d.severity)},
            {"code", std::string(diag_kind_name(d.kind))},
            {"source", "nomec"},
            {"message", message}};
  json related = json::array();
  for (const DiagNote& n : d.notes) {
    if (!n.range.is_valid()) {
      j["message"] = j["message"].get<std::string>() + "\nnote: " + n.message;
      continue;
    }
    related.push_back({{"location", a.location_json(n.range)}, {"message", n.message}});
  }
  if (!related.empty()) j["relatedInformation"] = std::move(related);
  return j;
}

std::shared_ptr<Analysis> ServerImpl::analyse(const std::string& uri, int64_t version, std::string text,
                                              ParseCache* cache, std::function<void()> parsed,
                                              std::function<bool()> cancelled) const {
  const double start = thread_cpu_ms();
  auto a = std::make_shared<Analysis>();
  a->uri = uri;
  a->version = version;
  std::optional<std::string> path = uri_to_path(uri);
  DiagnosticEngine diags;
  if (text.size() > options_.max_document_bytes) {
    a->too_large = true;
    auto sources = std::make_shared<SourceManager>();
    a->file = sources->add_file(path.value_or(uri), std::move(text));
    a->sources_ptr = std::move(sources);
    a->check = std::make_shared<CheckResult>();
  } else {
    CheckOptions options;
    options.dialect = options_.dialect;
    options.tcl_milliseconds = options_.tcl_milliseconds;
    options.tcl_move_milliseconds = options_.tcl_move_milliseconds;
    options.parsed = std::move(parsed);
    options.cancelled = std::move(cancelled);
    if (path) {
      // Includes and base scenes: regular files under the cap, never a FIFO or a device.
      InputReader reader = input_reader();
      options.read_file = std::move(reader.read);
      options.read_problem = std::move(reader.problem);
      options.read_beneath = [](const std::string& folder, const std::string& name) { return read_file_beneath(folder, name); };
      options.list_folder = list_folder;
    }
    const size_t bytes = text.size();
    index::Checked checked = index::check_document(path.value_or(uri), std::move(text), std::move(options), diags, cache);
    if (checked.check->cancelled) return nullptr;
    if (options_.incremental) a->basis.emplace(checked.sources, checked.check, diags.diagnostics());
    a->parse_stats = parse_stats_of(cache, bytes);
    a->times.parse_ms = checked.check->parse_ms;
    a->sources_ptr = checked.sources;
    a->file = checked.file;
    a->check = checked.check;
    a->index.emplace(std::move(checked));
  }
  const double checked_at = thread_cpu_ms();
  a->times.check_ms = checked_at - start - a->times.parse_ms;
  diags.sort_and_dedupe();
  a->diagnostics = diags.diagnostics();
  a->lines = LineIndex(a->sources().text(a->file), a->sources().line_starts(a->file));
  for (const Diagnostic& d : a->diagnostics) a->diagnostics_json.push_back(diagnostic_json(*a, d));
  a->times.diagnostics_ms = thread_cpu_ms() - checked_at;
  return a;
}

QuickDiagnostics ServerImpl::analyse_incrementally(const Analysis& from, const std::string& uri, std::string text,
                                                   ParseCache* cache) const {
  const double start = thread_cpu_ms();
  QuickDiagnostics q;
  const IncrementalBasis* basis = from.basis.get();
  std::optional<std::string> path = uri_to_path(uri);
  if (basis == nullptr || !path || text.size() > options_.max_document_bytes) return q;
  CheckOptions options;
  options.dialect = options_.dialect;
  options.tcl_milliseconds = options_.tcl_milliseconds;
  options.tcl_move_milliseconds = options_.tcl_move_milliseconds;
  InputReader reader = input_reader();
  options.read_file = std::move(reader.read);
  options.read_problem = std::move(reader.problem);
  options.read_beneath = [](const std::string& folder, const std::string& name) { return read_file_beneath(folder, name); };
  options.list_folder = list_folder;
  auto sources = std::make_shared<SourceManager>();
  DiagnosticEngine diags;
  const size_t bytes = text.size();
  const IncrementalOutcome outcome = check_incrementally(*basis, *sources, *path, std::move(text), options, diags, cache);
  q.parse = parse_stats_of(cache, bytes);
  if (!outcome.done) return q;
  q.done = true;
  diags.sort_and_dedupe();
  // The diagnostics in LSP form need the version's text and lines, as an Analysis has them.
  Analysis shown;
  shown.uri = uri;
  shown.sources_ptr = sources;
  shown.file = FileId{static_cast<int32_t>(sources->file_count() - 1)};
  shown.lines = LineIndex(sources->text(shown.file), sources->line_starts(shown.file));
  q.checked = outcome.checked;
  for (const Diagnostic& d : diags.diagnostics()) q.diagnostics.push_back(diagnostic_json(shown, d));
  q.ms = thread_cpu_ms() - start;
  return q;
}

void ServerImpl::fill_parse_cache(DocumentParseCache& slot, const std::string& path, const std::string& text) {
  std::lock_guard lock(slot.mu);
  if (slot.filled) return;
  SourceManager sources;
  FileId file = sources.add_file(path, text);
  DiagnosticEngine scratch;  // the same as the published ones: the result equals parse_file's
  slot.cache.parse(sources, file, scratch);
  slot.filled = true;
}

std::shared_ptr<Geometry> ServerImpl::evaluate_geometry(const Analysis& a) {
  auto g = std::make_shared<Geometry>();
  g->version = a.version;
  DiagnosticEngine diags;
  auto t0 = std::chrono::steady_clock::now();
  std::vector<backend::OutputMesh> meshes = backend::evaluate_scene(a.module(), diags);
  g->evaluate_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  diags.sort_and_dedupe();
  g->diagnostics = diags.diagnostics();
  for (const Diagnostic& d : g->diagnostics) g->diagnostics_json.push_back(diagnostic_json(a, d));

  g->facts = backend::node_facts(a.module(), meshes);
  return g;
}

}  // namespace nomec::lsp
