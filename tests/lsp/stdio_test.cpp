// End-to-end over pipes: starts the real `nomec --lsp` binary, speaks framed JSON-RPC to
// it (initialize → didOpen → diagnostics → shutdown → exit) and checks it exits with code
// 0 and is gone; also that a client vanishing (end of input) ends the server.
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <nlohmann/json.hpp>
#include <functional>
#include <string>
#include <thread>

namespace {

using json = nlohmann::json;

class Process {
 public:
  Process() {
    int in[2], out[2];
    EXPECT_EQ(pipe(in), 0);
    EXPECT_EQ(pipe(out), 0);
    pid_ = fork();
    if (pid_ == 0) {
      dup2(in[0], 0);
      dup2(out[1], 1);
      close(in[0]);
      close(in[1]);
      close(out[0]);
      close(out[1]);
      execl(NOMEC_BINARY, NOMEC_BINARY, "--lsp", "--stdio", static_cast<char*>(nullptr));
      _exit(127);
    }
    close(in[0]);
    close(out[1]);
    to_ = in[1];
    from_ = out[0];
  }
  ~Process() {
    if (to_ >= 0) close(to_);
    close(from_);
    if (pid_ > 0 && !reaped_) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  void send(const json& m) {
    std::string body = m.dump();
    send_raw("Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body);
  }
  void send_raw(const std::string& bytes) {
    ASSERT_EQ(write(to_, bytes.data(), bytes.size()), static_cast<ssize_t>(bytes.size()));
  }
  void close_input() {
    close(to_);
    to_ = -1;
  }
  // Reads the next framed message (or null on timeout / end of output).
  json read(std::chrono::milliseconds timeout = std::chrono::seconds(20)) {
    auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      size_t header_end = buffer_.find("\r\n\r\n");
      if (header_end != std::string::npos) {
        size_t len = std::stoul(buffer_.substr(buffer_.find(':') + 1, header_end));
        if (buffer_.size() >= header_end + 4 + len) {
          json m = json::parse(buffer_.substr(header_end + 4, len));
          buffer_.erase(0, header_end + 4 + len);
          return m;
        }
      }
      auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) return nullptr;
      pollfd p{from_, POLLIN, 0};
      if (poll(&p, 1, static_cast<int>(left.count())) <= 0) return nullptr;
      char chunk[65536];
      ssize_t n = ::read(from_, chunk, sizeof chunk);
      if (n <= 0) return nullptr;
      buffer_.append(chunk, static_cast<size_t>(n));
    }
  }
  json read_until(const std::function<bool(const json&)>& want) {
    for (;;) {
      json m = read();
      if (m.is_null() || want(m)) return m;
    }
  }
  // Waits for the process to end; returns its exit code, or -1 if it is still running.
  int wait_exit(std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
    auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        reaped_ = true;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return -1;
  }

 private:
  pid_t pid_ = -1;
  int to_ = -1;
  int from_ = -1;
  bool reaped_ = false;
  std::string buffer_;
};

TEST(LspStdio, SessionEndsWithExitCodeZero) {
  Process p;
  p.send({{"jsonrpc", "2.0"}, {"id", 1}, {"method", "initialize"}, {"params", {{"capabilities", json::object()}}}});
  json init = p.read_until([](const json& m) { return m.value("id", json()) == 1; });
  ASSERT_TRUE(init.contains("result")) << init.dump();
  EXPECT_EQ(init["result"]["capabilities"]["textDocumentSync"]["change"], 2);
  p.send({{"jsonrpc", "2.0"}, {"method", "initialized"}, {"params", json::object()}});
  const std::string uri = "file:///tmp/lsp-stdio/a.nome";
  p.send({{"jsonrpc", "2.0"},
          {"method", "textDocument/didOpen"},
          {"params", {{"textDocument", {{"uri", uri}, {"languageId", "nome"}, {"version", 1},
                                        {"text", "# a scene\ninstance x nosuch endinstance\n"}}}}}});
  json diags = p.read_until([](const json& m) { return m.value("method", "") == "textDocument/publishDiagnostics"; });
  ASSERT_FALSE(diags.is_null());
  ASSERT_EQ(diags["params"]["diagnostics"].size(), 1u) << diags.dump();
  EXPECT_EQ(diags["params"]["diagnostics"][0]["code"], "UnknownName");
  EXPECT_EQ(diags["params"]["diagnostics"][0]["range"]["start"]["line"], 1);
  EXPECT_EQ(diags["params"]["diagnostics"][0]["range"]["start"]["character"], 11);
  // A malformed frame body is answered with a parse error, and the session goes on.
  p.send_raw("Content-Length: 5\r\n\r\n{oops");
  json parse_error = p.read_until([](const json& m) { return m.contains("error"); });
  EXPECT_EQ(parse_error["error"]["code"], -32700);
  EXPECT_TRUE(parse_error["id"].is_null());
  p.send({{"jsonrpc", "2.0"}, {"id", 2}, {"method", "shutdown"}});
  json sd = p.read_until([](const json& m) { return m.value("id", json()) == 2; });
  EXPECT_TRUE(sd.contains("result") && sd["result"].is_null()) << sd.dump();
  p.send({{"jsonrpc", "2.0"}, {"method", "exit"}});
  EXPECT_EQ(p.wait_exit(), 0);
}

// A frame whose header is malformed (a negative or absurd Content-Length, one that is not a
// number, none at all, a line that is no header) is answered with a parse error and skipped,
// body included, up to the next `Content-Length:`: the next well-formed message is answered.
// `Content-Length: -1` used to be read as 2^64 - 1 and the rest of the stream dropped.
TEST(LspStdio, MalformedHeadersAreSkippedAndTheNextMessageIsAnswered) {
  Process p;
  p.send({{"jsonrpc", "2.0"}, {"id", 1}, {"method", "initialize"}, {"params", {{"capabilities", json::object()}}}});
  ASSERT_TRUE(p.read_until([](const json& m) { return m.value("id", json()) == 1; }).contains("result"));
  const std::string hover_body = json{{"jsonrpc", "2.0"}, {"id", 99}, {"method", "shutdown"}}.dump();
  const char* bad_frames[] = {
      "Content-Length: -1\r\n\r\n",
      "Content-Length: -1\r\n\r\n{\"jsonrpc\":\"2.0\",\"id\":98,\"method\":\"shutdown\"}",
      "Content-Length: 99999999999999999999999\r\n\r\n{\"x\":1}",
      "Content-Length: 1099511627776\r\n\r\n",  // 1 TiB
      "Content-Length: 12abc\r\n\r\n{\"x\":1}",
      "Content-Length: +5\r\n\r\n{\"x\":1}",
      "Content-Length:\r\n\r\n",
      "Content-Type: application/json\r\n\r\n{\"x\":1}",
      "garbage without a colon\r\n\r\n",
      "Content-Length: 5\r\nContent-Length: 6\r\n\r\n{\"x\":1}",
  };
  int64_t id = 10;
  for (const char* bad : bad_frames) {
    SCOPED_TRACE(bad);
    p.send_raw(bad);
    json parse_error = p.read_until([](const json& m) { return m.contains("error"); });
    ASSERT_FALSE(parse_error.is_null());
    EXPECT_EQ(parse_error["error"]["code"], -32700);
    EXPECT_TRUE(parse_error["id"].is_null());
    // The next message, right after the bad frame's bytes, is read and answered.
    const std::string body = json{{"jsonrpc", "2.0"}, {"id", id}, {"method", "textDocument/hover"},
                                  {"params", {{"textDocument", {{"uri", "file:///none.nome"}}},
                                              {"position", {{"line", 0}, {"character", 0}}}}}}
                                 .dump();
    p.send_raw("Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body);
    json answer = p.read_until([&](const json& m) { return m.value("id", json()) == id; });
    ASSERT_FALSE(answer.is_null()) << "no answer after the malformed frame";
    ++id;
  }
  p.send_raw("Content-Length: " + std::to_string(hover_body.size()) + "\r\n\r\n" + hover_body);
  json sd = p.read_until([](const json& m) { return m.value("id", json()) == 99; });
  EXPECT_TRUE(sd.contains("result")) << sd.dump();
  p.send({{"jsonrpc", "2.0"}, {"method", "exit"}});
  EXPECT_EQ(p.wait_exit(), 0);
}

TEST(LspStdio, EndOfInputEndsTheServer) {
  Process p;
  p.send({{"jsonrpc", "2.0"}, {"id", 1}, {"method", "initialize"}, {"params", {{"capabilities", json::object()}}}});
  ASSERT_FALSE(p.read().is_null());
  p.close_input();
  EXPECT_EQ(p.wait_exit(), 1);  // no shutdown/exit: exit code 1
}

}  // namespace
