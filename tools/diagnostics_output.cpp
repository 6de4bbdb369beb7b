// Diagnostics as clang-style text or JSON (see diagnostics_output.h).
#include "tools/diagnostics_output.h"

#include <iostream>

namespace nomec::tools {

namespace {

nlohmann::json range_json(const SourceManager& sources, SourceRange r) {
  if (!r.is_valid()) return nullptr;
  const LineCol b = sources.line_col(r.file, r.begin);
  const LineCol e = sources.line_col(r.file, r.end);
  return {{"file", std::string(sources.name(r.file))},
          {"start", {{"line", b.line}, {"column", b.column}, {"offset", r.begin}}},
          {"end", {{"line", e.line}, {"column", e.column}, {"offset", r.end}}}};
}

nlohmann::json diag_json(const SourceManager& sources, const Diagnostic& d, bool werror) {
  const Severity sev = werror && d.severity == Severity::Warning ? Severity::Error : d.severity;
  nlohmann::json j = {{"code", std::string(diag_kind_name(d.kind))},
                      {"severity", std::string(severity_name(sev))},
                      {"message", d.message},
                      {"range", range_json(sources, d.range)},
                      {"notes", nlohmann::json::array()},
                      {"fixits", nlohmann::json::array()}};
  for (const auto& n : d.notes) {
    j["notes"].push_back({{"message", n.message}, {"range", range_json(sources, n.range)}});
  }
  for (const auto& f : d.fixits) {
    j["fixits"].push_back(
        {{"description", f.description}, {"replacement", f.replacement}, {"range", range_json(sources, f.range)}});
  }
  return j;
}

}  // namespace

void DiagnosticOutput::begin_file(const std::string& path, std::string_view dialect) {
  if (!json_) return;
  files_.push_back({{"file", path}, {"dialect", std::string(dialect)}, {"diagnostics", nlohmann::json::array()}});
}

void DiagnosticOutput::show(const SourceManager& sources, const DiagnosticEngine& diags) {
  for (const Diagnostic& d : diags.diagnostics()) {
    if (json_ && !files_.empty()) {
      files_.back()["diagnostics"].push_back(diag_json(sources, d, werror_));
    } else {
      std::cerr << render_text(sources, d, werror_, color_);
    }
  }
}

void DiagnosticOutput::finish(std::ostream& out) const {
  if (json_) out << files_.dump(2) << "\n";
}

}  // namespace nomec::tools
