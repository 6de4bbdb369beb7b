// Source manager: owns the text of every input file and turns compact locations
// (file id + byte offset) into line and column, only when a human or the LSP needs them.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "base/id.h"

namespace nomec {

/// Line starts of `text` when only `\n` ends lines: 0, then the offset after every `\n`.
/// Shared by SourceManager's line tables and the language server's LineIndex.
std::vector<uint32_t> lf_line_starts(std::string_view text);

/// The UTF-8 byte order mark some editors write at the start of a file (`EF BB BF`).
inline constexpr std::string_view kUtf8Bom = "\xEF\xBB\xBF";

/// 3 when `text` starts with a UTF-8 byte order mark, else 0. A leading mark is not part of
/// the scene: the lexer and the flat-mesh readers skip it, and columns on the first line
/// count from after it (as editors show them, which hide the mark).
constexpr uint32_t utf8_bom_length(std::string_view text) {
  return text.substr(0, kUtf8Bom.size()) == kUtf8Bom ? static_cast<uint32_t>(kUtf8Bom.size()) : 0;
}

/// Identifies one file held by a SourceManager.
struct FileTag;
using FileId = Id<FileTag>;

/// A half-open byte range [begin, end) in one file, e.g. the name `fun` in `funnel fun (…)`.
struct SourceRange {
  FileId file;
  uint32_t begin = 0;
  uint32_t end = 0;
  bool is_valid() const { return file.is_valid(); }
  friend bool operator==(const SourceRange&, const SourceRange&) = default;
};

/// A 1-based line and column (column counts bytes, on the first line from after a leading
/// byte order mark) for printing.
struct LineCol {
  uint32_t line = 0;
  uint32_t column = 0;
};

class SourceManager {
 public:
  /// Adds a file's text under a display name; returns its id.
  FileId add_file(std::string name, std::string text);

  std::string_view name(FileId file) const { return files_[file.index].name; }
  std::string_view text(FileId file) const { return files_[file.index].text; }
  std::string_view text(SourceRange range) const;
  size_t file_count() const { return files_.size(); }

  /// Line and column of a byte offset (offset may equal the text size).
  LineCol line_col(FileId file, uint32_t offset) const;
  /// The text of a 1-based line without its line terminator (nor, on line 1, a leading
  /// byte order mark).
  std::string_view line_text(FileId file, uint32_t line) const;
  /// The byte offset of a 1-based line/0-based byte column (clamped to the text), the
  /// inverse of `line_col`.
  uint32_t offset_of(FileId file, uint32_t line, uint32_t column0) const;
  /// The file's line table: `lf_line_starts` of its text.
  const std::vector<uint32_t>& line_starts(FileId file) const { return files_[file.index].line_starts; }

 private:
  // Rationale: line starts are computed once per file when it is added; every position
  // query is then a binary search. Locations elsewhere stay 8 bytes (id + offset).
  // A deque keeps every file (and its text, even one short enough to live inside the
  // std::string) at a stable address when more files are added: syntax trees and
  // diagnostics hold string_views into the texts (an `.anom` adds its base scene mid-check).
  struct File {
    std::string name;
    std::string text;
    std::vector<uint32_t> line_starts;
    uint32_t bom = 0;  // utf8_bom_length(text)
  };
  std::deque<File> files_;
};

}  // namespace nomec
