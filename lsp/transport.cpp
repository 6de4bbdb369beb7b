// `nomec --lsp`: the stdio transport. Reads LSP base-protocol frames (`Content-Length`
// header, blank line, JSON body) from stdin, hands each body to a `Server`, and writes its
// messages to stdout with the same framing. Ends on `exit` or end of input.
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

#include "lsp/server.h"

namespace nomec::lsp {

namespace {

// Largest body accepted; bigger frames are skipped (their bytes are read and dropped).
constexpr size_t kMaxBody = size_t{512} << 20;

// Reads one header line without its `\r\n`; nullopt at end of input.
std::optional<std::string> read_line(std::FILE* in) {
  std::string line;
  for (;;) {
    int c = std::fgetc(in);
    if (c == EOF) return line.empty() ? std::nullopt : std::optional<std::string>(line);
    if (c == '\n') break;
    if (line.size() < 4096) line += static_cast<char>(c);
  }
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return line;
}

enum class Frame { Message, Skipped, End };

Frame read_frame(std::FILE* in, std::string& body) {
  std::optional<size_t> length;
  bool bad_header = false;
  for (;;) {
    std::optional<std::string> line = read_line(in);
    if (!line) return Frame::End;
    if (line->empty()) {
      if (!length && !bad_header) continue;  // stray blank line between frames
      break;
    }
    constexpr std::string_view kName = "content-length:";
    std::string lower = *line;
    for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (lower.rfind(kName, 0) == 0) {
      const char* digits = line->c_str() + kName.size();
      char* end = nullptr;
      unsigned long long n = std::strtoull(digits, &end, 10);
      if (end == digits) {
        bad_header = true;
      } else {
        length = static_cast<size_t>(n);
      }
    }
  }
  if (!length) return Frame::Skipped;
  if (*length > kMaxBody) {
    for (size_t left = *length; left > 0; --left) {
      if (std::fgetc(in) == EOF) return Frame::End;
    }
    return Frame::Skipped;
  }
  body.resize(*length);
  size_t got = std::fread(body.data(), 1, *length, in);
  if (got != *length) return Frame::End;  // truncated input
  return Frame::Message;
}

}  // namespace

int run_stdio(ServerOptions options) {
  std::signal(SIGPIPE, SIG_IGN);  // a client that went away must not kill us mid-write
  std::FILE* out = stdout;
  Server server(
      [out](std::string message) {
        std::fprintf(out, "Content-Length: %zu\r\n\r\n", message.size());
        std::fwrite(message.data(), 1, message.size(), out);
        std::fflush(out);
      },
      options);
  std::string body;
  for (;;) {
    Frame f = read_frame(stdin, body);
    if (f == Frame::End) break;
    if (f == Frame::Skipped) {
      server.handle("{");  // answered as a parse error, like any malformed message
      continue;
    }
    server.handle(body);
    if (server.exit_requested()) break;
  }
  server.wait_idle();
  int code = server.exit_requested() ? server.exit_code() : 1;
  if (server.background_busy()) {
    // A long check or scene evaluation cannot be interrupted; end without waiting for it.
    std::fflush(out);
    std::_Exit(code);
  }
  return code;
}

}  // namespace nomec::lsp
