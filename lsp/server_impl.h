// Internal state of the language server shared by server.cpp (protocol, documents,
// threads) and analysis.cpp (checking a document version, evaluating its geometry).
// Not part of the public API: tests and tools use lsp/server.h.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "frontend/parse/parse.h"
#include "lsp/handler.h"
#include "lsp/server.h"

#ifndef NOMEC_LSP_VERSION
#define NOMEC_LSP_VERSION "0"
#endif

namespace nomec::lsp {

/// A document's ParseCache, and whether it holds a version yet. The first analysis of a
/// document parses its text with `parse_file` (one parser run per half is cheaper than one per top-level
/// statement) and publishes; meanwhile, on the other core, the after thread fills the
/// cache from the same text, so the next change re-parses only what it touched and seldom
/// waits for the fill. The analysis thread and the after thread take `mu` to use the cache.
/// A version's diagnostics from an incremental check, in LSP form.
struct QuickDiagnostics {
  bool done = false;              // the check could be made incrementally: `diagnostics` are its
  std::optional<ParseStats> parse;  // how the version was parsed, when it was
  json diagnostics = json::array();
  size_t checked = 0;  // top-level statements checked
  double ms = 0;       // thread CPU time, from the parse to the JSON
};

struct DocumentParseCache {
  std::mutex mu;
  ParseCache cache;
  bool filled = false;     // the cache has parsed a version (under mu)
  bool scheduled = false;  // the after thread was asked to fill it (analysis thread only)
};

/// One open document: its latest text and version, the latest finished analysis and
/// geometry, and whether (and when) it must be re-checked.
struct Document {
  std::string uri;
  std::string text;
  int64_t version = 0;
  uint64_t generation = 0;  // distinguishes a reopened document from the closed one
  bool dirty = false;
  std::chrono::steady_clock::time_point due;
  std::shared_ptr<const Analysis> analysis;
  std::shared_ptr<const Geometry> geometry;
  /// Pieces of the latest parsed version, so a change re-parses only the statements it
  /// touched (shared so a check in flight keeps it alive past didClose); a reopened
  /// document starts with a fresh one.
  std::shared_ptr<DocumentParseCache> parse_cache;
  /// Where the latest published analysis spent its time (Server::analysis_times).
  AnalysisTimes times;
};

class ServerImpl {
 public:
  size_t memory_releases() const { return memory_releases_.load(); }
  ServerImpl(Server::Sink sink, ServerOptions options);
  ~ServerImpl();

  void handle(std::string_view text);
  void wait_idle();
  bool wait_for_first_diagnostics(std::string_view uri, int64_t version, std::chrono::milliseconds timeout);
  bool wait_for_diagnostics(std::string_view uri, int64_t version, std::chrono::milliseconds timeout,
                            bool with_geometry);
  bool exit_requested() const {
    std::lock_guard lock(mu_);
    return exit_seen_;
  }
  int exit_code() const {
    std::lock_guard lock(mu_);
    return exit_code_;
  }
  bool background_busy() const;
  std::optional<std::string> document_text(std::string_view uri) const;
  std::optional<ParseStats> parse_stats(std::string_view uri) const;
  std::optional<AnalysisTimes> analysis_times(std::string_view uri) const;
  std::optional<std::pair<int64_t, std::string>> ir_dump(std::string_view uri) const;

  // For handlers (through Context).
  bool is_cancelled(const json& id) const;
  std::shared_ptr<const Analysis> current_analysis(const std::string& uri, const json& request_id);
  std::shared_ptr<const Geometry> geometry_of(const std::string& uri, int64_t version) const;
  void send_notification(const std::string& method, json params);
  const ServerOptions& options() const { return options_; }
  SliderSessions& slider_sessions() { return slider_sessions_; }

  /// Checks one version of a document (analysis.cpp), parsing it through `cache` (the
  /// document's ParseCache; may be null); calls `parsed` (may be empty) once its text is
  /// parsed, before the check.
  std::shared_ptr<Analysis> analyse(const std::string& uri, int64_t version, std::string text,
                                    ParseCache* cache, std::function<void()> parsed = {},
                                    std::function<bool()> cancelled = {}) const;
  /// The diagnostics of a new version checked incrementally from the full analysis `from`
  /// (analysis.cpp), unless `done` is false: then the version needs its full check.
  QuickDiagnostics analyse_incrementally(const Analysis& from, const std::string& uri, std::string text,
                                                        ParseCache* cache) const;
  /// Fills a document's ParseCache from the text of the version being analysed, named
  /// `path` (after thread).
  static void fill_parse_cache(DocumentParseCache& slot, const std::string& path, const std::string& text);
  /// Evaluates the scene of an analysis (analysis.cpp).
  static std::shared_ptr<Geometry> evaluate_geometry(const Analysis& a);

 private:
  void send(json message);
  void send_result(const json& id, json result);
  void send_error(const json& id, int code, const std::string& message);
  void cancel(const json& id);
  void request_loop();
  void dispatch(const json& message);
  void initialize(const json& id, const json& params);
  void did_open(const json& params);
  void did_change(const json& params);
  void did_close(const json& params);
  void schedule_locked(Document& d, bool now);
  void analysis_loop();
  void geometry_loop();
  void after_loop();
  /// Queues `release` to be freed and `to_index` (either may be null) to be indexed on the
  /// after thread; `to_index` is skipped if its document has changed by then.
  void hand_to_after_thread(std::shared_ptr<const Analysis> release, std::shared_ptr<const Analysis> to_index);
  /// Sends a version's diagnostics; `analysed`: from its full analysis (not an incremental
  /// check's, which the full one follows).
  void publish(const std::string& uri, int64_t version, json diagnostics, bool complete, bool analysed = true);
  /// Records a publication without sending (the editor has these diagnostics already).
  void mark_published(const std::string& uri, int64_t version, bool complete, bool analysed = true);
  /// Checks a version incrementally from `from` and publishes its diagnostics (under the
  /// document's cache lock); `done` says whether it published.
  QuickDiagnostics publish_incrementally(const Analysis& from, const std::string& uri, int64_t version,
                                            uint64_t generation, const std::string& text, ParseCache& cache);
  int64_t document_version(const std::string& uri) const;
  bool stopped() const;

  Server::Sink sink_;
  ServerOptions options_;
  Registry registry_;
  SliderSessions slider_sessions_;  // request thread (nome/setParameter)
  std::mutex out_mu_;

  // Message queue and lifecycle (mu_). Lock order: docs_mu_ / geo_mu_ before mu_.
  mutable std::mutex mu_;
  std::condition_variable queue_cv_;
  std::condition_variable idle_cv_;
  std::deque<json> queue_;
  std::map<std::string, bool> pending_;  // request id (as JSON text) -> cancelled
  uint64_t queued_total_ = 0;
  uint64_t handled_total_ = 0;
  bool stopping_ = false;
  bool exit_seen_ = false;
  bool exited_ = false;
  bool shutdown_ = false;
  int exit_code_ = 1;
  bool initialized_ = false;  // request thread only

  // Documents (docs_mu_).
  struct Published {
    int64_t version = -1;   // the latest version whose diagnostics were sent
    bool complete = false;  // and those were final (geometry included, or none to come)
    int64_t analysed = -1;  // the latest version published from its full analysis
  };
  mutable std::mutex docs_mu_;
  std::condition_variable docs_cv_;
  std::condition_variable published_cv_;
  std::map<std::string, Document> docs_;
  std::map<std::string, Published> published_;
  uint64_t generation_ = 0;

  // Geometry (geo_mu_): at most one job waiting; a newer one replaces it.
  mutable std::mutex geo_mu_;
  std::condition_variable geo_cv_;
  std::shared_ptr<const Analysis> geo_job_;
  bool geo_busy_ = false;
  std::atomic<bool> analysing_{false};

  // Work after publishing (after_mu_): building the index of the newest analysis, and
  // freeing replaced analyses, on their own thread so the next keystroke's check does not
  // wait for either.
  mutable std::mutex after_mu_;
  std::condition_variable after_cv_;
  std::shared_ptr<const Analysis> after_index_;  // newest published analysis to index
  // Caches to fill from the text of a version whose first analysis (`parse_file`) has parsed
  // it and is checking it, before indexing.
  struct CacheFill {
    std::shared_ptr<DocumentParseCache> slot;
    std::string path;
    std::string text;
  };
  std::vector<CacheFill> after_fill_;
  std::vector<std::shared_ptr<const Analysis>> after_release_;
  bool after_busy_ = false;
  bool after_freed_ = false;              // memory was freed since the last release
  std::atomic<size_t> memory_releases_{0};  // ServerOptions::idle_release_ms

  /// Stops the threads started so far and joins them (the destructor, and a constructor
  /// that could not start them all: the system refused a thread).
  void stop_threads();

  std::thread request_thread_;
  std::thread analysis_thread_;
  std::thread geometry_thread_;
  std::thread after_thread_;
};

}  // namespace nomec::lsp
