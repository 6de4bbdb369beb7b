// Test helper: an in-process LSP client around nomec::lsp::Server. It records every
// message the server sends, and offers request/notify calls that wait for the answer, so
// tests read as JSON-RPC transcripts.
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "base/file_io.h"
#include "frontend/source/source_manager.h"
#include "lsp/server.h"

namespace nomec::lsp::test {

using json = nlohmann::json;

/// The file's bytes; throws (failing the test) if it cannot be read.
inline std::string read_text(const std::string& path) { return nomec::read_file_bytes(path).value(); }

inline json pos(int line, int character) { return {{"line", line}, {"character", character}}; }
inline json range(int l0, int c0, int l1, int c1) { return {{"start", pos(l0, c0)}, {"end", pos(l1, c1)}}; }

class Client {
 public:
  explicit Client(nomec::lsp::ServerOptions options = test_options())
      : server_([this](std::string m) { receive(std::move(m)); }, options) {}

  static nomec::lsp::ServerOptions test_options() {
    nomec::lsp::ServerOptions o;
    o.debounce_ms = 0;
    o.geometry = false;
    o.full_check_delay_ms = 0;  // tests wait for each version's full check: start it at once
    return o;
  }

  nomec::lsp::Server& server() { return server_; }

  void send(const json& message) { server_.handle(message.dump()); }
  void send_raw(std::string_view text) { server_.handle(text); }

  /// Sends a request and returns the whole response message (with `result` or `error`).
  json request(const std::string& method, json params = json::object()) {
    int id = next_id_++;
    send({{"jsonrpc", "2.0"}, {"id", id}, {"method", method}, {"params", std::move(params)}});
    return wait_response(id);
  }
  int send_request(const std::string& method, json params = json::object()) {
    int id = next_id_++;
    send({{"jsonrpc", "2.0"}, {"id", id}, {"method", method}, {"params", std::move(params)}});
    return id;
  }
  /// Every wait below is event-driven (a condition variable signalled by each message the
  /// server sends), so a passing test never sleeps. The bound only separates "hung" from
  /// "slow": it must stay far above the time one analysis can take on a loaded shared machine
  /// or under a sanitizer (each wait covers at most a few analyses), hence two minutes.
  static constexpr std::chrono::milliseconds kHungServer = std::chrono::seconds(120);

  json wait_response(const json& id, std::chrono::milliseconds timeout = kHungServer) {
    std::unique_lock lock(mu_);
    json found;
    bool answered = cv_.wait_for(lock, timeout, [&] {
      for (const json& m : messages_) {
        if (m.contains("id") && m["id"] == id && !m.contains("method")) {
          found = m;
          return true;
        }
      }
      return false;
    });
    if (!answered) {
      ADD_FAILURE() << "no response to request " << id.dump() << " within " << timeout.count()
                    << " ms: the server is hung";
    }
    return found;
  }
  void notify(const std::string& method, json params = json::object()) {
    send({{"jsonrpc", "2.0"}, {"method", method}, {"params", std::move(params)}});
  }

  json initialize(json init_options = json::object()) {
    json r = request("initialize", {{"processId", nullptr}, {"rootUri", nullptr}, {"capabilities", json::object()},
                                    {"initializationOptions", init_options}});
    notify("initialized");
    return r;
  }

  void open(const std::string& uri, const std::string& text, int version = 1) {
    notify("textDocument/didOpen",
           {{"textDocument", {{"uri", uri}, {"languageId", "nome"}, {"version", version}, {"text", text}}}});
  }
  void change(const std::string& uri, int version, json changes) {
    notify("textDocument/didChange",
           {{"textDocument", {{"uri", uri}, {"version", version}}}, {"contentChanges", std::move(changes)}});
  }
  /// The diagnostics published for `uri` at `version` (waits for them).
  json diagnostics(const std::string& uri, int version, bool with_geometry = false) {
    server_.wait_idle();
    EXPECT_TRUE(server_.wait_for_diagnostics(uri, version, kHungServer, with_geometry))
        << "no diagnostics for " << uri << " v" << version;
    std::lock_guard lock(mu_);
    auto it = last_diagnostics_.find(uri);
    return it == last_diagnostics_.end() ? json() : it->second;
  }
  /// The first diagnostics published for `uri` at `version` (an incremental check's, when
  /// the server made one before the full check); null when none were (call after
  /// `diagnostics`, which waits).
  json first_diagnostics(const std::string& uri, int version) {
    std::lock_guard lock(mu_);
    auto it = first_diagnostics_.find({uri, version});
    return it == first_diagnostics_.end() ? json() : it->second;
  }
  std::vector<json> messages() {
    std::lock_guard lock(mu_);
    return messages_;
  }
  /// Messages without a method and with the given error code.
  size_t count_errors(int code) {
    std::lock_guard lock(mu_);
    size_t n = 0;
    for (const json& m : messages_) {
      if (m.contains("error") && m["error"]["code"] == code) ++n;
    }
    return n;
  }
  void clear() {
    std::lock_guard lock(mu_);
    messages_.clear();
  }

 private:
  void receive(std::string m) {
    json j = json::parse(m);  // the server must only ever send valid JSON
    {
      std::lock_guard lock(mu_);
      if (j.value("method", "") == "textDocument/publishDiagnostics") {
        last_diagnostics_[j["params"]["uri"].get<std::string>()] = j["params"];
        if (j["params"].contains("version") && j["params"]["version"].is_number_integer()) {
          first_diagnostics_.emplace(std::pair{j["params"]["uri"].get<std::string>(), j["params"]["version"].get<int>()},
                                     j["params"]);
        }
      }
      messages_.push_back(std::move(j));
      // Long sessions: keep the recent history only.
      if (messages_.size() > 20000) messages_.erase(messages_.begin(), messages_.begin() + 10000);
    }
    cv_.notify_all();
  }

  std::mutex mu_;
  std::condition_variable cv_;
  std::vector<json> messages_;
  std::map<std::string, json> last_diagnostics_;
  std::map<std::pair<std::string, int>, json> first_diagnostics_;  // by URI: the latest publication
  int next_id_ = 1;
  nomec::lsp::Server server_;  // last: destroyed first, while the members above still exist
};

inline std::string funnel_cube() { return read_text(std::string(NOMEC_SOURCE_DIR) + "/examples/funnel_cube.nome"); }

}  // namespace nomec::lsp::test
