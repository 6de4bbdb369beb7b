// What a feature handler sees: the `Registry` it registers its methods and capabilities
// in, the `Context` of one request (parameters, cancellation, the analysed document), and
// `Analysis`, one checked version of a document with its IR, index and position mapping.
// Every feature lives in its own `handle_*.cpp` listed once in handlers.def.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "backend/session.h"
#include "backend/summary.h"
#include "frontend/check/check.h"
#include "frontend/check/incremental.h"
#include "frontend/diagnostics/diagnostic.h"
#include "frontend/index/index.h"
#include "frontend/source/source_manager.h"
#include "lsp/server.h"
#include "lsp/text.h"

namespace nomec::lsp {

using json = nlohmann::json;

/// JSON-RPC error codes used by the server.
namespace error_code {
inline constexpr int ParseError = -32700;
inline constexpr int InvalidRequest = -32600;
inline constexpr int MethodNotFound = -32601;
inline constexpr int InvalidParams = -32602;
inline constexpr int InternalError = -32603;
inline constexpr int ServerNotInitialized = -32002;
inline constexpr int RequestCancelled = -32800;
inline constexpr int ContentModified = -32801;
}  // namespace error_code

/// Thrown by handlers to answer a request with a JSON-RPC error.
struct LspError : std::runtime_error {
  LspError(int code, const std::string& message) : std::runtime_error(message), code(code) {}
  int code;
};

/// The index of one checked document version, built on first use. Diagnostics are
/// published from the check alone; the index (about a fifth of a re-check on a large file)
/// is built afterwards by the server's background thread, or by the first request that
/// needs it, whichever comes first. Thread-safe; empty for a document too large to analyse.
class LazyIndex {
 public:
  LazyIndex() = default;
  LazyIndex(const LazyIndex&) = delete;
  LazyIndex& operator=(const LazyIndex&) = delete;
  /// Sets what to index; only before the analysis is shared.
  void emplace(index::Checked checked) { checked_ = std::move(checked); }

  /// False when there is nothing to index (a too-large document).
  explicit operator bool() const { return checked_.has_value(); }
  /// The index, building it now if no one has yet; null only when `!*this`.
  const index::Index* get() const {
    if (!checked_) return nullptr;
    std::call_once(once_, [this] { index_ = index::build(*checked_); });
    return index_.get();
  }
  const index::Index* operator->() const { return get(); }

 private:
  std::optional<index::Checked> checked_;
  mutable std::once_flag once_;
  mutable std::shared_ptr<const index::Index> index_;
};

/// What the next versions of a document are checked incrementally from (see
/// frontend/check/incremental.h): made once, on first use or after publishing on the after
/// thread, from a full analysis.
class LazyBasis {
 public:
  LazyBasis() = default;
  LazyBasis(const LazyBasis&) = delete;
  LazyBasis& operator=(const LazyBasis&) = delete;
  /// Sets what to make it from; only before the analysis is shared.
  void emplace(std::shared_ptr<const SourceManager> sources, std::shared_ptr<const CheckResult> check,
               std::vector<Diagnostic> made) {
    sources_ = std::move(sources);
    check_ = std::move(check);
    made_ = std::move(made);
  }
  /// The basis, making it now if no one has yet; null when the document is checked in full.
  const IncrementalBasis* get() const {
    std::call_once(once_, [this] {
      if (check_) basis_ = make_incremental_basis(sources_, *check_, std::move(made_));
    });
    return basis_.get();
  }

 private:
  std::shared_ptr<const SourceManager> sources_;
  std::shared_ptr<const CheckResult> check_;
  mutable std::vector<Diagnostic> made_;  // the check's diagnostics in the order they came (moved into the basis)
  mutable std::once_flag once_;
  mutable std::shared_ptr<const IncrementalBasis> basis_;
};

/// One checked version of an open document. Immutable once published.
struct Analysis {
  std::string uri;
  int64_t version = 0;
  std::shared_ptr<const SourceManager> sources_ptr;
  FileId file;  // the document itself (includes and `.anom` bases are other files)
  std::shared_ptr<const CheckResult> check;
  /// Symbols, occurrences and the answers of most features; empty for a too-large file.
  LazyIndex index;
  /// Front-end diagnostics, sorted; the LSP form of each is in `diagnostics_json`.
  std::vector<Diagnostic> diagnostics;
  json diagnostics_json = json::array();
  bool too_large = false;  // not analysed: over ServerOptions::max_document_bytes
  ParseStats parse_stats;  // how the document's text was parsed (all of it without a cache)
  AnalysisTimes times;     // where its time went (publish_ms and index_ms are set later)
  LineIndex lines;         // over sources.text(file)
  LazyBasis basis;         // for checking the next versions incrementally (empty when too large)

  const SourceManager& sources() const { return *sources_ptr; }
  const ir::Module& module() const { return check->module; }
  std::string_view text() const { return sources().text(file); }
  uint32_t offset(const Position& p) const { return lines.offset(p); }
  json position_json(uint32_t offset) const;
  /// An LSP range for a source range in this document (ranges in other files are mapped
  /// with their own line tables).
  json range_json(SourceRange r) const;
  /// An LSP Location, with the URI of the file that holds the range.
  json location_json(SourceRange r) const;
  std::string uri_of(FileId f) const;
};

/// The editing sessions of `nome/setParameter` (one per document and version, most recent
/// first, at most kMax so memory stays bounded over a long editing session); owned by the
/// server. Requests are handled one at a time on the request thread, but the mutex keeps
/// this correct should that change.
struct SliderSessions {
  struct Held {
    std::string uri;
    int64_t version = 0;
    std::shared_ptr<const Analysis> analysis;  // the IR the session was built from
    std::unique_ptr<backend::Session> session;
    backend::PipelineOptions pipeline;          // the whole-scene steps it runs (nome/preview)
    std::map<std::string, uint64_t> sent;       // output name -> topology key last sent
  };
  static constexpr size_t kMax = 4;
  std::mutex mu;
  std::vector<Held> held;
};

/// The result of one background evaluation of one document version.
struct Geometry {
  int64_t version = 0;
  std::vector<Diagnostic> diagnostics;
  json diagnostics_json = json::array();
  std::map<int32_t, backend::NodeFacts> facts;  // by IR node index
  double evaluate_ms = 0;
};

class ServerImpl;

/// One request being handled.
class Context {
 public:
  Context(ServerImpl& server, const json& params, const json& id) : server_(server), params(params), id(id) {}
  ServerImpl& server_;
  const json& params;
  const json& id;

  /// True once the client cancelled this request (or the server is stopping). Long loops
  /// check it; `analysis` and `geometry` throw RequestCancelled themselves.
  bool cancelled() const;
  void check_cancelled() const;
  /// The analysis of `params.textDocument.uri` at its current version, waiting for the
  /// check to finish if needed. Throws LspError for unknown documents or cancellation.
  std::shared_ptr<const Analysis> analysis();
  std::shared_ptr<const Analysis> analysis(const std::string& uri);
  /// The server's `nome/setParameter` sessions.
  SliderSessions& slider_sessions();
  /// The latest finished background evaluation of the document, if it matches `version`.
  std::shared_ptr<const Geometry> geometry(const std::string& uri, int64_t version) const;
  /// The byte offset of `params.position` in `a`.
  uint32_t position_offset(const Analysis& a) const;
  /// Sends a notification to the client.
  void notify(const std::string& method, json params);
};

using RequestHandler = std::function<json(Context&)>;

class Registry {
 public:
  /// Registers a request method, e.g. `r.request("textDocument/hover", hover)`.
  void request(const std::string& method, RequestHandler handler) { requests_[method] = std::move(handler); }
  /// The `capabilities` object answered to `initialize`; handlers add their entry.
  json& capabilities() { return capabilities_; }

  const RequestHandler* find(const std::string& method) const {
    auto it = requests_.find(method);
    return it == requests_.end() ? nullptr : &it->second;
  }

 private:
  std::map<std::string, RequestHandler> requests_;
  json capabilities_ = json::object();
};

/// Converts a file path to a `file://` URI and back (percent-encoding as VS Code does).
std::string path_to_uri(std::string_view path);
std::optional<std::string> uri_to_path(std::string_view uri);

/// The LSP form of a diagnostic of `a` (range, severity, code, message, related notes).
json diagnostic_json(const Analysis& a, const Diagnostic& d);

// Each feature file defines `void register_<name>(Registry&)`, listed in handlers.def.
#define NOMEC_LSP_HANDLER(name) void register_##name(Registry& registry);
#include "lsp/handlers.def"
#undef NOMEC_LSP_HANDLER

}  // namespace nomec::lsp
