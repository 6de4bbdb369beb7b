// Source manager implementation: line tables and offset <-> line/column conversion.
#include "frontend/source/source_manager.h"

#include <algorithm>
#include <cstring>

namespace nomec {

std::vector<uint32_t> lf_line_starts(std::string_view text) {
  // memchr finds line ends far faster than a byte loop; tables are rebuilt for every
  // version of a document the language server checks.
  std::vector<uint32_t> starts;
  starts.reserve(text.size() / 40 + 16);
  starts.push_back(0);
  const char* begin = text.data();
  const char* end = begin + text.size();
  for (const char* p = begin; const void* nl = std::memchr(p, '\n', static_cast<size_t>(end - p));) {
    p = static_cast<const char*>(nl) + 1;
    starts.push_back(static_cast<uint32_t>(p - begin));
  }
  return starts;
}

FileId SourceManager::add_file(std::string name, std::string text) {
  File file{std::move(name), std::move(text), {}};
  file.line_starts = lf_line_starts(file.text);
  file.bom = utf8_bom_length(file.text);
  files_.push_back(std::move(file));
  return FileId{static_cast<int32_t>(files_.size() - 1)};
}

std::string_view SourceManager::text(SourceRange range) const {
  std::string_view all = text(range.file);
  uint32_t begin = std::min<uint32_t>(range.begin, all.size());
  uint32_t end = std::clamp<uint32_t>(range.end, begin, all.size());
  return all.substr(begin, end - begin);
}

LineCol SourceManager::line_col(FileId file, uint32_t offset) const {
  const File& f = files_[file.index];
  offset = std::min<uint32_t>(offset, f.text.size());
  auto it = std::upper_bound(f.line_starts.begin(), f.line_starts.end(), offset);
  uint32_t line = static_cast<uint32_t>(it - f.line_starts.begin());
  const uint32_t start = f.line_starts[line - 1] + (line == 1 ? std::min(f.bom, offset) : 0);
  return LineCol{line, offset - start + 1};
}

std::string_view SourceManager::line_text(FileId file, uint32_t line) const {
  const File& f = files_[file.index];
  if (line == 0 || line > f.line_starts.size()) {
    return {};
  }
  uint32_t begin = f.line_starts[line - 1] + (line == 1 ? f.bom : 0);
  uint32_t end = line < f.line_starts.size() ? f.line_starts[line] : f.text.size();
  std::string_view s(f.text.data() + begin, end - begin);
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) {
    s.remove_suffix(1);
  }
  return s;
}

uint32_t SourceManager::offset_of(FileId file, uint32_t line, uint32_t column0) const {
  const File& f = files_[file.index];
  if (line == 0) {
    return 0;
  }
  if (line > f.line_starts.size()) {
    return f.text.size();
  }
  uint32_t begin = f.line_starts[line - 1] + (line == 1 ? f.bom : 0);
  uint32_t len = static_cast<uint32_t>(line_text(file, line).size());
  return begin + std::min(column0, len);
}

}  // namespace nomec
