// Fuzz-style session test: thousands of seeded random incremental edits (non-ASCII,
// surrogate pairs, CR/LF/CRLF, out-of-range positions), stale versions, malformed and
// truncated messages and wrong parameter types. The server's text must match a mirror
// kept in UTF-16 by the test, and the server must still answer and shut down cleanly.
#include <gtest/gtest.h>

#include <random>

#include "lsp_client.h"

namespace nomec::lsp::test {
namespace {

std::u16string to_u16(const std::string& s) {
  std::u16string out;
  for (size_t i = 0; i < s.size();) {
    unsigned char c = static_cast<unsigned char>(s[i]);
    uint32_t cp;
    int n;
    if (c < 0x80) { cp = c; n = 1; }
    else if (c < 0xE0) { cp = c & 0x1F; n = 2; }
    else if (c < 0xF0) { cp = c & 0x0F; n = 3; }
    else { cp = c & 0x07; n = 4; }
    for (int k = 1; k < n; ++k) cp = (cp << 6) | (static_cast<unsigned char>(s[i + k]) & 0x3F);
    i += static_cast<size_t>(n);
    if (cp >= 0x10000) {
      cp -= 0x10000;
      out += static_cast<char16_t>(0xD800 + (cp >> 10));
      out += static_cast<char16_t>(0xDC00 + (cp & 0x3FF));
    } else {
      out += static_cast<char16_t>(cp);
    }
  }
  return out;
}

std::string to_u8(const std::u16string& s) {
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    uint32_t cp = s[i];
    if (cp >= 0xD800 && cp < 0xDC00 && i + 1 < s.size()) {
      cp = 0x10000 + ((cp - 0xD800) << 10) + (s[i + 1] - 0xDC00);
      ++i;
    }
    if (cp < 0x80) {
      out += static_cast<char>(cp);
    } else if (cp < 0x800) {
      out += static_cast<char>(0xC0 | (cp >> 6));
      out += static_cast<char>(0x80 | (cp & 0x3F));
    } else if (cp < 0x10000) {
      out += static_cast<char>(0xE0 | (cp >> 12));
      out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (cp & 0x3F));
    } else {
      out += static_cast<char>(0xF0 | (cp >> 18));
      out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
      out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (cp & 0x3F));
    }
  }
  return out;
}

// The LSP meaning of a position in a UTF-16 text, written independently of lsp/text.cpp:
// lines end at `\n`, `\r\n` or `\r`; positions clamp to the line content and to the text.
size_t mirror_offset(const std::u16string& s, uint32_t line, uint32_t character) {
  size_t i = 0;
  for (uint32_t l = 0; l < line; ++l) {
    while (i < s.size() && s[i] != u'\n' && s[i] != u'\r') ++i;
    if (i == s.size()) return s.size();
    if (s[i] == u'\r' && i + 1 < s.size() && s[i + 1] == u'\n') ++i;
    ++i;
  }
  size_t end = i;
  while (end < s.size() && s[end] != u'\n' && s[end] != u'\r') ++end;
  size_t at = std::min(end, i + character);
  if (at > i && at < s.size() && s[at] >= 0xDC00 && s[at] < 0xE000 && s[at - 1] >= 0xD800 && s[at - 1] < 0xDC00) --at;
  return at;
}

TEST(LspFuzz, RandomEditsAndMalformedMessages) {
  Client c;
  c.initialize();
  const std::string uri = "file:///tmp/lsp-test/fuzz.nome";
  std::string start = funnel_cube();
  std::u16string mirror = to_u16(start);
  c.open(uri, start, 1);
  int version = 1;
  std::mt19937 rng(20261122);
  auto pick = [&](int n) { return static_cast<int>(rng() % static_cast<unsigned>(n)); };
  const std::vector<std::string> pieces = {"instance ", "é", "😀", "\r\n", "\n", "\r", "{expr $fp_n}", "(", ")",
                                           "endinstance", "bank", " ", "x", "0.5", "(*", "*)", "#", "$", "ü ",
                                           "funnel f (3 1 0.2 0.5) endfunnel\n"};
  int malformed = 0;
  for (int iter = 0; iter < 3000; ++iter) {
    int action = pick(100);
    if (action < 70) {
      json changes = json::array();
      for (int k = 1 + pick(3); k > 0; --k) {
        uint32_t lines = static_cast<uint32_t>(std::count(mirror.begin(), mirror.end(), u'\n')) + 1;
        uint32_t l0 = static_cast<uint32_t>(pick(static_cast<int>(lines) + 2));
        uint32_t c0 = static_cast<uint32_t>(pick(60));
        uint32_t l1 = l0 + static_cast<uint32_t>(pick(3) == 0 ? pick(3) : 0);
        uint32_t c1 = l1 == l0 ? c0 + static_cast<uint32_t>(pick(8)) : static_cast<uint32_t>(pick(60));
        std::string insert;
        for (int p = pick(4); p > 0; --p) insert += pieces[static_cast<size_t>(pick(static_cast<int>(pieces.size())))];
        size_t a = mirror_offset(mirror, l0, c0);
        size_t b = mirror_offset(mirror, l1, c1);
        if (b < a) std::swap(a, b);
        mirror.replace(a, b - a, to_u16(insert));
        changes.push_back({{"range", range(static_cast<int>(l0), static_cast<int>(c0), static_cast<int>(l1),
                                           static_cast<int>(c1))},
                           {"text", insert}});
      }
      c.change(uri, ++version, changes);
    } else if (action < 75) {
      // A stale version: must be ignored.
      c.change(uri, version - pick(3), json::array({{{"range", range(0, 0, 0, 0)}, {"text", "STALE"}}}));
    } else if (action < 90) {
      ++malformed;
      switch (pick(6)) {
        case 0: {
          std::string junk;
          for (int n = pick(40); n > 0; --n) junk += static_cast<char>(pick(256));
          c.send_raw(junk);
          break;
        }
        case 1: {
          std::string msg = json{{"jsonrpc", "2.0"}, {"id", 100000 + iter}, {"method", "textDocument/codeAction"}}.dump();
          c.send_raw(msg.substr(0, static_cast<size_t>(pick(static_cast<int>(msg.size())))));
          break;
        }
        case 2:
          c.send({{"jsonrpc", "2.0"}, {"method", "textDocument/didChange"},
                  {"params", {{"textDocument", {{"uri", uri}, {"version", "v"}}}, {"contentChanges", "oops"}}}});
          break;
        case 3:
          c.send({{"jsonrpc", "2.0"}, {"method", "textDocument/didChange"},
                  {"params", {{"textDocument", {{"uri", uri}, {"version", version + 1}}},
                              {"contentChanges", json::array({{{"range", {{"start", "x"}}}, {"text", 3}}})}}}});
          break;
        case 4:
          c.send({{"jsonrpc", "2.0"}, {"id", 200000 + iter}, {"method", "textDocument/codeAction"},
                  {"params", {{"textDocument", {{"uri", uri}}}, {"range", {{"start", pos(-1, 2)}, {"end", 7}}}}}});
          break;
        default:
          c.send({{"jsonrpc", "2.0"}, {"id", {{"x", 1}}}, {"method", 17}, {"params", 4}});
          break;
      }
    } else {
      c.send_request("textDocument/codeAction", {{"textDocument", {{"uri", uri}}},
                                                  {"range", range(pick(40), pick(40), pick(40), pick(40))},
                                                  {"context", json::object()}});
    }
    if (iter % 500 == 499) {
      c.server().wait_idle();
      ASSERT_EQ(c.server().document_text(uri), to_u8(mirror)) << "after " << iter << " steps";
      c.clear();
    }
  }
  EXPECT_GT(malformed, 100);
  c.server().wait_idle();
  ASSERT_EQ(c.server().document_text(uri), to_u8(mirror));
  // Still answering, with diagnostics for the latest version.
  json d = c.diagnostics(uri, version);
  EXPECT_EQ(d["version"], version);
  json r = c.request("textDocument/codeAction",
                     {{"textDocument", {{"uri", uri}}}, {"range", range(0, 0, 0, 0)}, {"context", json::object()}});
  EXPECT_TRUE(r["result"].is_array()) << r.dump();
  // Hover on a fresh, known line appended at the end answers with the bank.
  uint32_t last = static_cast<uint32_t>(std::count(mirror.begin(), mirror.end(), u'\n')) + 5;
  c.change(uri, ++version, json::array({{{"range", range(static_cast<int>(last), 0, static_cast<int>(last), 0)},
                                         {"text", "\nbank zz\n  set q 1 0 2 1\nendbank\n"}}}));
  json h = c.request("textDocument/hover", {{"textDocument", {{"uri", uri}}}, {"position", pos(static_cast<int>(last) + 100, 0)}});
  EXPECT_TRUE(h.contains("result")) << h.dump();
  std::string text = *c.server().document_text(uri);
  EXPECT_TRUE(text.ends_with("\nbank zz\n  set q 1 0 2 1\nendbank\n")) << text;
  EXPECT_TRUE(c.request("shutdown")["result"].is_null());
  c.notify("exit");
  c.server().wait_idle();
  EXPECT_EQ(c.server().exit_code(), 0);
}

}  // namespace
}  // namespace nomec::lsp::test
