// Document text for the language server: LSP positions (line + UTF-16 code unit) <-> our
// byte offsets, for any mix of `\n`, `\r\n` and `\r` line ends and for non-ASCII or
// invalid UTF-8 text, and applying incremental `didChange` edits to a text.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace nomec::lsp {

/// An LSP position: 0-based line, 0-based character counted in UTF-16 code units.
struct Position {
  uint32_t line = 0;
  uint32_t character = 0;
  friend bool operator==(const Position&, const Position&) = default;
};

/// Line starts of one text, computed once; conversions are a binary search plus a scan of
/// one line. The text must outlive the index (it keeps a view).
class LineIndex {
 public:
  LineIndex() = default;
  explicit LineIndex(std::string_view text);
  /// The same, given `lf_line_starts(text)` already computed (e.g. by SourceManager): it
  /// is copied when `\n` is the only line end, so the table is not computed twice.
  LineIndex(std::string_view text, const std::vector<uint32_t>& lf_starts);

  /// Byte offset of a position. Lines past the end clamp to the end of the text;
  /// characters past the end of a line clamp to the end of that line (before its line
  /// terminator); a position inside a surrogate pair rounds down to the character start.
  uint32_t offset(Position p) const;
  /// Position of a byte offset (clamped to the text; an offset inside a UTF-8 sequence
  /// rounds down to the start of that character).
  Position position(uint32_t offset) const;
  uint32_t line_count() const { return static_cast<uint32_t>(starts_.size()); }
  /// Byte offset of the start of 0-based `line` and the end of its content (before `\r\n`).
  uint32_t line_start(uint32_t line) const { return starts_[line]; }
  uint32_t line_content_end(uint32_t line) const;
  /// UTF-16 length of the bytes [begin, end) (invalid bytes count one unit each).
  static uint32_t utf16_length(std::string_view bytes);

 private:
  std::string_view text_;
  std::vector<uint32_t> starts_;
};

/// Replaces the text between two LSP positions, e.g. one `contentChanges` entry.
void apply_edit(std::string& text, Position start, Position end, std::string_view new_text);

}  // namespace nomec::lsp
