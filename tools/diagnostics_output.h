// How the CLI shows diagnostics: clang-style text on stderr (coloured on a terminal) or,
// with `--diagnostics-format json`, one JSON object per file printed at the end (the only
// JSON of the CLI besides the summaries).
#pragma once

#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "frontend/diagnostics/diagnostic.h"
#include "frontend/source/source_manager.h"

namespace nomec::tools {

class DiagnosticOutput {
 public:
  DiagnosticOutput(bool json, bool werror, bool color) : json_(json), werror_(werror), color_(color) {}

  /// Starts a file's entry (JSON only).
  void begin_file(const std::string& path, std::string_view dialect);
  /// Shows `diags` (sorted) for the current file.
  void show(const SourceManager& sources, const DiagnosticEngine& diags);
  /// Prints the JSON collected (JSON only).
  void finish(std::ostream& out) const;

 private:
  bool json_;
  bool werror_;
  bool color_;
  nlohmann::json files_ = nlohmann::json::array();
};

}  // namespace nomec::tools
