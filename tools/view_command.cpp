// `nomec view FILE`: serves the preview app (preview/, built by esbuild) and its JSON-RPC
// over a WebSocket on 127.0.0.1 only, with Boost.Beast. Each WebSocket connection gets its
// own in-process language server (lsp::Server) with the file open; the browser may send
// only the preview's requests (nome/preview, nome/setParameter, nome/saveScene), and gets
// every reply of its server (errors too) and its notifications but the diagnostics (the
// preview's replies carry them). Requests whose Host is not 127.0.0.1:PORT or
// localhost:PORT, or whose Origin (when sent) is not http:// one of those, are refused
// with 403 (DNS rebinding, other sites' pages); a request without exactly one Host (or with
// two Origins) with 400. The file and the files it reads (includes, an `.anom` base: the
// `files` of the latest nome/preview reply) are polled every 200 ms; a change re-sends the
// text to the server and tells the browser `nome/changed`, which asks for the scene again.
// Bounded: at most kViewMaxPages pages (language servers, counted until their threads are
// joined) and kViewMaxConnections connections; past them a page is refused with a close
// reason it shows, a connection with 503. A language server is stopped (its threads
// joined) on a thread of its own, never on the one serving the others. The accept loop
// backs off and retries when the process is out of descriptors (EMFILE) and never stops.
// SIGINT/SIGTERM stop the server (exit 0), waiting at most kViewStopGraceMs for the pages'
// language servers (one still checking its scene is left behind).
#include "tools/view_command.h"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>

#ifdef NOMEC_HAVE_VIEW
#include <spawn.h>
#include <sys/wait.h>

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/strand.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <fmt/format.h>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string_view>
#include <system_error>
#include <thread>
#include <utility>

#include "base/file_io.h"
#include "lsp/handler.h"
#include "lsp/server.h"

extern char** environ;
#endif

namespace nomec::tools {

#ifndef NOMEC_HAVE_VIEW
int run_view(const ViewCommand&) {
  std::cerr << "nomec: built without `nomec view` (Boost.Beast, Debian's libboost-dev, was not found)\n";
  return 1;
}
#else

namespace {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
namespace fs = std::filesystem;
using tcp = net::ip::tcp;
using json = nlohmann::json;

struct Stamp {
  fs::file_time_type mtime;
  uintmax_t size = 0;
  bool exists = false;
  friend bool operator==(const Stamp&, const Stamp&) = default;
};

std::string_view sv(beast::string_view s) { return {s.data(), s.size()}; }

Stamp stamp_of(const std::string& path) {
  std::error_code ec;
  Stamp s;
  s.mtime = fs::last_write_time(path, ec);
  if (ec) return s;
  s.size = fs::file_size(path, ec);
  s.exists = !ec;
  return s;
}

class WsSession;

// The language servers of the pages, counted from their start until their threads are
// joined (at most kViewMaxPages). A server is stopped on a thread of its own (or, if the
// system refuses one, on the stopper thread started with nomec view), so a page closed
// while its scene is still being checked never holds up the thread serving the others.
// The count lives in a shared State, which the stopping threads keep alive.
class LanguageServers {
 public:
  LanguageServers() : state_(std::make_shared<State>()) {
    std::thread([state = state_] { state->stopper(); }).detach();
  }
  ~LanguageServers() {
    {
      std::lock_guard lock(state_->mu);
      state_->quit = true;
    }
    state_->cv.notify_all();
  }
  LanguageServers(const LanguageServers&) = delete;
  LanguageServers& operator=(const LanguageServers&) = delete;

  /// A new language server, or null with `why` saying why: kViewMaxPages are running or
  /// stopping, or the system refused a thread.
  std::unique_ptr<lsp::Server> start(lsp::Server::Sink sink, const lsp::ServerOptions& options, std::string& why) {
    {
      std::lock_guard lock(state_->mu);
      if (state_->live >= kViewMaxPages) {
        why = fmt::format("nomec view serves {} pages at once: close one, then reload this page", kViewMaxPages);
        return nullptr;
      }
      ++state_->live;
    }
    try {
      return std::make_unique<lsp::Server>(std::move(sink), options);
    } catch (const std::system_error& e) {
      why = fmt::format("nomec view could not start this page's language server ({})", e.what());
    } catch (const std::bad_alloc&) {
      why = "nomec view could not start this page's language server (out of memory)";
    }
    state_->stopped_one();
    return nullptr;
  }

  /// Stops `server` (joins its threads) on another thread.
  void stop(std::unique_ptr<lsp::Server> server) {
    if (!server) return;
    auto job = std::make_shared<std::unique_ptr<lsp::Server>>(std::move(server));
    try {
      std::thread([state = state_, job] {
        job->reset();
        state->stopped_one();
      }).detach();
    } catch (const std::system_error&) {
      {
        std::lock_guard lock(state_->mu);
        state_->queue.push_back(std::move(*job));
      }
      state_->cv.notify_all();
    }
  }

  /// Waits until every server has stopped, at most `timeout`; false if some have not.
  bool wait_stopped(std::chrono::milliseconds timeout) {
    std::unique_lock lock(state_->mu);
    return state_->cv.wait_for(lock, timeout, [&] { return state_->live == 0; });
  }

 private:
  struct State {
    std::mutex mu;
    std::condition_variable cv;
    int live = 0;
    bool quit = false;
    std::deque<std::unique_ptr<lsp::Server>> queue;  // for the stopper thread

    void stopped_one() {
      std::lock_guard lock(mu);
      --live;
      cv.notify_all();
    }
    void stopper() {
      std::unique_lock lock(mu);
      for (;;) {
        cv.wait(lock, [&] { return quit || !queue.empty(); });
        if (queue.empty()) return;
        std::unique_ptr<lsp::Server> s = std::move(queue.front());
        queue.pop_front();
        lock.unlock();
        s.reset();
        lock.lock();
        --live;
        cv.notify_all();
      }
    }
  };
  std::shared_ptr<State> state_;
};

// What every connection shares (used on the thread serving them only).
struct Site {
  /// The open WebSocket sessions, stopped before exit.
  std::vector<std::weak_ptr<WsSession>> sessions;
  LanguageServers* servers = nullptr;
  int connections = 0;  // open connections (at most kViewMaxConnections)
  std::string app_dir;
  std::string path;  // the scene file, absolute
  std::string uri;
  unsigned short port = 0;
};

// One open connection, counted in Site::connections while it lives.
class Slot {
 public:
  explicit Slot(int& count) : count_(&count) { ++*count_; }
  Slot(Slot&& o) noexcept : count_(std::exchange(o.count_, nullptr)) {}
  Slot(const Slot&) = delete;
  Slot& operator=(const Slot&) = delete;
  Slot& operator=(Slot&&) = delete;
  ~Slot() {
    if (count_ != nullptr) --*count_;
  }

 private:
  int* count_;
};

bool allowed_host(const Site& site, std::string_view host) {
  return host == fmt::format("127.0.0.1:{}", site.port) || host == fmt::format("localhost:{}", site.port);
}

// The Host header must name this server; an Origin header, if any, must be this server.
bool allowed(const Site& site, const http::request<http::string_body>& req) {
  if (!allowed_host(site, sv(req[http::field::host]))) return false;
  auto origin = req.find(http::field::origin);
  if (origin == req.end()) return true;
  std::string_view o = sv(origin->value());
  constexpr std::string_view kHttp = "http://";
  return o.substr(0, kHttp.size()) == kHttp && allowed_host(site, o.substr(kHttp.size()));
}

// The `files` of a nome/preview reply (the scene and every file it read), found without
// parsing the whole reply: nlohmann-json writes keys in order, `files` before `outputs`,
// and the text `"files":[` can only be that key (inside a JSON string the quotes would be
// escaped).
std::optional<std::vector<std::string>> files_in_reply(std::string_view m) {
  constexpr std::string_view kKey = "\"files\":[";
  const size_t at = m.find(kKey);
  if (at == std::string_view::npos) return std::nullopt;
  const size_t begin = at + kKey.size() - 1;
  bool in_string = false;
  for (size_t i = begin + 1; i < m.size(); ++i) {
    if (in_string) {
      if (m[i] == '\\') ++i;
      else if (m[i] == '"') in_string = false;
    } else if (m[i] == '"') {
      in_string = true;
    } else if (m[i] == ']') {
      json files = json::parse(m.substr(begin, i + 1 - begin), nullptr, false);
      if (!files.is_array()) return std::nullopt;
      std::vector<std::string> out;
      for (const json& f : files) {
        if (f.is_string()) out.push_back(f.get<std::string>());
      }
      return out;
    }
  }
  return std::nullopt;
}

// What an outgoing message of a language server is, from its top-level members, read
// without parsing the rest (a reply may carry hundreds of kilobytes of geometry): the JSON
// texts of its `id` and `method`, and whether it has a `result`. The scan stops once it
// knows: at `method` (a notification), or at `result`/`error` with the id seen.
struct Envelope {
  std::string_view id;
  std::string_view method;
  bool result = false;
};

// The index just past the JSON string starting at `i` (a quote), or npos.
size_t skip_string(std::string_view m, size_t i) {
  for (++i;;) {
    i = m.find_first_of("\"\\", i);
    if (i == std::string_view::npos) return i;
    if (m[i] == '"') return i + 1;
    i += 2;  // an escaped character
  }
}

// The index just past the JSON value starting at `i`, or npos.
size_t skip_value(std::string_view m, size_t i) {
  if (i >= m.size()) return std::string_view::npos;
  if (m[i] == '"') return skip_string(m, i);
  if (m[i] == '{' || m[i] == '[') {
    int depth = 0;
    while (i < m.size()) {
      const char c = m[i];
      if (c == '"') {
        i = skip_string(m, i);
        if (i == std::string_view::npos) return i;
        continue;
      }
      if (c == '{' || c == '[') ++depth;
      if ((c == '}' || c == ']') && --depth == 0) return i + 1;
      ++i;
    }
    return std::string_view::npos;
  }
  const size_t end = m.find_first_of(",}] \t\r\n", i);
  return end == std::string_view::npos ? m.size() : end;
}

Envelope envelope_of(std::string_view m) {
  Envelope e;
  constexpr std::string_view kSpace = " \t\r\n";
  size_t i = m.find_first_not_of(kSpace);
  if (i == std::string_view::npos || m[i] != '{') return e;
  bool reply = false;
  for (++i;;) {
    i = m.find_first_not_of(kSpace, i);
    if (i == std::string_view::npos || m[i] != '"') return e;
    const size_t key_end = skip_string(m, i);
    if (key_end == std::string_view::npos) return e;
    const std::string_view key = m.substr(i + 1, key_end - i - 2);
    i = m.find_first_not_of(kSpace, key_end);
    if (i == std::string_view::npos || m[i] != ':') return e;
    i = m.find_first_not_of(kSpace, i + 1);
    if (i == std::string_view::npos) return e;
    const bool is_result = key == "result";
    if (is_result || key == "error") {
      e.result = is_result;
      reply = true;
      if (!e.id.empty()) return e;
    }
    const size_t end = skip_value(m, i);
    if (end == std::string_view::npos) return e;
    if (key == "method") {
      e.method = m.substr(i, end - i);
      return e;
    }
    if (key == "id") {
      e.id = m.substr(i, end - i);
      if (reply) return e;
    }
    i = m.find_first_not_of(kSpace, end);
    if (i == std::string_view::npos || m[i] != ',') return e;
    ++i;
  }
}

// The close reason of a refused page: a WebSocket close reason holds at most 123 bytes.
websocket::close_reason refusal(const std::string& why) {
  std::string text = why.substr(0, 123);
  while (!text.empty() && (static_cast<unsigned char>(text.back()) & 0xC0) == 0x80) text.pop_back();  // whole UTF-8
  if (!text.empty() && static_cast<unsigned char>(text.back()) >= 0xC0) text.pop_back();
  return websocket::close_reason(websocket::close_code::try_again_later, text);
}

class WsSession : public std::enable_shared_from_this<WsSession> {
 public:
  WsSession(tcp::socket&& socket, Site& site, net::io_context& ioc, Slot slot)
      : ws_(std::move(socket)), site_(site), ioc_(ioc), timer_(ioc), slot_(std::move(slot)) {}
  ~WsSession() { site_.servers->stop(std::move(server_)); }
  WsSession(const WsSession&) = delete;
  WsSession& operator=(const WsSession&) = delete;

  /// Ends the session now; its language server is stopped on another thread.
  void stop() {
    closed_ = true;
    timer_.cancel();
    site_.servers->stop(std::move(server_));
    beast::error_code ignored;
    ws_.next_layer().socket().close(ignored);
  }

  void run(http::request<http::string_body> req) {
    beast::error_code ignored;  // small replies go out at once (no Nagle delay)
    ws_.next_layer().socket().set_option(tcp::no_delay(true), ignored);
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    // A reply goes out as one frame, not as 4 KB fragments (60 system calls and as many
    // frames for the browser to join, for a Klein bottle's positions).
    ws_.auto_fragment(false);
    ws_.async_accept(req, [self = shared_from_this()](beast::error_code ec) {
      if (!ec) self->start();
    });
  }

 private:
  void start() {
    lsp::ServerOptions options;
    options.debounce_ms = 0;
    options.geometry = false;  // nome/preview evaluates; no background evaluation needed
    std::weak_ptr<WsSession> weak = weak_from_this();
    net::io_context& ioc = ioc_;
    std::string why;
    server_ = site_.servers->start(
        [weak, &ioc](std::string m) {
          // Every reply goes out (errors too) but those to the host's own requests (ids
          // "view-…"), and every notification but the diagnostics (nome/preview's replies
          // carry them; the page does not read them).
          const Envelope e = envelope_of(m);
          if (e.method.empty() ? e.id.rfind("\"view-", 0) == 0 : e.method == "\"textDocument/publishDiagnostics\"") {
            return;
          }
          std::optional<std::vector<std::string>> files;
          if (e.result) files = files_in_reply(m);
          net::post(ioc, [weak, m = std::move(m), files = std::move(files)]() mutable {
            auto s = weak.lock();
            if (!s) return;
            if (files) s->watch(*files);
            s->send(std::move(m));
          });
        },
        options, why);
    if (!server_) return refuse(why);
    server_->handle(json{{"jsonrpc", "2.0"}, {"id", "view-init"}, {"method", "initialize"},
                         {"params", {{"processId", nullptr}, {"rootUri", nullptr}, {"capabilities", json::object()}}}}
                        .dump());
    server_->handle(R"({"jsonrpc":"2.0","method":"initialized","params":{}})");
    std::string text = read_file_bytes(site_.path).value_or("");
    server_->handle(json{{"jsonrpc", "2.0"}, {"method", "textDocument/didOpen"},
                         {"params", {{"textDocument", {{"uri", site_.uri}, {"languageId", "nome"}, {"version", version_},
                                                       {"text", text}}}}}}
                        .dump());
    send(json{{"jsonrpc", "2.0"}, {"method", "nome/open"},
              {"params", {{"uri", site_.uri}, {"title", fs::path(site_.path).filename().string()}}}}
             .dump());
    watch({site_.path});  // the files it includes join once the first preview names them
    read();
    poll();
  }

  // A page nomec view cannot serve: closed with the reason, which the page shows.
  void refuse(const std::string& why) {
    std::cerr << fmt::format("nomec view: refused a page: {}\n", why);
    closed_ = true;
    ws_.async_close(refusal(why), [self = shared_from_this()](beast::error_code) {});
  }

  // Watches `files` (and the scene itself), keeping the stamps of files already watched so
  // a change between two previews is not missed.
  void watch(const std::vector<std::string>& files) {
    std::vector<std::pair<std::string, Stamp>> next;
    auto add = [&](const std::string& f) {
      if (std::find_if(next.begin(), next.end(), [&](const auto& w) { return w.first == f; }) != next.end()) return;
      auto old = std::find_if(watched_.begin(), watched_.end(), [&](const auto& w) { return w.first == f; });
      next.emplace_back(f, old != watched_.end() ? old->second : stamp_of(f));
    };
    add(site_.path);
    for (const std::string& f : files) add(f);
    watched_ = std::move(next);
  }

  void poll() {
    timer_.expires_after(std::chrono::milliseconds(200));
    timer_.async_wait([self = shared_from_this()](beast::error_code ec) {
      if (ec || self->closed_ || !self->server_) return;
      bool changed = false;
      for (auto& [file, stamp] : self->watched_) changed |= stamp_of(file) != stamp;
      if (changed) self->reload();
      self->poll();
    });
  }

  void reload() {
    std::optional<std::string> text = read_file_bytes(site_.path);
    if (!text) return;  // mid-save (an editor's rename): try again at the next poll
    ++version_;
    server_->handle(json{{"jsonrpc", "2.0"}, {"method", "textDocument/didChange"},
                         {"params", {{"textDocument", {{"uri", site_.uri}, {"version", version_}}},
                                     {"contentChanges", json::array({{{"text", *text}}})}}}}
                        .dump());
    for (auto& [file, stamp] : watched_) stamp = stamp_of(file);
    send(json{{"jsonrpc", "2.0"}, {"method", "nome/changed"}, {"params", {{"uri", site_.uri}, {"version", version_}}}}
             .dump());
  }

  void read() {
    ws_.async_read(buffer_, [self = shared_from_this()](beast::error_code ec, size_t) {
      if (ec) {
        self->closed_ = true;
        self->timer_.cancel();
        return;
      }
      std::string text = beast::buffers_to_string(self->buffer_.data());
      self->buffer_.consume(self->buffer_.size());
      self->take(std::move(text));
      self->read();
    });
  }

  // A message from the browser: the preview's requests go to the server, anything else is
  // refused (the page must not close documents or stop the server).
  void take(std::string text) {
    if (!server_) return;
    json m = json::parse(text, nullptr, false);
    static const std::set<std::string> kAllowed = {"nome/preview", "nome/setParameter", "nome/saveScene",
                                                   "$/cancelRequest"};
    const bool ok = m.is_object() && m.contains("method") && m["method"].is_string() &&
                    kAllowed.contains(m["method"].get<std::string>()) &&
                    !(m.contains("id") && m["id"].is_string() && m["id"].get<std::string>().rfind("view-", 0) == 0);
    if (ok) {
      server_->handle(text);
    } else if (m.is_object() && m.contains("id")) {
      send(json{{"jsonrpc", "2.0"}, {"id", m["id"]},
                {"error", {{"code", lsp::error_code::MethodNotFound}, {"message", "nomec view accepts only nome/preview, nome/setParameter and nome/saveScene"}}}}
               .dump());
    }
  }

  void send(std::string m) {
    if (closed_) return;
    out_.push_back(std::move(m));
    if (out_.size() == 1) write();
  }

  void write() {
    ws_.text(true);
    ws_.async_write(net::buffer(out_.front()), [self = shared_from_this()](beast::error_code ec, size_t) {
      if (ec) {
        self->closed_ = true;
        return;
      }
      self->out_.pop_front();
      if (!self->out_.empty()) self->write();
    });
  }

  websocket::stream<beast::tcp_stream> ws_;
  Site& site_;
  net::io_context& ioc_;
  net::steady_timer timer_;
  Slot slot_;
  beast::flat_buffer buffer_;
  std::deque<std::string> out_;
  std::unique_ptr<lsp::Server> server_;
  std::vector<std::pair<std::string, Stamp>> watched_;
  int64_t version_ = 1;
  bool closed_ = false;
};

http::response<http::string_body> text_response(http::status status, const std::string& body, unsigned version) {
  http::response<http::string_body> res{status, version};
  res.set(http::field::content_type, "text/plain; charset=utf-8");
  res.set(http::field::cache_control, "no-store");
  res.body() = body;
  res.prepare_payload();
  return res;
}

// The app's files, by exact name only.
http::response<http::string_body> static_response(const Site& site, const http::request<http::string_body>& req) {
  std::string_view target = sv(req.target());
  if (size_t q = target.find('?'); q != std::string_view::npos) target = target.substr(0, q);
  static const std::pair<std::string_view, std::pair<const char*, const char*>> kFiles[] = {
      {"/", {"index.html", "text/html; charset=utf-8"}},
      {"/index.html", {"index.html", "text/html; charset=utf-8"}},
      {"/app.js", {"app.js", "text/javascript; charset=utf-8"}},
      {"/style.css", {"style.css", "text/css; charset=utf-8"}}};
  if (req.method() != http::verb::get && req.method() != http::verb::head) {
    return text_response(http::status::method_not_allowed, "GET only\n", req.version());
  }
  for (const auto& [path, file] : kFiles) {
    if (target != path) continue;
    std::optional<std::string> body = read_file_bytes(site.app_dir + "/" + file.first);
    if (!body) return text_response(http::status::not_found, "the preview app is missing\n", req.version());
    http::response<http::string_body> res{http::status::ok, req.version()};
    res.set(http::field::content_type, file.second);
    res.set(http::field::cache_control, "no-store");
    res.set("X-Content-Type-Options", "nosniff");
    res.set("Content-Security-Policy",
            fmt::format("default-src 'self'; connect-src ws://127.0.0.1:{0} ws://localhost:{0}; img-src 'self' blob: data:",
                        site.port));
    res.body() = std::move(*body);
    res.prepare_payload();
    return res;
  }
  return text_response(http::status::not_found, "not found\n", req.version());
}

class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(tcp::socket&& socket, Site& site, net::io_context& ioc, Slot slot)
      : stream_(std::move(socket)), site_(site), ioc_(ioc), slot_(std::move(slot)) {}
  void run() { read(); }

 private:
  void read() {
    req_ = {};
    stream_.expires_after(std::chrono::seconds(30));
    http::async_read(stream_, buffer_, req_, [self = shared_from_this()](beast::error_code ec, size_t) {
      if (ec) {
        beast::error_code ignored;
        self->stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
        return;
      }
      self->answer();
    });
  }

  void answer() {
    // One Host names the server (RFC 9112: 400 without one or with several); with two,
    // which one a check reads and which one a proxy reads could differ.
    const size_t hosts = req_.count(http::field::host);
    const size_t origins = req_.count(http::field::origin);
    if (hosts != 1 || origins > 1) {
      std::cerr << fmt::format("nomec view: refused a request with {} Host and {} Origin headers\n", hosts, origins);
      return respond(text_response(http::status::bad_request,
                                   "nomec view needs exactly one Host header and at most one Origin header\n",
                                   req_.version()),
                     /*keep_alive=*/false);
    }
    if (!allowed(site_, req_)) {
      std::cerr << fmt::format("nomec view: refused a request from Host `{}`, Origin `{}`\n",
                               sv(req_[http::field::host]), sv(req_[http::field::origin]));
      return respond(text_response(http::status::forbidden,
                                   "nomec view answers only pages it served itself (Host/Origin refused)\n", req_.version()));
    }
    if (websocket::is_upgrade(req_)) {
      if (sv(req_.target()) != "/rpc") return respond(text_response(http::status::not_found, "not found\n", req_.version()));
      stream_.expires_never();
      auto ws = std::make_shared<WsSession>(stream_.release_socket(), site_, ioc_, std::move(slot_));
      std::erase_if(site_.sessions, [](const std::weak_ptr<WsSession>& w) { return w.expired(); });
      site_.sessions.push_back(ws);
      ws->run(std::move(req_));
      return;
    }
    respond(static_response(site_, req_));
  }

  void respond(http::response<http::string_body> res, bool keep_alive = true) {
    res.keep_alive(keep_alive && req_.keep_alive());
    auto sp = std::make_shared<http::response<http::string_body>>(std::move(res));
    http::async_write(stream_, *sp, [self = shared_from_this(), sp](beast::error_code ec, size_t) {
      if (ec || !sp->keep_alive()) {
        beast::error_code ignored;
        self->stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
        return;
      }
      self->read();
    });
  }

  beast::tcp_stream stream_;
  Site& site_;
  net::io_context& ioc_;
  Slot slot_;
  beast::flat_buffer buffer_;
  http::request<http::string_body> req_;
};

// Takes connections until closed. When the process is out of descriptors (EMFILE, ENFILE)
// or memory, the waiting connection stays in the listen queue and accepting resumes after
// a pause (10 ms, doubling up to 1 s) — never stops. A connection past
// kViewMaxConnections is answered 503 and closed at once.
class Listener {
 public:
  Listener(tcp::acceptor& acceptor, Site& site, net::io_context& ioc)
      : acceptor_(acceptor), site_(site), ioc_(ioc), timer_(ioc) {}

  void accept() {
    acceptor_.async_accept(ioc_, [this](beast::error_code ec, tcp::socket socket) { accepted(ec, std::move(socket)); });
  }

  void close() {
    beast::error_code ignored;
    acceptor_.close(ignored);
    timer_.cancel();
  }

 private:
  void accepted(beast::error_code ec, tcp::socket socket) {
    if (!acceptor_.is_open()) return;  // closed by Ctrl-C
    if (ec) {
      if (pause_.count() == 0) {
        std::cerr << fmt::format("nomec view: cannot accept connections for now ({}); trying again\n", ec.message());
      }
      pause_ = std::clamp(pause_ * 2, std::chrono::milliseconds(10), std::chrono::milliseconds(1000));
      timer_.expires_after(pause_);
      timer_.async_wait([this](beast::error_code wait_ec) {
        if (!wait_ec && acceptor_.is_open()) accept();
      });
      return;
    }
    if (pause_.count() != 0) {
      std::cerr << "nomec view: accepting connections again\n";
      pause_ = {};
    }
    if (site_.connections >= kViewMaxConnections) {
      refuse_busy(socket);
    } else {
      std::make_shared<HttpSession>(std::move(socket), site_, ioc_, Slot(site_.connections))->run();
    }
    accept();
  }

  // A fresh socket's send buffer takes the short answer whole; it is never waited for.
  static void refuse_busy(tcp::socket& socket) {
    static const std::string kBusy = [] {
      const std::string body = fmt::format("nomec view has {} connections open; try again\n", kViewMaxConnections);
      return fmt::format(
          "HTTP/1.1 503 Service Unavailable\r\nContent-Type: text/plain; charset=utf-8\r\n"
          "Content-Length: {}\r\nRetry-After: 1\r\nConnection: close\r\n\r\n{}",
          body.size(), body);
    }();
    beast::error_code ignored;
    socket.non_blocking(true, ignored);
    socket.write_some(net::buffer(kBusy), ignored);
    socket.shutdown(tcp::socket::shutdown_send, ignored);
    socket.close(ignored);
  }

  tcp::acceptor& acceptor_;
  Site& site_;
  net::io_context& ioc_;
  net::steady_timer timer_;
  std::chrono::milliseconds pause_{0};
};

// The built app: --app-dir, $NOMEC_PREVIEW_DIR, the build tree, or share/nomec/preview
// beside the installed binary.
std::string find_app_dir(const ViewCommand& c) {
  std::vector<std::string> candidates;
  if (!c.app_dir.empty()) candidates.push_back(c.app_dir);  // given: the only candidate
  if (const char* env = std::getenv("NOMEC_PREVIEW_DIR")) candidates.emplace_back(env);
#ifdef NOMEC_PREVIEW_BUILD_DIR
  candidates.emplace_back(NOMEC_PREVIEW_BUILD_DIR);
#endif
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) candidates.push_back((exe.parent_path().parent_path() / "share/nomec/preview").string());
  if (!c.app_dir.empty()) candidates.resize(1);
  for (const std::string& d : candidates) {
    if (fs::exists(fs::path(d) / "index.html") && fs::exists(fs::path(d) / "app.js")) return d;
  }
  return {};
}

void open_browser(const std::string& url) {
  pid_t pid = 0;
  const char* argv[] = {"xdg-open", url.c_str(), nullptr};
  if (posix_spawnp(&pid, "xdg-open", nullptr, nullptr, const_cast<char**>(argv), environ) != 0) {
    std::cerr << "nomec view: could not run xdg-open; open " << url << " yourself\n";
  }
}

}  // namespace

int run_view(const ViewCommand& command) {
  // No `use_huge_pages_from_now()` here (tools/allocator.h), unlike the other commands that
  // build meshes: its extent hooks on jemalloc's arena 0 deadlocked the allocator when
  // several pages' language servers ended at once (their threads exiting while others
  // freed memory; ViewLoad.PagesPastTheCapAreRefusedWithAReasonAndTheOthersServed hung
  // every time). The kernel still asks for huge pages for its large arrays.
  Site site;
  std::error_code ec;
  site.path = fs::absolute(command.file, ec).lexically_normal().string();
  if (ec || !read_file_bytes(site.path)) {
    std::cerr << fmt::format("nomec view: cannot read `{}`: {}\n", command.file, std::strerror(ec ? ec.value() : errno));
    return 1;
  }
  site.uri = lsp::path_to_uri(site.path);
  site.app_dir = find_app_dir(command);
  if (site.app_dir.empty()) {
    std::cerr << "nomec view: the preview app is not built (configure with node and npm installed, or pass "
                 "--app-dir DIR holding index.html and app.js)\n";
    return 1;
  }
  std::optional<LanguageServers> servers;  // outlives the sessions (they stop their servers through it)
  try {
    servers.emplace();
  } catch (const std::system_error& e) {
    std::cerr << fmt::format("nomec view: cannot start a thread: {}\n", e.what());
    return 1;
  }
  site.servers = &*servers;
  net::io_context ioc{1};
  tcp::acceptor acceptor(ioc);
  try {
    const tcp::endpoint at(net::ip::make_address("127.0.0.1"), static_cast<unsigned short>(command.port));
    acceptor.open(at.protocol());
    acceptor.set_option(net::socket_base::reuse_address(true));
    acceptor.bind(at);
    acceptor.listen();
  } catch (const boost::system::system_error& e) {
    std::cerr << fmt::format("nomec view: cannot listen on 127.0.0.1:{}: {}\n", command.port, e.what());
    return 1;
  }
  site.port = acceptor.local_endpoint().port();
  const std::string url = fmt::format("http://127.0.0.1:{}/", site.port);
  std::cout << fmt::format("nomec view: serving {} at {} (Ctrl-C stops)\n", command.file, url) << std::flush;
  if (command.open) open_browser(url);
  Listener listener(acceptor, site, ioc);
  net::signal_set signals(ioc, SIGINT, SIGTERM);
  signals.async_wait([&](beast::error_code, int) {
    listener.close();
    for (const auto& w : site.sessions) {
      if (auto s = w.lock()) s->stop();
    }
    ioc.stop();
  });
  listener.accept();
  ioc.run();
  // The language servers stop on their own threads; one whose scene is still being checked
  // (a Tcl command that runs for minutes) is not waited for: the process ends without it.
  const bool all_stopped = servers->wait_stopped(std::chrono::milliseconds(kViewStopGraceMs));
  std::cout << "nomec view: stopped\n" << std::flush;
  if (!all_stopped) {
    std::cerr << "nomec view: a page's scene was still being checked; stopped without waiting for it\n" << std::flush;
    std::fflush(nullptr);
    std::_Exit(0);
  }
  return 0;
}

#endif

}  // namespace nomec::tools
