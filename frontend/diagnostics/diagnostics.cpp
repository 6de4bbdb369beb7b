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

// Appends `file:line:col: ` (or nothing for an invalid range), the source line and a
// caret/underline for the range.
void render_location(const SourceManager& sources, SourceRange range, std::string& out,
                     std::string_view header) {
  if (!range.is_valid()) {
    out += header;
    out += '\n';
    return;
  }
  LineCol begin = sources.line_col(range.file, range.begin);
  out += fmt::format("{}:{}:{}: {}\n", sources.name(range.file), begin.line, begin.column,
                     header);
  std::string_view line = sources.line_text(range.file, begin.line);
  if (line.size() > 240) {
    return;  // minified or generated input: the caret line would not help
  }
  std::string gutter = fmt::format("{:>5} | ", begin.line);
  out += gutter;
  out += line;
  out += '\n';
  out += std::string(gutter.size() - 2, ' ');
  out += "| ";
  uint32_t col0 = begin.column - 1;
  for (uint32_t i = 0; i < col0 && i < line.size(); ++i) {
    out += line[i] == '\t' ? '\t' : ' ';
  }
  LineCol end = sources.line_col(range.file, range.end);
  uint32_t width = 1;
  if (end.line == begin.line && end.column > begin.column) {
    width = end.column - begin.column;
  } else if (end.line > begin.line) {
    width = static_cast<uint32_t>(line.size() > col0 ? line.size() - col0 : 1);
  }
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
      fmt::format("{}: {} [{}]", sev_colored, diag.message, diag_kind_name(diag.kind)));
  for (const DiagNote& note : diag.notes) {
    render_location(sources, note.range, out, fmt::format("note: {}", note.message));
  }
  for (const FixIt& fix : diag.fixits) {
    if (fix.range.is_valid()) {
      LineCol at = sources.line_col(fix.range.file, fix.range.begin);
      out += fmt::format("{}:{}:{}: fix-it: {}\n", sources.name(fix.range.file), at.line,
                         at.column, fix.description);
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

}  // namespace nomec
