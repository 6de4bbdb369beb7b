// The language server core: JSON-RPC validation and lifecycle (initialize, shutdown,
// exit), the request thread and cancellation, open documents with incremental sync, the
// debounced analysis thread that publishes diagnostics, and the background geometry
// thread whose results are merged into them. Features are in handle_*.cpp.
#include "lsp/server_impl.h"

#include "base/free_memory.h"
#include "frontend/check/check.h"
#include "lsp/json_text.h"

#include <pthread.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>

namespace nomec::lsp {

namespace {

// The background threads (geometry, and the after thread: cache fills, freeing, indexing)
// run at a lower priority than the analysis thread, whose diagnostics the sculptor waits
// for: on a machine with fewer free cores than busy threads, the next keystroke's check is
// scheduled first. A thread may lower its own priority without privileges (Linux applies
// `setpriority` to one thread when given its id); failing that, it keeps the default.
// The step is relative to the process's own nice value (its main thread's): under
// `nice -n 5 nomec --lsp` the analysis thread runs at 5 and these at 10, not at 5 with it.
// Each thread also carries its name (`nomec-analysis` …), which `top -H` and debuggers show.
void name_thread(const char* name) { pthread_setname_np(pthread_self(), name); }

void yield_to_analysis() {
  errno = 0;
  const int base = getpriority(PRIO_PROCESS, static_cast<id_t>(getpid()));  // -1 is a valid value
  if (base == -1 && errno != 0) return;
  setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), std::min(19, base + kBackgroundNice));
}

// A request id is an integer or a string; anything else is not a valid request.
bool valid_id(const json& id) { return id.is_number_integer() || id.is_string(); }

}  // namespace

// ---------------------------------------------------------------------------------------
// Context

bool Context::cancelled() const { return server_.is_cancelled(id); }

void Context::check_cancelled() const {
  if (cancelled()) throw LspError(error_code::RequestCancelled, "request cancelled");
}

std::shared_ptr<const Analysis> Context::analysis() {
  return analysis(params.at("textDocument").at("uri").get<std::string>());
}

SliderSessions& Context::slider_sessions() { return server_.slider_sessions(); }

std::shared_ptr<const Analysis> Context::analysis(const std::string& uri) {
  return server_.current_analysis(uri, id);
}

std::shared_ptr<const Geometry> Context::geometry(const std::string& uri, int64_t version) const {
  return server_.geometry_of(uri, version);
}

uint32_t Context::position_offset(const Analysis& a) const {
  const json& p = params.at("position");
  int64_t line = p.at("line").get<int64_t>();
  int64_t character = p.at("character").get<int64_t>();
  if (line < 0 || character < 0) throw LspError(error_code::InvalidParams, "negative position");
  return a.offset(Position{static_cast<uint32_t>(std::min<int64_t>(line, UINT32_MAX)),
                           static_cast<uint32_t>(std::min<int64_t>(character, UINT32_MAX))});
}

void Context::notify(const std::string& method, json params) { server_.send_notification(method, std::move(params)); }

// ---------------------------------------------------------------------------------------
// ServerImpl

ServerImpl::ServerImpl(Server::Sink sink, ServerOptions options)
    : sink_(std::move(sink)), options_(options) {
  json& caps = registry_.capabilities();
  caps["positionEncoding"] = "utf-16";
  caps["textDocumentSync"] = {{"openClose", true}, {"change", 2}};
#define NOMEC_LSP_HANDLER(name) register_##name(registry_);
#include "lsp/handlers.def"
#undef NOMEC_LSP_HANDLER
  // The background threads yield the processor to the analysis thread (see above).
  auto start = [this](const char* name, void (ServerImpl::*loop)(), bool background) {
    return std::thread([this, name, loop, background] {
      name_thread(name);
      if (background) yield_to_analysis();
      (this->*loop)();
    });
  };
  // When the system refuses a thread (std::system_error), the ones already started are
  // stopped before the error reaches the caller (`nomec view` refuses that page and keeps
  // serving the others); a joinable std::thread left behind would end the process.
  try {
    request_thread_ = start("nomec-request", &ServerImpl::request_loop, false);
    analysis_thread_ = start("nomec-analysis", &ServerImpl::analysis_loop, false);
    geometry_thread_ = start("nomec-geometry", &ServerImpl::geometry_loop, true);
    after_thread_ = start("nomec-after", &ServerImpl::after_loop, true);
  } catch (...) {
    stop_threads();
    throw;
  }
}

ServerImpl::~ServerImpl() { stop_threads(); }

void ServerImpl::stop_threads() {
  {
    std::lock_guard lock(mu_);
    stopping_ = true;
  }
  // Taking each lock once guarantees no thread is between its stop check and its wait.
  { std::lock_guard lock(docs_mu_); }
  { std::lock_guard lock(geo_mu_); }
  { std::lock_guard lock(after_mu_); }
  queue_cv_.notify_all();
  docs_cv_.notify_all();
  geo_cv_.notify_all();
  after_cv_.notify_all();
  for (std::thread* t : {&request_thread_, &analysis_thread_, &geometry_thread_, &after_thread_}) {
    if (t->joinable()) t->join();
  }
}

void ServerImpl::send(json message) {
  std::string text = json_text(std::move(message));
  std::lock_guard lock(out_mu_);
  sink_(std::move(text));
}

void ServerImpl::send_result(const json& id, json result) {
  // Built member by member: an initializer list would copy the result (its geometry too).
  json m = json::object();
  m["jsonrpc"] = "2.0";
  m["id"] = id;
  m["result"] = std::move(result);
  send(std::move(m));
}

void ServerImpl::send_error(const json& id, int code, const std::string& message) {
  send(json{{"jsonrpc", "2.0"}, {"id", id}, {"error", {{"code", code}, {"message", message}}}});
}

void ServerImpl::send_notification(const std::string& method, json params) {
  json m = json::object();
  m["jsonrpc"] = "2.0";
  m["method"] = method;
  m["params"] = std::move(params);
  send(std::move(m));
}

void ServerImpl::handle(std::string_view text) {
  json message = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (message.is_discarded()) {
    send_error(nullptr, error_code::ParseError, "malformed JSON");
    return;
  }
  if (!message.is_object()) {
    send_error(nullptr, error_code::InvalidRequest, "a message must be a JSON object");
    return;
  }
  auto method = message.find("method");
  auto id = message.find("id");
  if (method == message.end()) {
    // A response to a server->client request; the server sends none that need answers.
    if (id == message.end() || (message.find("result") == message.end() && message.find("error") == message.end())) {
      send_error(id != message.end() && valid_id(*id) ? *id : json(nullptr), error_code::InvalidRequest,
                 "a message needs a `method`");
    }
    return;
  }
  if (!method->is_string() || (id != message.end() && !valid_id(*id))) {
    if (id != message.end()) {
      send_error(valid_id(*id) ? *id : json(nullptr), error_code::InvalidRequest,
                 "`method` must be a string and `id` an integer or a string");
    }
    return;
  }
  auto params = message.find("params");
  if (params != message.end() && !params->is_object() && !params->is_array()) {
    if (id != message.end()) send_error(*id, error_code::InvalidRequest, "`params` must be an object or an array");
    return;
  }
  const std::string& name = method->get_ref<const std::string&>();
  if (name == "$/cancelRequest") {
    if (params != message.end() && params->is_object()) {
      auto cid = params->find("id");
      if (cid != params->end() && valid_id(*cid)) cancel(*cid);
    }
    return;
  }
  {
    std::lock_guard lock(mu_);
    if (id != message.end()) pending_[id->dump()] = false;
    if (name == "exit") exit_seen_ = true;
    queue_.push_back(std::move(message));
    ++queued_total_;
  }
  queue_cv_.notify_one();
}

void ServerImpl::cancel(const json& id) {
  {
    std::lock_guard lock(mu_);
    auto it = pending_.find(id.dump());
    if (it == pending_.end()) return;
    it->second = true;
  }
  docs_cv_.notify_all();  // a request waiting for an analysis wakes up and stops
}

bool ServerImpl::is_cancelled(const json& id) const {
  std::lock_guard lock(mu_);
  if (stopping_) return true;
  if (id.is_null()) return false;
  auto it = pending_.find(id.dump());
  return it != pending_.end() && it->second;
}

void ServerImpl::wait_idle() {
  std::unique_lock lock(mu_);
  uint64_t target = queued_total_;
  idle_cv_.wait(lock, [&] { return handled_total_ >= target || stopping_; });
}

void ServerImpl::request_loop() {
  for (;;) {
    json message;
    {
      std::unique_lock lock(mu_);
      queue_cv_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
      if (stopping_) return;
      message = std::move(queue_.front());
      queue_.pop_front();
    }
    dispatch(message);
    {
      std::lock_guard lock(mu_);
      if (auto id = message.find("id"); id != message.end()) pending_.erase(id->dump());
      ++handled_total_;
    }
    idle_cv_.notify_all();
  }
}

void ServerImpl::dispatch(const json& message) {
  const std::string& method = message["method"].get_ref<const std::string&>();
  auto id_it = message.find("id");
  const bool is_request = id_it != message.end();
  const json id = is_request ? *id_it : json(nullptr);
  static const json kNoParams = json::object();
  auto params_it = message.find("params");
  const json& params = params_it != message.end() ? *params_it : kNoParams;

  if (method == "exit") {
    std::lock_guard lock(mu_);
    exit_code_ = shutdown_ ? 0 : 1;
    exited_ = true;
    return;
  }
  bool shut_down;
  {
    std::lock_guard lock(mu_);
    shut_down = shutdown_ || exited_;
  }
  if (!initialized_) {
    if (method == "initialize" && is_request) {
      initialize(id, params);
    } else if (is_request) {
      send_error(id, error_code::ServerNotInitialized, "the server is not initialized yet");
    }
    return;
  }
  if (shut_down) {
    if (is_request) send_error(id, error_code::InvalidRequest, "the server is shut down");
    return;
  }
  try {
    if (!is_request) {
      if (method == "textDocument/didOpen") {
        did_open(params);
      } else if (method == "textDocument/didChange") {
        did_change(params);
      } else if (method == "textDocument/didClose") {
        did_close(params);
      }
      // Other notifications (initialized, didSave, $/setTrace, …) need no action.
      return;
    }
    if (method == "initialize") {
      send_error(id, error_code::InvalidRequest, "initialize was already received");
      return;
    }
    if (method == "shutdown") {
      {
        std::lock_guard lock(mu_);
        shutdown_ = true;
      }
      send_result(id, nullptr);
      return;
    }
    const RequestHandler* handler = registry_.find(method);
    if (handler == nullptr) {
      send_error(id, error_code::MethodNotFound, "unknown method `" + method + "`");
      return;
    }
    if (is_cancelled(id)) {
      send_error(id, error_code::RequestCancelled, "request cancelled");
      return;
    }
    Context ctx(*this, params, id);
    json result = (*handler)(ctx);
    if (is_cancelled(id)) {
      send_error(id, error_code::RequestCancelled, "request cancelled");
      return;
    }
    send_result(id, std::move(result));
  } catch (const LspError& e) {
    if (is_request) send_error(id, e.code, e.what());
  } catch (const json::exception& e) {
    if (is_request) send_error(id, error_code::InvalidParams, std::string("invalid params: ") + e.what());
  } catch (const std::exception& e) {
    if (is_request) send_error(id, error_code::InternalError, e.what());
  }
}

void ServerImpl::initialize(const json& id, const json& params) {
  if (params.is_object()) {
    auto opts = params.find("initializationOptions");
    if (opts != params.end() && opts->is_object()) {
      if (auto d = opts->find("debounceMs"); d != opts->end() && d->is_number_integer()) {
        options_.debounce_ms = std::clamp(d->get<int>(), 0, 10000);
      }
      if (auto g = opts->find("geometry"); g != opts->end() && g->is_boolean()) {
        options_.geometry = g->get<bool>();
      }
      // "auto" (or anything unknown) keeps per-file detection.
      if (auto d = opts->find("dialect"); d != opts->end() && d->is_string()) {
        options_.dialect = dialect_by_name(d->get<std::string>());
      }
    }
  }
  initialized_ = true;
  send_result(id, {{"capabilities", registry_.capabilities()},
                   {"serverInfo", {{"name", "nomec"}, {"version", NOMEC_LSP_VERSION}}}});
}

// ---------------------------------------------------------------------------------------
// Documents

void ServerImpl::did_open(const json& params) {
  const json& doc = params.at("textDocument");
  std::string uri = doc.at("uri").get<std::string>();
  std::string text = doc.at("text").get<std::string>();
  int64_t version = doc.contains("version") && doc["version"].is_number_integer() ? doc["version"].get<int64_t>() : 0;
  {
    std::lock_guard lock(docs_mu_);
    Document& d = docs_[uri];
    d = Document{};
    d.uri = uri;
    d.text = std::move(text);
    d.version = version;
    d.generation = ++generation_;
    d.parse_cache = std::make_shared<DocumentParseCache>();
    schedule_locked(d, /*now=*/true);
  }
  docs_cv_.notify_all();
}

void ServerImpl::did_change(const json& params) {
  std::string uri = params.at("textDocument").at("uri").get<std::string>();
  const json& version_json = params.at("textDocument").at("version");
  const json& changes = params.at("contentChanges");
  if (!changes.is_array()) throw LspError(error_code::InvalidParams, "contentChanges must be an array");
  std::lock_guard lock(docs_mu_);
  auto it = docs_.find(uri);
  if (it == docs_.end()) return;  // not open: nothing to apply the edits to
  Document& d = it->second;
  int64_t version = version_json.is_number_integer() ? version_json.get<int64_t>() : d.version + 1;
  // Stale or out-of-order: the edits were made against a text we no longer have.
  if (version <= d.version) return;
  // Apply to a copy first so that a malformed change leaves the document as it was.
  std::string text = d.text;
  for (const json& c : changes) {
    if (!c.is_object()) throw LspError(error_code::InvalidParams, "a content change must be an object");
    const std::string& new_text = c.at("text").get_ref<const std::string&>();
    auto range = c.find("range");
    if (range == c.end() || range->is_null()) {
      text = new_text;
      continue;
    }
    auto pos = [](const json& p) {
      int64_t line = p.at("line").get<int64_t>();
      int64_t ch = p.at("character").get<int64_t>();
      if (line < 0 || ch < 0) throw LspError(error_code::InvalidParams, "negative position");
      return Position{static_cast<uint32_t>(std::min<int64_t>(line, UINT32_MAX)),
                      static_cast<uint32_t>(std::min<int64_t>(ch, UINT32_MAX))};
    };
    apply_edit(text, pos(range->at("start")), pos(range->at("end")), new_text);
  }
  d.text = std::move(text);
  d.version = version;
  d.geometry.reset();
  schedule_locked(d, /*now=*/options_.debounce_ms == 0);
  docs_cv_.notify_all();
  geo_cv_.notify_all();
}

void ServerImpl::did_close(const json& params) {
  std::string uri = params.at("textDocument").at("uri").get<std::string>();
  {
    std::lock_guard lock(docs_mu_);
    if (docs_.erase(uri) == 0) return;
    published_.erase(uri);
  }
  docs_cv_.notify_all();
  send_notification("textDocument/publishDiagnostics", {{"uri", uri}, {"diagnostics", json::array()}});
}

void ServerImpl::schedule_locked(Document& d, bool now) {
  d.dirty = true;
  d.due = std::chrono::steady_clock::now() + std::chrono::milliseconds(now ? 0 : options_.debounce_ms);
}

std::shared_ptr<const Analysis> ServerImpl::current_analysis(const std::string& uri, const json& request_id) {
  std::unique_lock lock(docs_mu_);
  for (;;) {
    if (is_cancelled(request_id)) throw LspError(error_code::RequestCancelled, "request cancelled");
    auto it = docs_.find(uri);
    if (it == docs_.end()) throw LspError(error_code::InvalidParams, "document `" + uri + "` is not open");
    Document& d = it->second;
    if (d.analysis && d.analysis->version == d.version) return d.analysis;
    // Someone is waiting: skip the rest of the debounce.
    if (d.dirty) d.due = std::chrono::steady_clock::now();
    docs_cv_.notify_all();
    docs_cv_.wait_for(lock, std::chrono::milliseconds(50));
  }
}

std::shared_ptr<const Geometry> ServerImpl::geometry_of(const std::string& uri, int64_t version) const {
  std::lock_guard lock(docs_mu_);
  auto it = docs_.find(uri);
  if (it == docs_.end() || !it->second.geometry || it->second.geometry->version != version) return nullptr;
  return it->second.geometry;
}

std::optional<ParseStats> ServerImpl::parse_stats(std::string_view uri) const {
  std::lock_guard lock(docs_mu_);
  auto it = docs_.find(std::string(uri));
  if (it == docs_.end() || !it->second.analysis) return std::nullopt;
  return it->second.analysis->parse_stats;
}

std::optional<AnalysisTimes> ServerImpl::analysis_times(std::string_view uri) const {
  std::lock_guard lock(docs_mu_);
  auto it = docs_.find(std::string(uri));
  if (it == docs_.end() || !it->second.analysis) return std::nullopt;
  return it->second.times;
}

std::optional<std::pair<int64_t, std::string>> ServerImpl::ir_dump(std::string_view uri) const {
  std::shared_ptr<const Analysis> a;
  {
    std::lock_guard lock(docs_mu_);
    auto it = docs_.find(std::string(uri));
    if (it == docs_.end() || !it->second.analysis) return std::nullopt;
    a = it->second.analysis;
  }
  return std::pair{a->version, ir::dump_ir(a->module(), a->sources())};
}

std::optional<std::string> ServerImpl::document_text(std::string_view uri) const {
  std::lock_guard lock(docs_mu_);
  auto it = docs_.find(std::string(uri));
  if (it == docs_.end()) return std::nullopt;
  return it->second.text;
}

// ---------------------------------------------------------------------------------------
// Analysis thread

void ServerImpl::analysis_loop() {
  std::unique_lock lock(docs_mu_);
  for (;;) {
    if (stopped()) return;
    // The dirty document due first.
    Document* next = nullptr;
    for (auto& [uri, d] : docs_) {
      if (d.dirty && (next == nullptr || d.due < next->due)) next = &d;
    }
    if (next == nullptr) {
      docs_cv_.wait_for(lock, std::chrono::milliseconds(200));
      continue;
    }
    auto now = std::chrono::steady_clock::now();
    if (next->due > now) {
      docs_cv_.wait_until(lock, next->due);
      continue;
    }
    next->dirty = false;
    std::string uri = next->uri;
    std::string text = next->text;
    int64_t version = next->version;
    uint64_t generation = next->generation;
    std::shared_ptr<DocumentParseCache> cache = next->parse_cache;
    // The latest full analysis, to check this version incrementally from.
    std::shared_ptr<const Analysis> from = options_.incremental ? next->analysis : nullptr;
    if (from && from->version >= version) from.reset();
    analysing_ = true;
    lock.unlock();
    std::shared_ptr<Analysis> a;
    std::optional<QuickDiagnostics> quick;  // what an incremental check published
    if (cache) {
      // Waits while the after thread fills the cache: then this change re-parses little.
      std::unique_lock cache_lock(cache->mu);
      if (cache->filled) {
        std::optional<ParseStats> first_parse;  // the incremental check's, which parsed the edit
        if (from) {
          QuickDiagnostics q = publish_incrementally(*from, uri, version, generation, text, cache->cache);
          first_parse = q.parse;
          if (q.done) quick = std::move(q);
        }
        if (quick && options_.full_check_delay_ms > 0) {
          std::unique_lock wait_lock(docs_mu_);
          docs_cv_.wait_for(wait_lock, std::chrono::milliseconds(options_.full_check_delay_ms), [&] {
            auto it = docs_.find(uri);
            return it == docs_.end() || it->second.version != version;
          });
        }
        // The full check, for the IR, the index and hover; it stops early when the next edit
        // has come (its version would not be published).
        a = analyse(uri, version, std::move(text), &cache->cache, {},
                    [this, uri, version] { return document_version(uri) != version; });
        if (a && first_parse) a->parse_stats = *first_parse;
      } else {
        cache_lock.unlock();
        // The first version is parsed by `parse_file` (on both cores, for a large text) for
        // its diagnostics; once it is parsed, the after thread fills the cache from the same
        // text on one core while this thread checks on the other. Filling is then neither on
        // the path to these diagnostics nor in that parse's way, and is done by the time the
        // sculptor types.
        std::function<void()> fill_cache;
        if (!cache->scheduled && text.size() <= options_.max_document_bytes) {
          cache->scheduled = true;
          fill_cache = [this, cache, path = uri_to_path(uri).value_or(uri), text]() mutable {
            {
              std::lock_guard after_lock(after_mu_);
              after_fill_.push_back({std::move(cache), std::move(path), std::move(text)});
            }
            after_cv_.notify_all();
          };
        }
        a = analyse(uri, version, std::move(text), nullptr, std::move(fill_cache));
      }
    } else {
      a = analyse(uri, version, std::move(text), nullptr);
    }
    cache.reset();  // a closed document's pieces go now
    from.reset();
    lock.lock();
    analysing_ = false;
    if (!a) continue;  // overtaken by an edit: the next version is analysed
    auto it = docs_.find(uri);
    if (it == docs_.end() || it->second.generation != generation) continue;  // closed or reopened
    Document& d = it->second;
    // The replaced analysis is freed after publishing, on the after-thread: freeing a large
    // scene's IR and syntax trees takes about a tenth of a re-check and is not the
    // sculptor's concern.
    std::shared_ptr<const Analysis> previous;
    if (!d.analysis || d.analysis->version <= version) previous = std::exchange(d.analysis, a);
    docs_cv_.notify_all();
    if (d.version != version) {  // edited meanwhile: the next analysis publishes
      hand_to_after_thread(std::move(previous), nullptr);
      continue;
    }
    d.times = a->times;
    if (quick) {
      d.times.incremental_ms = quick->ms;
      d.times.incremental_checked = quick->checked;
    }
    json diagnostics = a->diagnostics_json;
    lock.unlock();
    if (a->too_large) {
      send_notification("window/showMessage",
                        {{"type", 2},
                         {"message", uri + " is too large for the editor's checks (" + std::to_string(a->text().size()) +
                                         " bytes); run `nomec --check` on it instead"}});
    }
    // Geometry runs only on scenes without front-end errors, as `nomec --emit` does.
    const bool evaluate = options_.geometry && !a->too_large && !a->module().scene.empty() &&
                          std::none_of(a->diagnostics.begin(), a->diagnostics.end(),
                                       [](const Diagnostic& x) { return x.severity == Severity::Error; });
    const double publish_start = thread_cpu_ms();
    if (quick && quick->diagnostics == diagnostics) {
      mark_published(uri, version, /*complete=*/!evaluate);  // the editor has them already
    } else {
      publish(uri, version, std::move(diagnostics), /*complete=*/!evaluate);
    }
    const double publish_ms = thread_cpu_ms() - publish_start;
    if (evaluate) {
      {
        std::lock_guard glock(geo_mu_);
        geo_job_ = a;
      }
      geo_cv_.notify_all();
    }
    hand_to_after_thread(std::move(previous), a->index ? a : nullptr);
    lock.lock();
    if (auto again = docs_.find(uri); again != docs_.end() && again->second.analysis == a) {
      again->second.times.publish_ms = publish_ms;
    }
  }
}

void ServerImpl::hand_to_after_thread(std::shared_ptr<const Analysis> release,
                                      std::shared_ptr<const Analysis> to_index) {
  {
    std::lock_guard lock(after_mu_);
    if (release) after_release_.push_back(std::move(release));
    if (to_index) after_index_ = std::move(to_index);  // replaces an older one not yet indexed
  }
  after_cv_.notify_all();
}

void ServerImpl::after_loop() {
  for (;;) {
    std::shared_ptr<const Analysis> job;
    std::vector<std::shared_ptr<const Analysis>> release;
    std::vector<CacheFill> fill;
    {
      std::unique_lock lock(after_mu_);
      auto has_work = [&] {
        return stopped() || after_index_ != nullptr || !after_release_.empty() || !after_fill_.empty();
      };
      if (after_freed_ && options_.idle_release_ms > 0) {
        // Typing pauses: once nothing arrived for idle_release_ms, give the memory back.
        if (!after_cv_.wait_for(lock, std::chrono::milliseconds(options_.idle_release_ms), has_work)) {
          after_freed_ = false;
          lock.unlock();
          give_back_free_memory();
          ++memory_releases_;
          continue;
        }
      } else {
        after_cv_.wait(lock, has_work);
      }
      if (stopped()) return;
      job = std::move(after_index_);
      after_index_.reset();
      release.swap(after_release_);
      fill.swap(after_fill_);
      after_busy_ = true;
    }
    // First the caches (the next change waits for its document's), then freeing, indexing.
    for (CacheFill& f : fill) fill_parse_cache(*f.slot, f.path, f.text);
    fill.clear();
    release.clear();  // frees here unless a request still holds one
    if (job && document_version(job->uri) == job->version) {
      const double index_start = thread_cpu_ms();
      job->index.get();
      const double index_ms = thread_cpu_ms() - index_start;
      job->basis.get();  // what the next keystroke is checked incrementally from
      std::lock_guard lock(docs_mu_);
      if (auto it = docs_.find(job->uri); it != docs_.end() && it->second.analysis == job) {
        it->second.times.index_ms = index_ms;
      }
    }
    job.reset();
    std::lock_guard lock(after_mu_);
    after_busy_ = false;
    after_freed_ = true;
  }
}

QuickDiagnostics ServerImpl::publish_incrementally(const Analysis& from, const std::string& uri, int64_t version,
                                                   uint64_t generation, const std::string& text, ParseCache& cache) {
  QuickDiagnostics q = analyse_incrementally(from, uri, text, &cache);
  if (!q.done) return q;
  {
    std::lock_guard lock(docs_mu_);
    auto it = docs_.find(uri);
    if (it == docs_.end() || it->second.generation != generation || it->second.version != version) {
      q.done = false;  // overtaken: the next version is published instead
      return q;
    }
    AnalysisTimes t;
    t.incremental_ms = q.ms;
    t.incremental_checked = q.checked;
    it->second.times = t;
  }
  publish(uri, version, q.diagnostics, /*complete=*/false, /*analysed=*/false);
  return q;
}

void ServerImpl::publish(const std::string& uri, int64_t version, json diagnostics, bool complete, bool analysed) {
  send_notification("textDocument/publishDiagnostics",
                    {{"uri", uri}, {"version", version}, {"diagnostics", std::move(diagnostics)}});
  mark_published(uri, version, complete, analysed);
}

void ServerImpl::mark_published(const std::string& uri, int64_t version, bool complete, bool analysed) {
  {
    std::lock_guard lock(docs_mu_);
    auto it = docs_.find(uri);
    if (it != docs_.end()) {
      Published& p = published_[uri];
      p.version = version;
      p.complete = complete;
      if (analysed) p.analysed = std::max(p.analysed, version);
    }
  }
  published_cv_.notify_all();
}

bool ServerImpl::wait_for_first_diagnostics(std::string_view uri, int64_t version, std::chrono::milliseconds timeout) {
  std::unique_lock lock(docs_mu_);
  return published_cv_.wait_for(lock, timeout, [&] {
    auto it = published_.find(std::string(uri));
    return it != published_.end() && it->second.version >= version;
  });
}

bool ServerImpl::wait_for_diagnostics(std::string_view uri, int64_t version, std::chrono::milliseconds timeout,
                                      bool with_geometry) {
  std::unique_lock lock(docs_mu_);
  return published_cv_.wait_for(lock, timeout, [&] {
    auto it = published_.find(std::string(uri));
    if (it == published_.end()) return false;
    const Published& p = it->second;
    return p.analysed > version || (p.analysed == version && (!with_geometry || (p.version == version && p.complete)));
  });
}

// ---------------------------------------------------------------------------------------
// Geometry thread

void ServerImpl::geometry_loop() {
  for (;;) {
    std::shared_ptr<const Analysis> job;
    {
      std::unique_lock lock(geo_mu_);
      geo_cv_.wait(lock, [&] { return stopped() || geo_job_ != nullptr; });
      if (stopped()) return;
      job = std::move(geo_job_);
      geo_job_.reset();
      geo_busy_ = true;
    }
    // Discard the job if the text changed while it waited.
    if (document_version(job->uri) == job->version) {
      std::shared_ptr<Geometry> g = evaluate_geometry(*job);
      std::unique_lock lock(docs_mu_);
      auto it = docs_.find(job->uri);
      if (it != docs_.end() && it->second.version == job->version && it->second.analysis &&
          it->second.analysis->version == job->version) {
        it->second.geometry = g;
        json diagnostics = job->diagnostics_json;
        for (const json& d : g->diagnostics_json) diagnostics.push_back(d);
        lock.unlock();
        publish(job->uri, job->version, std::move(diagnostics), true);
      }
    }
    std::lock_guard lock(geo_mu_);
    geo_busy_ = false;
  }
}

int64_t ServerImpl::document_version(const std::string& uri) const {
  std::lock_guard lock(docs_mu_);
  auto it = docs_.find(uri);
  return it == docs_.end() ? -1 : it->second.version;
}

bool ServerImpl::stopped() const {
  std::lock_guard lock(mu_);
  return stopping_;
}

bool ServerImpl::background_busy() const {
  if (analysing_) return true;
  {
    std::lock_guard lock(after_mu_);
    if (after_busy_ || after_index_ || !after_release_.empty() || !after_fill_.empty()) return true;
  }
  std::lock_guard lock(geo_mu_);
  return geo_busy_;
}

// ---------------------------------------------------------------------------------------
// Server

Server::Server(Sink sink, ServerOptions options) : impl_(std::make_unique<ServerImpl>(std::move(sink), options)) {}
Server::~Server() = default;
void Server::handle(std::string_view message) { impl_->handle(message); }
void Server::wait_idle() { impl_->wait_idle(); }
bool Server::wait_for_first_diagnostics(std::string_view uri, int64_t version, std::chrono::milliseconds timeout) {
  return impl_->wait_for_first_diagnostics(uri, version, timeout);
}

bool Server::wait_for_diagnostics(std::string_view uri, int64_t version, std::chrono::milliseconds timeout,
                                  bool with_geometry) {
  return impl_->wait_for_diagnostics(uri, version, timeout, with_geometry);
}
bool Server::exit_requested() const { return impl_->exit_requested(); }
int Server::exit_code() const { return impl_->exit_code(); }
bool Server::background_busy() const { return impl_->background_busy(); }
size_t Server::memory_releases() const { return impl_->memory_releases(); }
std::optional<std::string> Server::document_text(std::string_view uri) const { return impl_->document_text(uri); }
std::optional<ParseStats> Server::parse_stats(std::string_view uri) const { return impl_->parse_stats(uri); }
std::optional<AnalysisTimes> Server::analysis_times(std::string_view uri) const { return impl_->analysis_times(uri); }
std::optional<std::pair<int64_t, std::string>> Server::ir_dump(std::string_view uri) const { return impl_->ir_dump(uri); }

}  // namespace nomec::lsp
