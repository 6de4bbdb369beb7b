// Diagnostics engine, text rendering and "did you mean" suggestions.
#include <algorithm>
#include <array>
#include <fmt/format.h>
#include <tuple>

#include "frontend/diagnostics/diagnostic.h"

namespace nomec {

namespace {
// The position order of merge_in_order and sort_by_position: by start offset only.
bool starts_before(const Diagnostic& a, const Diagnostic& b) { return a.range.begin < b.range.begin; }
}  // namespace

void DiagnosticEngine::merge_in_order(DiagnosticEngine&& other) {
  std::vector<Diagnostic> merged;
  merged.reserve(diags_.size() + other.diags_.size());
  std::merge(std::make_move_iterator(diags_.begin()), std::make_move_iterator(diags_.end()),
             std::make_move_iterator(other.diags_.begin()), std::make_move_iterator(other.diags_.end()),
             std::back_inserter(merged), starts_before);
  diags_ = std::move(merged);
  other.diags_.clear();
}

void DiagnosticEngine::sort_by_position() {
  std::stable_sort(diags_.begin(), diags_.end(), starts_before);
}

namespace {
struct KindInfo {
  std::string_view name;
  Severity severity;
  std::string_view summary;
};
constexpr KindInfo kKindInfo[] = {
#define NOMEC_DIAG(Name, Sev, Summary) {#Name, Severity::Sev, Summary},
#include "frontend/diagnostics/kinds.def"
};
}  // namespace

std::string_view diag_kind_name(DiagKind kind) { return kKindInfo[static_cast<int>(kind)].name; }
Severity diag_kind_severity(DiagKind kind) { return kKindInfo[static_cast<int>(kind)].severity; }
std::string_view diag_kind_summary(DiagKind kind) {
  return kKindInfo[static_cast<int>(kind)].summary;
}

std::string_view severity_name(Severity severity) {
  switch (severity) {
    case Severity::Note:
      return "note";
    case Severity::Warning:
      return "warning";
    case Severity::Error:
      return "error";
  }
  return "error";
}

DiagnosticEngine::Builder& DiagnosticEngine::Builder::note(SourceRange range,
                                                           std::string message) {
  diag_->notes.push_back({range, std::move(message)});
  return *this;
}

DiagnosticEngine::Builder& DiagnosticEngine::Builder::fixit(SourceRange range,
                                                            std::string replacement,
                                                            std::string description) {
  diag_->fixits.push_back({range, std::move(replacement), std::move(description)});
  return *this;
}

DiagnosticEngine::Builder DiagnosticEngine::emit(DiagKind kind, SourceRange range,
                                                 std::string message) {
  diags_.push_back({kind, diag_kind_severity(kind), range, std::move(message), {}, {}});
  return Builder(&diags_.back());
}

void DiagnosticEngine::sort_and_dedupe() {
  auto key = [](const Diagnostic& d) {
    return std::tuple(d.range.file.index, d.range.begin, d.range.end,
                      static_cast<int>(d.kind), std::string_view(d.message));
  };
  std::stable_sort(diags_.begin(), diags_.end(),
                   [&](const Diagnostic& a, const Diagnostic& b) { return key(a) < key(b); });
  diags_.erase(std::unique(diags_.begin(), diags_.end(),
                           [&](const Diagnostic& a, const Diagnostic& b) {
                             return key(a) == key(b);
                           }),
               diags_.end());
}

int DiagnosticEngine::error_count() const {
  return static_cast<int>(std::count_if(diags_.begin(), diags_.end(), [](const Diagnostic& d) {
    return d.severity == Severity::Error;
  }));
}

int DiagnosticEngine::warning_count() const {
  return static_cast<int>(std::count_if(diags_.begin(), diags_.end(), [](const Diagnostic& d) {
    return d.severity == Severity::Warning;
  }));
}

void DiagnosticEngine::append(DiagnosticEngine&& other) {
  for (auto& d : other.diags_) {
    diags_.push_back(std::move(d));
  }
  other.diags_.clear();
}

namespace {

// A tab in a quoted source line moves to the next multiple of this many columns, as
// terminals and clang do, so the caret line below it can use spaces and still line up.
constexpr uint32_t kTabStop = 8;

// The length of the well-formed UTF-8 sequence at `s[i]` and its code point, or 0 for a
// byte that does not start one (a stray continuation byte, an overlong form, a surrogate,
// a truncated sequence).
size_t utf8_sequence(std::string_view s, size_t i, char32_t& cp) {
  const auto b = [&](size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = b(i);
  size_t len = 0;
  if (c >= 0xC2 && c <= 0xDF) {
    len = 2;
    cp = c & 0x1F;
  } else if (c >= 0xE0 && c <= 0xEF) {
    len = 3;
    cp = c & 0x0F;
  } else if (c >= 0xF0 && c <= 0xF4) {
    len = 4;
    cp = c & 0x07;
  } else {
    return 0;
  }
  if (i + len > s.size()) return 0;
  for (size_t k = 1; k < len; ++k) {
    if ((b(i + k) & 0xC0) != 0x80) return 0;
    cp = (cp << 6) | (b(i + k) & 0x3F);
  }
  if ((len == 3 && cp < 0x800) || (len == 4 && (cp < 0x10000 || cp > 0x10FFFF)) || (cp >= 0xD800 && cp <= 0xDFFF)) {
    return 0;
  }
  return len;
}

// Code points a terminal acts on instead of showing: C1 controls (U+0080–U+009F, `U+009B`
// starts an escape sequence on some terminals) and the bidirectional embeddings,
// overrides and isolates, which reorder what follows them on the line.
bool is_hidden_control(char32_t cp) {
  return (cp >= 0x80 && cp <= 0x9F) || (cp >= 0x202A && cp <= 0x202E) || (cp >= 0x2066 && cp <= 0x2069);
}

// `text` as it may be shown on a terminal: control characters, bytes that are not UTF-8 and
// the code points of `is_hidden_control` become visible escapes (`\x1b`, `\n`, `\u202e`), so a
// scene's text cannot move the cursor, clear the screen, change colours or reorder the
// line it is quoted in. With `expand_tabs`, a tab becomes the spaces to the next tab stop
// (a quoted source line, whose caret line must line up); otherwise `\t`. When `columns`
// is given, it receives the display column (0-based) at which each byte of `text` starts,
// and one more entry for the end.
std::string visible(std::string_view text, bool expand_tabs, std::vector<uint32_t>* columns = nullptr) {
  std::string out;
  out.reserve(text.size());
  uint32_t column = 0;
  if (columns != nullptr) columns->assign(text.size() + 1, 0);
  for (size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    size_t len = 1;
    const uint32_t at = column;
    if (c == '\t' && expand_tabs) {
      const uint32_t next = (column / kTabStop + 1) * kTabStop;
      out.append(next - column, ' ');
      column = next;
    } else if (c < 0x20 || c == 0x7F) {
      const std::string e = c == '\t' ? "\\t" : c == '\n' ? "\\n" : c == '\r' ? "\\r" : fmt::format("\\x{:02x}", c);
      out += e;
      column += static_cast<uint32_t>(e.size());
    } else if (c < 0x80) {
      out += static_cast<char>(c);
      ++column;
    } else {
      char32_t cp = 0;
      len = utf8_sequence(text, i, cp);
      std::string e;
      if (len == 0) {
        len = 1;
        e = fmt::format("\\x{:02x}", c);
      } else if (is_hidden_control(cp)) {
        e = fmt::format("\\u{:04x}", static_cast<uint32_t>(cp));
      }
      if (e.empty()) {
        out.append(text.substr(i, len));
        ++column;  // one column per code point (wide characters are rare in scenes)
      } else {
        out += e;
        column += static_cast<uint32_t>(e.size());
      }
    }
    if (columns != nullptr) {
      for (size_t k = 0; k < len; ++k) (*columns)[i + k] = at;
    }
    i += len;
  }
  if (columns != nullptr) columns->back() = column;
  return out;
}

// Appends `file:line:col: ` (or nothing for an invalid range), the source line and a
// caret/underline for the range. The line is shown through `visible`, and the caret and
// underline are placed by display column, so they stay under the range.
void render_location(const SourceManager& sources, SourceRange range, std::string& out,
                     std::string_view header) {
  if (!range.is_valid()) {
    out += header;
    out += '\n';
    return;
  }
  LineCol begin = sources.line_col(range.file, range.begin);
  out += fmt::format("{}:{}:{}: {}\n", visible(sources.name(range.file), false), begin.line, begin.column,
                     header);
  std::string_view line = sources.line_text(range.file, begin.line);
  if (line.size() > 240) {
    return;  // minified or generated input: the caret line would not help
  }
  std::vector<uint32_t> columns;
  const std::string shown = visible(line, true, &columns);
  std::string gutter = fmt::format("{:>5} | ", begin.line);
  out += gutter;
  out += shown;
  out += '\n';
  out += std::string(gutter.size() - 2, ' ');
  out += "| ";
  // Byte columns within the line (line_col's columns count from after a leading BOM, as
  // line_text's text starts there too).
  const uint32_t col0 = std::min<uint32_t>(begin.column - 1, static_cast<uint32_t>(line.size()));
  LineCol end = sources.line_col(range.file, range.end);
  // One column past the start (a range at the end of the line, as a missing token's, ends
  // there: the caret sits after the last character).
  uint32_t end0 = std::min<uint32_t>(col0 + 1, static_cast<uint32_t>(line.size()));
  if (end.line == begin.line && end.column > begin.column) {
    end0 = std::min<uint32_t>(end.column - 1, static_cast<uint32_t>(line.size()));
  } else if (end.line > begin.line) {
    end0 = static_cast<uint32_t>(line.size());
  }
  const uint32_t from = columns[col0];
  const uint32_t to = end0 > col0 ? columns[end0] : from + 1;
  const uint32_t width = std::max<uint32_t>(1, to - from);
  out += std::string(from, ' ');
  out += '^';
  if (width > 1) {
    out += std::string(width - 1, '~');
  }
  out += '\n';
}

}  // namespace

std::string render_text(const SourceManager& sources, const Diagnostic& diag, bool werror,
                        bool color) {
  Severity sev = diag.severity;
  if (werror && sev == Severity::Warning) {
    sev = Severity::Error;
  }
  std::string_view sev_text = severity_name(sev);
  std::string sev_colored(sev_text);
  if (color) {
    const char* code = sev == Severity::Error ? "\033[1;31m"
                       : sev == Severity::Warning ? "\033[1;35m"
                                                  : "\033[1;36m";
    sev_colored = fmt::format("{}{}\033[0m", code, sev_text);
  }
  std::string out;
  render_location(
      sources, diag.range, out,
      fmt::format("{}: {} [{}]", sev_colored, visible(diag.message, false), diag_kind_name(diag.kind)));
  for (const DiagNote& note : diag.notes) {
    render_location(sources, note.range, out, fmt::format("note: {}", visible(note.message, false)));
  }
  for (const FixIt& fix : diag.fixits) {
    if (fix.range.is_valid()) {
      LineCol at = sources.line_col(fix.range.file, fix.range.begin);
      out += fmt::format("{}:{}:{}: fix-it: {}\n", visible(sources.name(fix.range.file), false), at.line,
                         at.column, visible(fix.description, false));
    }
  }
  return out;
}

namespace {

// Names longer than this get no suggestion (a third of them may differ: no real hint).
constexpr size_t kMaxSuggestedLength = 64;

char lower(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }

// Case-insensitive edit distance of `a` and `b`, or a value above `bound` as soon as it is
// certain to exceed it. No allocation: both are at most kMaxSuggestedLength long.
size_t edit_distance(std::string_view a, std::string_view b, size_t bound) {
  const size_t la = a.size(), lb = b.size();
  if ((la > lb ? la - lb : lb - la) > bound) return bound + 1;
  std::array<uint8_t, kMaxSuggestedLength + 1> prev{}, cur{};
  for (size_t j = 0; j <= lb; ++j) prev[j] = static_cast<uint8_t>(j);
  for (size_t i = 1; i <= la; ++i) {
    cur[0] = static_cast<uint8_t>(i);
    uint8_t row_min = cur[0];
    const char ca = lower(a[i - 1]);
    for (size_t j = 1; j <= lb; ++j) {
      const uint8_t cost = ca == lower(b[j - 1]) ? 0 : 1;
      cur[j] = std::min({static_cast<uint8_t>(prev[j] + 1), static_cast<uint8_t>(cur[j - 1] + 1),
                         static_cast<uint8_t>(prev[j - 1] + cost)});
      row_min = std::min(row_min, cur[j]);
    }
    if (row_min > bound) return bound + 1;
    std::swap(prev, cur);
  }
  return prev[lb];
}

template <typename Candidates>
std::string closest(std::string_view name, const Candidates& candidates) {
  std::string_view result;
  if (name.empty() || name.size() > kMaxSuggestedLength) return {};
  // Allow roughly one edit per three characters, at least one.
  size_t best = std::max<size_t>(1, (name.size() + 2) / 3);
  bool found = false;
  for (const auto& candidate : candidates) {
    const std::string_view c(candidate);
    if (c == name || c.size() > kMaxSuggestedLength) continue;
    const size_t d = edit_distance(name, c, best);
    if (d < best || (d == best && !found)) {
      best = d;
      result = c;
      found = true;
    }
  }
  return std::string(result);
}

}  // namespace

std::string closest_match(std::string_view name, const std::vector<std::string>& candidates) {
  return closest(name, candidates);
}

std::string closest_match(std::string_view name, std::span<const std::string_view> candidates) {
  return closest(name, candidates);
}

namespace {

constexpr size_t kLongestWord = 64;

}  // namespace

size_t typo_distance(std::string_view a, std::string_view b, size_t bound) {
  const size_t la = a.size(), lb = b.size();
  if ((la > lb ? la - lb : lb - la) > bound || la > kLongestWord || lb > kLongestWord) return bound + 1;
  // Three rows of the optimal-string-alignment table.
  std::array<uint8_t, kLongestWord + 1> before{}, prev{}, cur{};
  for (size_t j = 0; j <= lb; ++j) prev[j] = static_cast<uint8_t>(j);
  for (size_t i = 1; i <= la; ++i) {
    cur[0] = static_cast<uint8_t>(i);
    uint8_t row_min = cur[0];
    for (size_t j = 1; j <= lb; ++j) {
      const bool same = lower(a[i - 1]) == lower(b[j - 1]);
      uint8_t v = std::min({static_cast<uint8_t>(prev[j] + 1), static_cast<uint8_t>(cur[j - 1] + 1),
                            static_cast<uint8_t>(prev[j - 1] + (same ? 0 : 1))});
      if (i > 1 && j > 1 && lower(a[i - 1]) == lower(b[j - 2]) && lower(a[i - 2]) == lower(b[j - 1])) {
        v = std::min(v, static_cast<uint8_t>(before[j - 2] + 1));
      }
      cur[j] = v;
      row_min = std::min(row_min, v);
    }
    if (row_min > bound) return bound + 1;
    before = prev;
    prev = cur;
  }
  return prev[lb];
}

bool is_typo_of(std::string_view word, std::string_view keyword) {
  if (word == keyword || keyword.empty() || word.empty()) return false;
  const size_t bound = keyword.size() <= 4 ? 1 : 2;
  return typo_distance(word, keyword, bound) <= bound;
}

}  // namespace nomec
