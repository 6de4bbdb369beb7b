// Unit tests of LSP position mapping: UTF-16 columns over non-ASCII, astral characters,
// invalid UTF-8, CRLF and lone CR line ends, clamping, and incremental edit splicing.
#include <gtest/gtest.h>

#include "frontend/source/source_manager.h"
#include "lsp/text.h"

namespace nomec::lsp {
namespace {

TEST(LspText, AsciiRoundTrip) {
  std::string text = "ab\ncd\n";
  LineIndex idx(text);
  EXPECT_EQ(idx.line_count(), 3u);
  EXPECT_EQ(idx.offset({1, 1}), 4u);
  EXPECT_EQ(idx.position(4), (Position{1, 1}));
  EXPECT_EQ(idx.position(6), (Position{2, 0}));
}

// Given SourceManager's `\n`-only table, LineIndex uses it for `\n` texts and ignores it
// when `\r` ends lines too: the same positions as computing its own.
TEST(LspText, PrecomputedLfTableGivesTheSameIndex) {
  for (std::string text : {"ab\ncd\n\nef", "ab\r\ncd\rx\ny", "", "no newline"}) {
    LineIndex own(text);
    LineIndex given(text, lf_line_starts(text));
    ASSERT_EQ(own.line_count(), given.line_count()) << text;
    for (uint32_t line = 0; line < own.line_count(); ++line) {
      EXPECT_EQ(own.line_start(line), given.line_start(line)) << text;
      EXPECT_EQ(own.line_content_end(line), given.line_content_end(line)) << text;
    }
  }
}

TEST(LspText, Utf16ColumnsForNonAscii) {
  // "é" is 2 bytes / 1 unit; "😀" is 4 bytes / 2 units (a surrogate pair).
  std::string text = "é😀x\n";
  LineIndex idx(text);
  EXPECT_EQ(idx.offset({0, 0}), 0u);
  EXPECT_EQ(idx.offset({0, 1}), 2u);
  EXPECT_EQ(idx.offset({0, 3}), 6u);  // after the pair
  EXPECT_EQ(idx.offset({0, 2}), 2u);  // inside the pair: rounds down to its start
  EXPECT_EQ(idx.position(6), (Position{0, 3}));
  EXPECT_EQ(idx.position(7), (Position{0, 4}));
  EXPECT_EQ(idx.position(4), (Position{0, 1}));  // inside the 4-byte sequence
}

TEST(LspText, CrLfAndLoneCr) {
  std::string text = "a\r\nbc\rd";
  LineIndex idx(text);
  EXPECT_EQ(idx.line_count(), 3u);
  EXPECT_EQ(idx.offset({1, 0}), 3u);
  EXPECT_EQ(idx.offset({1, 99}), 5u);  // clamps before the `\r`
  EXPECT_EQ(idx.offset({0, 5}), 1u);   // clamps before the `\r\n`
  EXPECT_EQ(idx.offset({2, 1}), 7u);
  EXPECT_EQ(idx.position(2), (Position{0, 1}));  // between `\r` and `\n`
  EXPECT_EQ(idx.position(6), (Position{2, 0}));
  EXPECT_EQ(idx.offset({9, 0}), 7u);  // past the last line: end of text
}

TEST(LspText, InvalidUtf8CountsOneUnitPerByte) {
  std::string text = "\xff\xfe" "a";
  LineIndex idx(text);
  EXPECT_EQ(idx.offset({0, 2}), 2u);
  EXPECT_EQ(idx.position(3), (Position{0, 3}));
  EXPECT_EQ(LineIndex::utf16_length("\xe2\x82"), 2u);  // truncated sequence
}

TEST(LspText, ApplyEdit) {
  std::string text = "héllo\r\nwörld\n";
  apply_edit(text, {0, 1}, {0, 2}, "e");
  EXPECT_EQ(text, "hello\r\nwörld\n");
  apply_edit(text, {1, 1}, {1, 2}, "o");
  EXPECT_EQ(text, "hello\r\nworld\n");
  apply_edit(text, {0, 5}, {1, 0}, " ");  // joins the lines across the CRLF
  EXPECT_EQ(text, "hello world\n");
  apply_edit(text, {5, 0}, {5, 0}, "!");  // past the end appends
  EXPECT_EQ(text, "hello world\n!");
}

}  // namespace
}  // namespace nomec::lsp
