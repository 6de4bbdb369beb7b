// The language server re-parses only what an edit touched: each open document keeps a
// ParseCache, so a one-character edit in a large document re-parses one top-level piece,
// and the diagnostics it publishes equal those of a fresh check of the same text.
#include <gtest/gtest.h>

#include <string>

#include "lsp_client.h"

namespace nomec::lsp::test {
namespace {

// `count` independent top-level statements: a mesh with points and a face per module.
std::string large_document(int count) {
  std::string out;
  for (int k = 0; k < count; ++k) {
    std::string n = std::to_string(k);
    out += "mesh m" + n + "\n";
    out += "  point a (0 0 " + n + ") endpoint\n";
    out += "  point b (1 0 " + n + ") endpoint\n";
    out += "  point c (0 1 " + n + ") endpoint\n";
    out += "  face f (a b c) endface\n";
    out += "endmesh\n";
  }
  return out;
}

// Replaces the character at (line, character) with `c`, as an editor's incremental change.
json replace_char(int line, int character, const std::string& c) {
  return json::array({{{"range", range(line, character, line, character + 1)}, {"text", c}}});
}

TEST(LspIncremental, OneCharacterEditReparsesOnePieceAndMatchesAFreshCheck) {
  Client c;
  c.initialize();
  const std::string uri = "file:///tmp/lsp-test/large.nome";
  const int modules = 400;
  std::string text = large_document(modules);
  c.open(uri, text, 1);
  EXPECT_TRUE(c.diagnostics(uri, 1)["diagnostics"].empty());
  std::optional<ParseStats> first = c.server().parse_stats(uri);
  ASSERT_TRUE(first.has_value());
  EXPECT_GE(first->pieces, static_cast<size_t>(modules));

  // Line 6*200+1 is `  point a (0 0 200) endpoint`: change the value 200 to 900.
  const int line = 6 * 200 + 1;
  c.change(uri, 2, replace_char(line, 15, "9"));
  EXPECT_TRUE(c.diagnostics(uri, 2)["diagnostics"].empty());
  std::optional<ParseStats> s = c.server().parse_stats(uri);
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->parsed, 1u);
  EXPECT_EQ(s->pieces, first->pieces);
  EXPECT_LT(s->parsed_bytes, 200u);

  // A name edit that makes an error: face f (a b c) -> (a x c) in module 300.
  const int face_line = 6 * 300 + 4;
  c.change(uri, 3, replace_char(face_line, 12, "x"));
  json edited = c.diagnostics(uri, 3)["diagnostics"];
  s = c.server().parse_stats(uri);
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->parsed, 1u);
  ASSERT_FALSE(edited.empty());

  // The same text opened fresh (its own, empty cache) gets the same diagnostics.
  std::optional<std::string> now = c.server().document_text(uri);
  ASSERT_TRUE(now.has_value());
  EXPECT_NE(now->find("point a (0 0 900) endpoint"), std::string::npos);
  const std::string fresh_uri = "file:///tmp/lsp-test/large.nome";  // same path: same messages
  c.notify("textDocument/didClose", {{"textDocument", {{"uri", uri}}}});
  c.open(fresh_uri, *now, 10);
  json fresh = c.diagnostics(fresh_uri, 10)["diagnostics"];
  std::optional<ParseStats> f = c.server().parse_stats(fresh_uri);
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->parsed, f->pieces);  // the reopened document starts with a fresh cache
  EXPECT_EQ(edited, fresh);
}

}  // namespace
}  // namespace nomec::lsp::test
