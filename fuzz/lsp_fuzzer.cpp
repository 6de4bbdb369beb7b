// libFuzzer target for the language server's input: the bytes are a client's stdin as
// `nomec --lsp` reads it (lsp/transport.cpp, `serve_stream`), in one of two shapes chosen by
// the first byte: raw (the framing itself: `Content-Length` headers, negative, absurd or
// missing lengths, truncated bodies), or one JSON-RPC message per line, each framed, after
// an `initialize` (the handlers: documents opened, edited, hovered, previewed, saved, slider
// moves; SLIDE documents run their Tcl in a worker under a small budget). The server must not
// crash, trip a sanitizer, hang, or write anything but well-formed frames of valid JSON.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "lsp/server.h"

namespace {

std::string frame(std::string_view body) {
  return "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" + std::string(body);
}

// Every message the server wrote is a frame whose body is JSON.
bool well_formed(std::string_view out) {
  while (!out.empty()) {
    constexpr std::string_view kHead = "Content-Length: ";
    if (out.substr(0, kHead.size()) != kHead) return false;
    out.remove_prefix(kHead.size());
    size_t n = 0, digits = 0;
    while (digits < out.size() && out[digits] >= '0' && out[digits] <= '9') n = n * 10 + (out[digits++] - '0');
    if (digits == 0 || out.substr(digits, 4) != "\r\n\r\n") return false;
    out.remove_prefix(digits + 4);
    if (out.size() < n || !nlohmann::json::accept(out.substr(0, n))) return false;
    out.remove_prefix(n);
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const std::string_view rest(reinterpret_cast<const char*>(data) + 1, size - 1);
  std::string stream;
  if ((data[0] & 1) != 0) {
    stream = rest;  // the framing
  } else {
    stream = frame(R"({"jsonrpc":"2.0","id":0,"method":"initialize","params":{"capabilities":{}}})");
    size_t at = 0;
    while (at <= rest.size()) {
      const size_t nl = rest.find('\n', at);
      const std::string_view line = rest.substr(at, nl == std::string_view::npos ? std::string_view::npos : nl - at);
      if (!line.empty()) stream += frame(line);
      if (nl == std::string_view::npos) break;
      at = nl + 1;
    }
  }
  std::FILE* in = fmemopen(stream.data(), stream.size(), "r");
  char* written = nullptr;
  size_t written_size = 0;
  std::FILE* out = open_memstream(&written, &written_size);
  if (in == nullptr || out == nullptr) std::abort();
  nomec::lsp::ServerOptions options;
  options.debounce_ms = 0;
  options.full_check_delay_ms = 0;
  options.idle_release_ms = 0;
  options.geometry = (data[0] & 2) != 0;
  options.tcl_milliseconds = 150;
  options.tcl_move_milliseconds = 50;
  try {
    (void)nomec::lsp::serve_stream(in, out, options, false);
  } catch (...) {
    std::abort();  // the server answers every message; it never throws
  }
  std::fclose(in);
  std::fclose(out);
  const bool ok = well_formed(std::string_view(written, written_size));
  if (!ok) std::fprintf(stderr, "lsp_fuzzer: the server wrote something that is not a frame of JSON:\n%.*s\n",
                        static_cast<int>(written_size), written);
  std::free(written);
  if (!ok) std::abort();
  return 0;
}
