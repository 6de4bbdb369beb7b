// `nomec --lsp`: the stdio transport. Reads LSP base-protocol frames (`Content-Length`
// header, blank line, JSON body) from stdin, hands each body to a `Server`, and writes its
// messages to stdout with the same framing. A malformed frame (a negative, absurd or
// missing length, a line that is no header) is answered with a parse error and skipped up
// to the next `Content-Length:`, so the next well-formed message is read and answered.
// Ends on `exit` or end of input.
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cctype>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "lsp/server.h"

namespace nomec::lsp {

namespace {

// Largest body accepted; a frame that declares more is refused like a malformed header.
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

constexpr std::string_view kLengthHeader = "content-length:";

bool starts_with_length_header(std::string_view line) {
  if (line.size() < kLengthHeader.size()) return false;
  for (size_t i = 0; i < kLengthHeader.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(line[i])) != kLengthHeader[i]) return false;
  }
  return true;
}

// The value of a `Content-Length` header: decimal digits, blanks around them allowed, at
// most kMaxBody. Nullopt for anything else: a sign (`-1`), other characters, an empty
// value, or a length too large to be a message (`99999999999999999999`).
std::optional<size_t> parse_length(std::string_view v) {
  while (!v.empty() && (v.front() == ' ' || v.front() == '\t')) v.remove_prefix(1);
  while (!v.empty() && (v.back() == ' ' || v.back() == '\t')) v.remove_suffix(1);
  if (v.empty() || v.size() > 12) return std::nullopt;
  size_t n = 0;
  for (char c : v) {
    if (c < '0' || c > '9') return std::nullopt;
    n = n * 10 + static_cast<size_t>(c - '0');
  }
  if (n > kMaxBody) return std::nullopt;
  return n;
}

// After a malformed frame, the bytes up to the next `Content-Length:` (any case), which
// starts the next frame: the malformed frame's body, if it has one, is dropped. Returns
// that header line (from `Content-Length:` to the end of its line), or nullopt at end of
// input. The header is looked for anywhere, not only at a line start, since a body need
// not end with a line break.
std::optional<std::string> skip_to_next_frame(std::FILE* in) {
  size_t matched = 0;
  while (matched < kLengthHeader.size()) {
    const int c = std::fgetc(in);
    if (c == EOF) return std::nullopt;
    if (std::tolower(c) == kLengthHeader[matched]) {
      ++matched;
    } else {
      matched = std::tolower(c) == kLengthHeader[0] ? 1 : 0;  // `c` occurs once in the name
    }
  }
  std::optional<std::string> rest = read_line(in);
  return "Content-Length:" + rest.value_or("");
}

enum class Frame { Message, Malformed, End };

// Reads one frame. `first` is its first header line when the caller already has it (after
// skip_to_next_frame). Malformed: a header block without a valid `Content-Length` (missing,
// negative, not a number, too large, given twice with different values) or with a line that
// is no header (no `:`); the caller answers it and looks for the next frame.
Frame read_frame(std::FILE* in, std::optional<std::string> first, std::string& body) {
  std::optional<size_t> length;
  bool malformed = false;
  bool any_header = false;
  for (;;) {
    std::optional<std::string> line = first ? std::exchange(first, std::nullopt) : read_line(in);
    if (!line) return Frame::End;
    if (line->empty()) {
      if (!any_header) continue;  // stray blank line between frames
      break;
    }
    any_header = true;
    if (starts_with_length_header(*line)) {
      const std::optional<size_t> n = parse_length(std::string_view(*line).substr(kLengthHeader.size()));
      if (!n || (length && *length != *n)) malformed = true;
      length = n;
    } else if (line->find(':') == std::string::npos) {
      malformed = true;  // not a header: e.g. a body sent without a frame
    }
  }
  if (malformed || !length) return Frame::Malformed;
  body.resize(*length);
  size_t got = std::fread(body.data(), 1, *length, in);
  if (got != *length) return Frame::End;  // truncated input
  return Frame::Message;
}

}  // namespace

int serve_stream(std::FILE* in, std::FILE* out, ServerOptions options, bool exit_when_busy) {
  Server server(
      [out](std::string message) {
        std::fprintf(out, "Content-Length: %zu\r\n\r\n", message.size());
        std::fwrite(message.data(), 1, message.size(), out);
        std::fflush(out);
      },
      options);
  std::string body;
  std::optional<std::string> next_header;  // the first line of the next frame, when found
  for (;;) {
    Frame f = read_frame(in, std::exchange(next_header, std::nullopt), body);
    if (f == Frame::End) break;
    if (f == Frame::Malformed) {
      server.handle("{");  // answered as a parse error, like any malformed message
      next_header = skip_to_next_frame(in);
      if (!next_header) break;
      continue;
    }
    server.handle(body);
    if (server.exit_requested()) break;
  }
  server.wait_idle();
  int code = server.exit_requested() ? server.exit_code() : 1;
  if (exit_when_busy && server.background_busy()) {
    // A long check or scene evaluation cannot be interrupted; end without waiting for it.
    std::fflush(out);
    std::_Exit(code);
  }
  return code;
}

int run_stdio(ServerOptions options) {
  std::signal(SIGPIPE, SIG_IGN);  // a client that went away must not kill us mid-write
  return serve_stream(stdin, stdout, std::move(options), true);
}

}  // namespace nomec::lsp
