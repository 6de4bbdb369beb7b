// Position conversion between LSP (line, UTF-16 unit) and byte offsets, and edit splicing.
#include "lsp/text.h"

#include <algorithm>
#include <cstring>

#include "frontend/source/source_manager.h"

namespace nomec::lsp {
namespace {

// Length in bytes of the UTF-8 sequence starting with `c`, or 0 for a byte that cannot
// start one (a continuation byte or an invalid lead byte), which counts as one unit alone.
int sequence_length(unsigned char c) {
  if (c < 0x80) return 1;
  if (c >= 0xC2 && c <= 0xDF) return 2;
  if (c >= 0xE0 && c <= 0xEF) return 3;
  if (c >= 0xF0 && c <= 0xF4) return 4;
  return 0;
}

// Decodes one character at `i` (never past `end`): its byte length and UTF-16 units.
void step(std::string_view s, size_t i, size_t end, size_t& bytes, uint32_t& units) {
  int n = sequence_length(static_cast<unsigned char>(s[i]));
  if (n <= 1 || i + n > end) {
    bytes = 1;
    units = 1;
    return;
  }
  for (int k = 1; k < n; ++k) {
    if ((static_cast<unsigned char>(s[i + k]) & 0xC0) != 0x80) {
      bytes = 1;
      units = 1;
      return;
    }
  }
  bytes = static_cast<size_t>(n);
  units = n == 4 ? 2 : 1;
}

}  // namespace

LineIndex::LineIndex(std::string_view text) : LineIndex(text, {}) {}

LineIndex::LineIndex(std::string_view text, const std::vector<uint32_t>& lf_starts) : text_(text) {
  if (std::memchr(text.data(), '\r', text.size()) == nullptr) {  // the usual case, `\n` only
    starts_ = lf_starts.empty() ? lf_line_starts(text) : lf_starts;
    return;
  }
  starts_.push_back(0);
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\n') {
      starts_.push_back(static_cast<uint32_t>(i + 1));
    } else if (text[i] == '\r') {
      if (i + 1 < text.size() && text[i + 1] == '\n') ++i;
      starts_.push_back(static_cast<uint32_t>(i + 1));
    }
  }
}

uint32_t LineIndex::line_content_end(uint32_t line) const {
  uint32_t end = line + 1 < starts_.size() ? starts_[line + 1] : static_cast<uint32_t>(text_.size());
  if (line + 1 < starts_.size()) {
    if (end > starts_[line] && text_[end - 1] == '\n') --end;
    if (end > starts_[line] && text_[end - 1] == '\r') --end;
  }
  return end;
}

uint32_t LineIndex::utf16_length(std::string_view bytes) {
  uint32_t units = 0;
  for (size_t i = 0; i < bytes.size();) {
    size_t b;
    uint32_t u;
    step(bytes, i, bytes.size(), b, u);
    i += b;
    units += u;
  }
  return units;
}

uint32_t LineIndex::offset(Position p) const {
  if (p.line >= starts_.size()) return static_cast<uint32_t>(text_.size());
  size_t i = starts_[p.line];
  const size_t end = line_content_end(p.line);
  uint32_t units = 0;
  while (i < end) {
    size_t b;
    uint32_t u;
    step(text_, i, end, b, u);
    if (units + u > p.character) break;
    units += u;
    i += b;
  }
  return static_cast<uint32_t>(i);
}

Position LineIndex::position(uint32_t offset) const {
  offset = std::min<uint32_t>(offset, static_cast<uint32_t>(text_.size()));
  auto it = std::upper_bound(starts_.begin(), starts_.end(), offset);
  uint32_t line = static_cast<uint32_t>(it - starts_.begin()) - 1;
  // An offset between `\r` and `\n` belongs to the end of the line's content.
  uint32_t end = std::min(offset, line_content_end(line));
  size_t i = starts_[line];
  uint32_t units = 0;
  while (i < end) {
    size_t b;
    uint32_t u;
    step(text_, i, text_.size(), b, u);
    if (i + b > end) break;  // inside a sequence: round down
    units += u;
    i += b;
  }
  return Position{line, units};
}

void apply_edit(std::string& text, Position start, Position end, std::string_view new_text) {
  LineIndex index(text);
  uint32_t a = index.offset(start);
  uint32_t b = index.offset(end);
  if (b < a) std::swap(a, b);
  text.replace(a, b - a, new_text);
}

}  // namespace nomec::lsp
