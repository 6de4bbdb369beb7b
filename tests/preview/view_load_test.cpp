// `nomec view` under load and abuse, on 127.0.0.1 only, with no browser: the real binary is
// started (port 0, a stand-in app folder) and driven by Boost.Beast clients. Pages past
// kViewMaxPages are refused with a close reason and the others keep being served;
// connections past kViewMaxConnections are answered 503; a burst of connections under a
// low `ulimit -n` (EMFILE) does not stop the accept loop; error replies of the language
// server reach the page; two Host headers are a 400; the system refusing a language
// server's threads refuses that page, not the server; and a page whose scene never finishes
// checking neither holds up the other pages when closed nor Ctrl-C. Every step has a
// deadline of a few seconds.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/read.hpp>
#include <boost/asio/write.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <array>
#include <chrono>
#include <deque>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "tools/view_command.h"

#if defined(__SANITIZE_ADDRESS__)
#define NOMEC_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define NOMEC_UNDER_ASAN 1
#endif
#endif

namespace {

namespace beast = boost::beast;
namespace websocket = beast::websocket;
namespace net = boost::asio;
namespace fs = std::filesystem;
using tcp = net::ip::tcp;
using json = nlohmann::json;
using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;
using nomec::tools::kViewMaxConnections;
using nomec::tools::kViewMaxPages;
using nomec::tools::kViewStopGraceMs;

std::string read_all(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_file(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

// Waits until `done()` (checked every 20 ms) or `limit` passes; returns done().
bool eventually(const std::function<bool()>& done, milliseconds limit) {
  const auto end = Clock::now() + limit;
  while (!done()) {
    if (Clock::now() >= end) return false;
    std::this_thread::sleep_for(milliseconds(20));
  }
  return true;
}

// Runs the client's io_context until `done()` or `limit` passes; returns done().
bool run_until(net::io_context& ioc, const std::function<bool()>& done, milliseconds limit) {
  const auto end = Clock::now() + limit;
  while (!done() && Clock::now() < end) {
    ioc.restart();
    ioc.run_for(milliseconds(10));
  }
  return done();
}

// A temporary folder with the scene and a stand-in preview app (index.html, app.js).
struct Workspace {
  fs::path dir;
  Workspace() {
    char tmpl[] = "/tmp/nomec-view-load-XXXXXX";
    dir = mkdtemp(tmpl);
    fs::create_directory(dir / "app");
    write_file(dir / "app/index.html", "<!doctype html><title>stand-in preview</title>\n");
    write_file(dir / "app/app.js", "// stand-in\n");
  }
  ~Workspace() {
    std::error_code ignored;
    fs::remove_all(dir, ignored);
  }
};

// A running `nomec view`, its stdout and stderr in files; killed if the test leaves it.
class View {
 public:
  View(const Workspace& w, const fs::path& scene, std::optional<rlimit> files = std::nullopt,
       std::optional<std::pair<rlimit, rlimit>> memory = std::nullopt)
      : out_(w.dir / fmt("out")), err_(w.dir / fmt("err")) {
    const std::string app = (w.dir / "app").string();
    const std::string file = scene.string();
    pid_ = fork();
    if (pid_ == 0) {
      if (files) setrlimit(RLIMIT_NOFILE, &*files);
      if (memory) {
        setrlimit(RLIMIT_STACK, &memory->first);
        setrlimit(RLIMIT_AS, &memory->second);
      }
      int out = open(out_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      int err = open(err_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      dup2(out, 1);
      dup2(err, 2);
      close(out);
      close(err);
      execl(NOMEC_BINARY, NOMEC_BINARY, "view", file.c_str(), "--port", "0", "--app-dir", app.c_str(),
            static_cast<char*>(nullptr));
      _exit(127);
    }
    const bool up = eventually(
        [&] {
          const std::string out = read_all(out_);
          const size_t at = out.find("at http://127.0.0.1:");
          if (at == std::string::npos) return false;
          port_ = std::stoi(out.substr(at + 20));
          return true;
        },
        milliseconds(10000));
    EXPECT_TRUE(up) << "nomec view did not start:\n" << read_all(err_);
  }
  ~View() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  View(const View&) = delete;
  View& operator=(const View&) = delete;

  unsigned short port() const { return static_cast<unsigned short>(port_); }
  pid_t pid() const { return pid_; }
  std::string out() const { return read_all(out_); }
  std::string err() const { return read_all(err_); }
  bool running() { return pid_ > 0 && waitpid(pid_, &status_, WNOHANG) == 0; }

  /// Sends `signal` and waits at most `limit` for the exit; the exit code, or -1 if it did
  /// not end in time (then it is killed) or ended by a signal.
  int stop(int signal, milliseconds limit) {
    kill(pid_, signal);
    const bool ended = eventually([&] { return waitpid(pid_, &status_, WNOHANG) == pid_; }, limit);
    if (!ended) return -1;
    pid_ = 0;
    return WIFEXITED(status_) ? WEXITSTATUS(status_) : -1;
  }

 private:
  static std::string fmt(const char* what) {
    static int n = 0;
    return std::string(what) + std::to_string(n++);
  }
  fs::path out_;
  fs::path err_;
  pid_t pid_ = -1;
  int port_ = 0;
  int status_ = 0;
};

// A page's WebSocket: connects, then reads every message until closed.
class Page : public std::enable_shared_from_this<Page> {
 public:
  explicit Page(net::io_context& ioc) : ws_(ioc) {}

  void open(unsigned short port) {
    auto self = shared_from_this();
    beast::get_lowest_layer(ws_).expires_after(std::chrono::seconds(10));
    beast::get_lowest_layer(ws_).async_connect(
        tcp::endpoint(net::ip::make_address("127.0.0.1"), port), [self, port](beast::error_code ec) {
          if (ec) return self->fail(ec);
          beast::get_lowest_layer(self->ws_).expires_never();
          self->ws_.set_option(websocket::stream_base::timeout{std::chrono::seconds(10), std::chrono::seconds(30), false});
          self->ws_.async_handshake("127.0.0.1:" + std::to_string(port), "/rpc", [self](beast::error_code hec) {
            if (hec) return self->fail(hec);
            self->connected = true;
            self->read();
          });
        });
  }

  void send(const json& m) {
    out_.push_back(m.dump());
    if (out_.size() == 1) write();
  }

  void close() {
    auto self = shared_from_this();
    if (!connected || closed) return;
    ws_.async_close(websocket::close_code::normal, [self](beast::error_code) {});
  }

  /// The first message with this `id` (as JSON), or null.
  const json* reply(int id) const {
    for (const json& m : messages) {
      if (m.contains("id") && m["id"] == id && !m.contains("method")) return &m;
    }
    return nullptr;
  }
  const json* notification(const std::string& method) const {
    for (const json& m : messages) {
      if (m.value("method", "") == method) return &m;
    }
    return nullptr;
  }

  bool connected = false;
  bool closed = false;  // the read loop ended (a close frame, or an error)
  beast::error_code error;
  websocket::close_reason reason;
  std::vector<json> messages;

 private:
  void fail(beast::error_code ec) {
    closed = true;
    error = ec;
  }
  void read() {
    ws_.async_read(buffer_, [self = shared_from_this()](beast::error_code ec, size_t) {
      if (ec) {
        self->reason = self->ws_.reason();
        return self->fail(ec);
      }
      self->messages.push_back(json::parse(beast::buffers_to_string(self->buffer_.data()), nullptr, false));
      self->buffer_.consume(self->buffer_.size());
      self->read();
    });
  }
  void write() {
    ws_.async_write(net::buffer(out_.front()), [self = shared_from_this()](beast::error_code ec, size_t) {
      if (ec) return;
      self->out_.pop_front();
      if (!self->out_.empty()) self->write();
    });
  }

  websocket::stream<beast::tcp_stream> ws_;
  beast::flat_buffer buffer_;
  std::deque<std::string> out_;
};

// Sends `request` on a new connection and reads until the server closes it (or `limit`):
// the raw response, or nullopt when nothing came.
std::optional<std::string> exchange(unsigned short port, const std::string& request, milliseconds limit) {
  net::io_context ioc;
  tcp::socket s(ioc);
  std::string got;
  bool done = false;
  auto buf = std::make_shared<std::array<char, 4096>>();
  std::function<void()> read = [&] {
    s.async_read_some(net::buffer(*buf), [&](beast::error_code ec, size_t n) {
      got.append(buf->data(), n);
      if (ec) {
        done = true;
        return;
      }
      read();
    });
  };
  s.async_connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port), [&](beast::error_code ec) {
    if (ec) {
      done = true;
      return;
    }
    net::async_write(s, net::buffer(request), [&](beast::error_code wec, size_t) {
      if (wec) {
        done = true;
        return;
      }
      read();
    });
  });
  run_until(ioc, [&] { return done; }, limit);
  if (got.empty()) return std::nullopt;
  return got;
}

std::string get(unsigned short port, const std::string& headers) {
  return exchange(port, "GET / HTTP/1.1\r\n" + headers + "Connection: close\r\n\r\n", milliseconds(3000)).value_or("");
}

std::string host(unsigned short port) { return "Host: 127.0.0.1:" + std::to_string(port) + "\r\n"; }

// Opens a page and waits for its `nome/open`, asks for the scene and waits for the reply:
// what a browser does first. Retries for `limit` while pages are refused as busy.
::testing::AssertionResult serves_a_page(unsigned short port, milliseconds limit = milliseconds(5000)) {
  const auto end = Clock::now() + limit;
  std::string last;
  do {
    net::io_context ioc;
    auto page = std::make_shared<Page>(ioc);
    page->open(port);
    run_until(ioc, [&] { return page->closed || page->notification("nome/open") != nullptr; }, milliseconds(5000));
    if (const json* open = page->notification("nome/open")) {
      page->send({{"jsonrpc", "2.0"}, {"id", 1}, {"method", "nome/preview"}, {"params", {{"uri", (*open)["params"]["uri"]}}}});
      run_until(ioc, [&] { return page->closed || page->reply(1) != nullptr; }, milliseconds(10000));
      const json* r = page->reply(1);
      if (r == nullptr) return ::testing::AssertionFailure() << "no answer to nome/preview";
      if (!r->contains("result")) return ::testing::AssertionFailure() << "nome/preview failed: " << r->dump();
      page->close();
      run_until(ioc, [&] { return page->closed; }, milliseconds(2000));
      return ::testing::AssertionSuccess();
    }
    last = page->error.message() + " / " + std::string(page->reason.reason.data(), page->reason.reason.size());
    std::this_thread::sleep_for(milliseconds(50));
  } while (Clock::now() < end);
  return ::testing::AssertionFailure() << "no page served: " << last;
}

::testing::AssertionResult serves_its_page(unsigned short port, milliseconds limit = milliseconds(5000)) {
  const auto end = Clock::now() + limit;
  std::string last;
  do {
    last = get(port, host(port));
    if (last.rfind("HTTP/1.1 200", 0) == 0 && last.find("stand-in preview") != std::string::npos) {
      return ::testing::AssertionSuccess();
    }
    std::this_thread::sleep_for(milliseconds(50));
  } while (Clock::now() < end);
  return ::testing::AssertionFailure() << "GET / answered: `" << last << "`";
}

fs::path funnel_cube() { return fs::path(NOMEC_SOURCE_DIR) / "examples/funnel_cube.nome"; }

TEST(ViewLoad, PagesPastTheCapAreRefusedWithAReasonAndTheOthersServed) {
  Workspace w;
  View view(w, funnel_cube());
  net::io_context ioc;
  constexpr int kExtra = 8;
  std::vector<std::shared_ptr<Page>> pages;
  for (int i = 0; i < kViewMaxPages + kExtra; ++i) {
    pages.push_back(std::make_shared<Page>(ioc));
    pages.back()->open(view.port());
  }
  auto settled = [&] {
    for (const auto& p : pages) {
      if (!p->closed && p->notification("nome/open") == nullptr) return false;
    }
    return true;
  };
  ASSERT_TRUE(run_until(ioc, settled, milliseconds(20000)));
  std::vector<std::shared_ptr<Page>> served;
  int refused = 0;
  for (const auto& p : pages) {
    if (p->notification("nome/open") != nullptr) {
      served.push_back(p);
      continue;
    }
    ASSERT_TRUE(p->connected) << p->error.message();
    EXPECT_EQ(p->error, websocket::error::closed) << p->error.message();
    EXPECT_EQ(p->reason.code, websocket::close_code::try_again_later);
    EXPECT_EQ(std::string(p->reason.reason.data(), p->reason.reason.size()),
              "nomec view serves " + std::to_string(kViewMaxPages) + " pages at once: close one, then reload this page");
    ++refused;
  }
  EXPECT_EQ(static_cast<int>(served.size()), kViewMaxPages);
  EXPECT_EQ(refused, kExtra);
  EXPECT_NE(view.err().find("nomec view: refused a page"), std::string::npos) << view.err();

  // The pages it has are still served: a scene, and the language server's error replies.
  const json uri = (*served.front()->notification("nome/open"))["params"]["uri"];
  served.front()->send({{"jsonrpc", "2.0"}, {"id", 1}, {"method", "nome/preview"}, {"params", {{"uri", uri}}}});
  served.front()->send({{"jsonrpc", "2.0"}, {"id", 2}, {"method", "nome/preview"}, {"params", json::object()}});
  served.front()->send({{"jsonrpc", "2.0"}, {"id", 3}, {"method", "nome/setParameter"},
                        {"params", {{"uri", uri}, {"parameter", "fp.nothing"}, {"value", 1}}}});
  served.back()->send({{"jsonrpc", "2.0"}, {"id", 4}, {"method", "nome/preview"}, {"params", {{"uri", uri}}}});
  ASSERT_TRUE(run_until(
      ioc,
      [&] {
        return served.front()->reply(1) && served.front()->reply(2) && served.front()->reply(3) &&
               served.back()->reply(4);
      },
      milliseconds(10000)));
  EXPECT_EQ((*served.front()->reply(1))["result"]["ok"], true);
  EXPECT_EQ((*served.back()->reply(4))["result"]["ok"], true);
  const json& missing_uri = *served.front()->reply(2);
  ASSERT_TRUE(missing_uri.contains("error")) << missing_uri.dump();
  EXPECT_EQ(missing_uri["error"]["code"], -32602);  // InvalidParams, from the language server
  const json& unknown = *served.front()->reply(3);
  ASSERT_TRUE(unknown.contains("error")) << unknown.dump();
  EXPECT_NE(unknown["error"]["message"].get<std::string>().find("fp.nothing"), std::string::npos) << unknown.dump();
  // Neither the host's own replies nor the diagnostics reach the page.
  for (const json& m : served.front()->messages) {
    EXPECT_FALSE(m.contains("id") && m["id"].is_string()) << m.dump().substr(0, 200);
    EXPECT_NE(m.value("method", ""), "textDocument/publishDiagnostics");
  }

  // Closed pages free their places.
  for (const auto& p : pages) p->close();
  ASSERT_TRUE(run_until(ioc, [&] { return std::all_of(pages.begin(), pages.end(), [](const auto& p) { return p->closed; }); },
                        milliseconds(5000)));
  EXPECT_TRUE(serves_a_page(view.port()));
  EXPECT_TRUE(serves_its_page(view.port()));
  EXPECT_EQ(view.stop(SIGTERM, milliseconds(kViewStopGraceMs + 3000)), 0);
}

TEST(ViewLoad, ConnectionsPastTheCapAreAnswered503) {
  Workspace w;
  View view(w, funnel_cube());
  constexpr int kExtra = 20;
  net::io_context ioc;
  std::vector<std::unique_ptr<tcp::socket>> held;
  std::vector<std::string> got(kViewMaxConnections + kExtra);
  auto buf = std::make_shared<std::vector<std::array<char, 512>>>(got.size());
  for (size_t i = 0; i < got.size(); ++i) {
    held.push_back(std::make_unique<tcp::socket>(ioc));
    held.back()->connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), view.port()));
    held.back()->async_read_some(net::buffer((*buf)[i]), [&, i](beast::error_code ec, size_t n) {
      if (!ec) got[i].append((*buf)[i].data(), n);
    });
  }
  auto busy = [&] { return std::count_if(got.begin(), got.end(), [](const std::string& g) { return g.rfind("HTTP/1.1 503", 0) == 0; }); };
  ASSERT_TRUE(run_until(ioc, [&] { return busy() >= kExtra; }, milliseconds(5000))) << busy();
  run_until(ioc, [] { return false; }, milliseconds(200));  // no more than those
  EXPECT_EQ(busy(), kExtra);
  EXPECT_NE(std::find_if(got.begin(), got.end(), [](const std::string& g) { return !g.empty(); })->find("connections open"),
            std::string::npos);
  held.clear();
  EXPECT_TRUE(serves_its_page(view.port()));
  EXPECT_TRUE(serves_a_page(view.port()));
  EXPECT_EQ(view.stop(SIGTERM, milliseconds(kViewStopGraceMs + 3000)), 0);
}

size_t open_files(pid_t pid) {
  std::error_code ec;
  size_t n = 0;
  for (auto it = fs::directory_iterator("/proc/" + std::to_string(pid) + "/fd", ec); !ec && it != fs::directory_iterator();
       it.increment(ec)) {
    ++n;
  }
  return n;
}

TEST(ViewLoad, ABurstOfConnectionsUnderALowFileLimitDoesNotStopTheServer) {
  Workspace w;
  constexpr rlim_t kFiles = 32;  // below kViewMaxConnections: the burst runs out of descriptors
  View view(w, funnel_cube(), rlimit{kFiles, kFiles});
  std::vector<std::unique_ptr<tcp::socket>> burst;
  net::io_context ioc;
  for (int i = 0; i < 100; ++i) {
    burst.push_back(std::make_unique<tcp::socket>(ioc));
    burst.back()->connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), view.port()));
  }
  // Every descriptor is taken: the next accept fails with EMFILE.
  ASSERT_TRUE(eventually([&] { return open_files(view.pid()) >= kFiles; }, milliseconds(5000))) << open_files(view.pid());
  EXPECT_TRUE(eventually([&] { return view.err().find("cannot accept connections for now") != std::string::npos; },
                         milliseconds(3000)))
      << view.err();
  EXPECT_NE(view.err().find("Too many open files"), std::string::npos) << view.err();
  burst.clear();
  EXPECT_TRUE(serves_its_page(view.port()));
  EXPECT_TRUE(serves_a_page(view.port()));
  EXPECT_NE(view.err().find("accepting connections again"), std::string::npos) << view.err();
  EXPECT_TRUE(view.running());
  EXPECT_EQ(view.stop(SIGTERM, milliseconds(kViewStopGraceMs + 3000)), 0);
}

TEST(ViewLoad, TwoHostHeadersAreRefused) {
  Workspace w;
  View view(w, funnel_cube());
  const unsigned short port = view.port();
  EXPECT_EQ(get(port, host(port)).substr(0, 12), "HTTP/1.1 200");
  EXPECT_EQ(get(port, host(port) + "Host: evil.example\r\n").substr(0, 12), "HTTP/1.1 400");
  EXPECT_EQ(get(port, "Host: evil.example\r\n" + host(port)).substr(0, 12), "HTTP/1.1 400");
  EXPECT_EQ(get(port, host(port) + host(port)).substr(0, 12), "HTTP/1.1 400");
  EXPECT_EQ(get(port, "").substr(0, 12), "HTTP/1.1 400");  // none
  const std::string origin = "Origin: http://127.0.0.1:" + std::to_string(port) + "\r\n";
  EXPECT_EQ(get(port, host(port) + origin).substr(0, 12), "HTTP/1.1 200");
  EXPECT_EQ(get(port, host(port) + origin + "Origin: http://evil.example\r\n").substr(0, 12), "HTTP/1.1 400");
  const std::string upgrade = "Upgrade: websocket\r\nSec-WebSocket-Version: 13\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n";
  const auto ws = [&](const std::string& headers) {
    return exchange(port, "GET /rpc HTTP/1.1\r\n" + headers + upgrade + "Connection: Upgrade\r\n\r\n", milliseconds(1000))
        .value_or("")
        .substr(0, 12);
  };
  EXPECT_EQ(ws(host(port) + "Host: evil.example\r\n"), "HTTP/1.1 400");
  EXPECT_EQ(ws(host(port)), "HTTP/1.1 101");
  EXPECT_NE(view.err().find("refused a request with 2 Host"), std::string::npos) << view.err();
  EXPECT_EQ(view.stop(SIGTERM, milliseconds(kViewStopGraceMs + 3000)), 0);
}

TEST(ViewLoad, ThreadsTheSystemRefusesRefuseThePageNotTheServer) {
#if defined(NOMEC_UNDER_ASAN)
  GTEST_SKIP() << "an address-space limit leaves AddressSanitizer no room for its shadow memory";
#endif
  Workspace w;
  // Each thread reserves a 256 MiB stack (glibc sizes them from RLIMIT_STACK) in 2 GiB of
  // address space: one page's language server (four threads) fits, a second one does not.
  constexpr rlim_t kStack = rlim_t{256} << 20;
  constexpr rlim_t kSpace = rlim_t{2} << 30;
  View view(w, funnel_cube(), std::nullopt, std::pair{rlimit{kStack, kStack}, rlimit{kSpace, kSpace}});
  net::io_context ioc;
  std::vector<std::shared_ptr<Page>> pages;
  for (int i = 0; i < 3; ++i) {
    pages.push_back(std::make_shared<Page>(ioc));
    pages.back()->open(view.port());
    ASSERT_TRUE(run_until(ioc, [&] { return pages.back()->closed || pages.back()->notification("nome/open"); },
                          milliseconds(5000)));
  }
  ASSERT_NE(pages[0]->notification("nome/open"), nullptr) << view.err();
  for (int i = 1; i < 3; ++i) {
    EXPECT_EQ(pages[i]->notification("nome/open"), nullptr);
    EXPECT_EQ(pages[i]->reason.code, websocket::close_code::try_again_later);
    EXPECT_EQ(std::string(pages[i]->reason.reason.data(), pages[i]->reason.reason.size())
                  .rfind("nomec view could not start this page's language server (", 0),
              0u)
        << pages[i]->reason.reason;
  }
  EXPECT_TRUE(view.running());
  const json uri = (*pages[0]->notification("nome/open"))["params"]["uri"];
  pages[0]->send({{"jsonrpc", "2.0"}, {"id", 1}, {"method", "nome/preview"}, {"params", {{"uri", uri}}}});
  ASSERT_TRUE(run_until(ioc, [&] { return pages[0]->reply(1) != nullptr; }, milliseconds(10000)));
  EXPECT_EQ((*pages[0]->reply(1))["result"]["ok"], true);
  EXPECT_TRUE(serves_its_page(view.port()));
  // Once that page is closed, its server's threads are joined (on the stopper thread if
  // the system refuses one more) and the next page is served.
  pages[0]->close();
  ASSERT_TRUE(run_until(ioc, [&] { return pages[0]->closed; }, milliseconds(3000)));
  EXPECT_TRUE(serves_a_page(view.port()));
  EXPECT_EQ(view.stop(SIGTERM, milliseconds(kViewStopGraceMs + 3000)), 0);
}

// A scene whose check stays busy: one Tcl command that runs for minutes, which Tcl's own
// limits cannot interrupt (nomec stops the file's Tcl after 10 s; these tests end sooner).
constexpr const char* kBusyScene =
    "tclinit {\n"
    "  set s [string repeat a 40]\n"
    "  string match [string repeat *a 12]*b $s\n"
    "}\n";

// Opens a page on the busy scene and asks for it: its language server is then checking.
std::shared_ptr<Page> busy_page(net::io_context& ioc, const View& view) {
  auto page = std::make_shared<Page>(ioc);
  page->open(view.port());
  run_until(ioc, [&] { return page->closed || page->notification("nome/open"); }, milliseconds(5000));
  EXPECT_NE(page->notification("nome/open"), nullptr);
  if (const json* open = page->notification("nome/open")) {
    page->send({{"jsonrpc", "2.0"}, {"id", 1}, {"method", "nome/preview"}, {"params", {{"uri", (*open)["params"]["uri"]}}}});
  }
  run_until(ioc, [&] { return page->reply(1) != nullptr; }, milliseconds(500));
  EXPECT_EQ(page->reply(1), nullptr) << "the scene was meant to keep its check busy";
  return page;
}

TEST(ViewLoad, ABusyPageClosedDoesNotHoldUpTheOthers) {
  Workspace w;
  write_file(w.dir / "busy.slf", kBusyScene);
  View view(w, w.dir / "busy.slf");
  net::io_context ioc;
  auto page = busy_page(ioc, view);
  page->close();
  ASSERT_TRUE(run_until(ioc, [&] { return page->closed; }, milliseconds(3000)));
  // Its language server is still checking: the others are served meanwhile.
  EXPECT_TRUE(serves_its_page(view.port(), milliseconds(3000)));
  auto other = std::make_shared<Page>(ioc);
  other->open(view.port());
  EXPECT_TRUE(run_until(ioc, [&] { return other->closed || other->notification("nome/open"); }, milliseconds(3000)));
  EXPECT_NE(other->notification("nome/open"), nullptr);
}

TEST(ViewLoad, CtrlCEndsItWhileAPageIsBusy) {
  Workspace w;
  write_file(w.dir / "busy.slf", kBusyScene);
  View view(w, w.dir / "busy.slf");
  net::io_context ioc;
  auto page = busy_page(ioc, view);
  EXPECT_EQ(view.stop(SIGTERM, milliseconds(kViewStopGraceMs + 1500)), 0);
  EXPECT_NE(view.out().find("nomec view: stopped"), std::string::npos);
  EXPECT_NE(view.err().find("still being checked"), std::string::npos) << view.err();
}

}  // namespace
