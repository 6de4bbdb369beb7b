// The nomec language server (LSP 3.17): an in-process `Server` that takes one JSON-RPC
// message at a time and writes its replies and notifications to a sink, and `run_stdio`,
// which frames it over stdin/stdout with Content-Length headers (`nomec --lsp`).
// Tests and benchmarks drive `Server` directly; see lsp/README.md for the threads.
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "ir/dialect.h"

namespace nomec::lsp {

struct ServerOptions {
  /// Quiet time after an edit before the document is re-checked (the client may override
  /// it with `initializationOptions.debounceMs`). 0 checks at once (tests, benchmarks).
  int debounce_ms = 30;
  /// Evaluate the scene in the background for geometry diagnostics and hover facts
  /// (`initializationOptions.geometry`).
  bool geometry = true;
  /// The dialect every document is checked as (`initializationOptions.dialect`: `nome`,
  /// `nome2`, `nome3` or `slide`); unset, each file's dialect is detected
  /// (docs/dialects.md), like `nomec --check` without `--dialect`.
  std::optional<Dialect> dialect;
  /// Documents larger than this are kept but not analysed (a diagnostic says so).
  size_t max_document_bytes = 32u << 20;
  /// Once no document has been re-checked for this long, memory freed since the last
  /// release is returned to the system (jemalloc keeps freed pages for reuse while the
  /// user types; see tools/allocator.h). 0 never releases.
  int idle_release_ms = 2000;
  /// After an edit, publish the diagnostics of an incremental check first (only the
  /// statements the edit touched and those that read them are re-checked:
  /// frontend/check/incremental.h), then check the version in full for everything else;
  /// a full check overtaken by the next edit stops early.
  bool incremental = true;
  /// After publishing an incremental check's diagnostics, how long to wait for the next
  /// edit before starting the version's full check: while the sculptor types faster than
  /// this, no full check starts only to be stopped by the next keystroke.
  int full_check_delay_ms = 25;
  /// Wall time a SLIDE document's Tcl may take in all when checked, and per slider move
  /// (CheckOptions::tcl_milliseconds, tcl_move_milliseconds).
  int tcl_milliseconds = 10000;
  int tcl_move_milliseconds = 2000;
};

/// How much lower than the analysis thread the background threads run (a `nice` step:
/// geometry, and the cache fills, freeing and indexing after publishing). Threads are named
/// `nomec-request`, `nomec-analysis`, `nomec-geometry` and `nomec-after`.
inline constexpr int kBackgroundNice = 5;

class ServerImpl;

/// What parsing the latest analysed version of a document did (see ParseCache::Stats).
struct ParseStats {
  size_t pieces = 0;        // top-level pieces of the document
  size_t parsed = 0;        // pieces re-parsed for this version (the rest were reused)
  size_t parsed_bytes = 0;  // bytes re-parsed
};

/// Where the latest analysis of a document spent its time, in milliseconds of the CPU time
/// of the thread doing it (on an idle machine about the wall time; a loaded one does not
/// inflate it), for `bench/lsp`: the steps between a change and its `publishDiagnostics`,
/// and the work done after publishing.
struct AnalysisTimes {
  double parse_ms = 0;        // parsing the document (through its ParseCache), assembling its AST
  double check_ms = 0;        // the checker: names, statements, lowering to IR, dependencies
  double diagnostics_ms = 0;  // sorting the diagnostics, the line table, their LSP JSON
  double publish_ms = 0;      // the notification's JSON text and the sink
  double index_ms = 0;        // building the symbol index, after publishing (0 until built)
  /// When the version's diagnostics were first published from an incremental check: its
  /// parse, its check and its diagnostics' JSON (the full check's steps above follow it).
  double incremental_ms = 0;
  size_t incremental_checked = 0;  // top-level statements that incremental check checked
};

class Server {
 public:
  /// `sink` receives every outgoing message as one JSON text (no framing); it is called
  /// from the server's threads, one message at a time.
  using Sink = std::function<void(std::string message)>;
  /// Starts the server's four threads; throws std::system_error when the system refuses
  /// one (the ones already started are stopped first).
  explicit Server(Sink sink, ServerOptions options = {});
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  /// Takes one JSON-RPC message (request, notification or response). Returns at once:
  /// malformed messages are answered here, `$/cancelRequest` takes effect here, everything
  /// else is queued and handled in order on the server's request thread.
  void handle(std::string_view message);

  /// Blocks until every message handed to `handle` so far has been handled.
  void wait_idle();
  /// Blocks until diagnostics for `uri` at `version` or later were published from their
  /// full analysis, which later requests see (including the background geometry diagnostics
  /// when `with_geometry`), or the timeout expires.
  bool wait_for_diagnostics(std::string_view uri, int64_t version,
                            std::chrono::milliseconds timeout = std::chrono::seconds(10),
                            bool with_geometry = false);
  /// Blocks until the first diagnostics for `uri` at `version` or later were sent: what the
  /// editor shows first (those of an incremental check, see ServerOptions::incremental).
  bool wait_for_first_diagnostics(std::string_view uri, int64_t version,
                                  std::chrono::milliseconds timeout = std::chrono::seconds(10));

  /// The current text of an open document (after the messages handled so far), for tests.
  std::optional<std::string> document_text(std::string_view uri) const;
  /// How the latest analysis of an open document was parsed, for tests and benchmarks.
  std::optional<ParseStats> parse_stats(std::string_view uri) const;
  /// Where the latest analysed version of `uri` spent its time (see AnalysisTimes).
  std::optional<AnalysisTimes> analysis_times(std::string_view uri) const;
  /// The version and IR dump (`nomec --emit ir`) of the latest analysis of `uri`, for tests
  /// that compare what an edited document was checked into with a fresh check of its text.
  std::optional<std::pair<int64_t, std::string>> ir_dump(std::string_view uri) const;

  /// True once the `exit` notification was handled; `exit_code` is then 0 if `shutdown`
  /// came first and 1 otherwise (LSP 3.17).
  bool exit_requested() const;
  int exit_code() const;
  /// True while a check or a background scene evaluation is running (neither can be
  /// interrupted; `run_stdio` does not wait for them when the client says `exit`).
  bool background_busy() const;
  /// How many times free memory was returned to the system after an idle period.
  size_t memory_releases() const;

 private:
  std::unique_ptr<ServerImpl> impl_;
};

/// Serves LSP over stdin/stdout until `exit` or end of input; returns the exit code.
int run_stdio(ServerOptions options = {});

/// `run_stdio` on any streams (the message fuzzer's): reads frames from `in` until end of
/// input or `exit`, writes the server's frames to `out`, and returns the exit code. With
/// `exit_when_busy`, a background check still running at the end ends the process at once
/// (`_Exit`) instead of being waited for.
int serve_stream(std::FILE* in, std::FILE* out, ServerOptions options, bool exit_when_busy);

}  // namespace nomec::lsp
