// The fuzz targets' common check: every range a diagnostic carries (its own, its notes' and
// its fix-its') lies inside a file of `sources`; a range outside is a finding (abort).
#pragma once

#include <cstddef>
#include <cstdlib>

#include "frontend/diagnostics/diagnostic.h"
#include "frontend/source/source_manager.h"

namespace nomec::fuzz {

inline bool inside(const SourceManager& sources, const SourceRange& r) {
  if (!r.is_valid()) return true;
  if (static_cast<size_t>(r.file.index) >= sources.file_count()) return false;
  return r.begin <= r.end && r.end <= sources.text(r.file).size();
}

inline void abort_unless_inside(const SourceManager& sources, const Diagnostic& d) {
  if (!inside(sources, d.range)) std::abort();
  for (const auto& n : d.notes) {
    if (!inside(sources, n.range)) std::abort();
  }
  for (const auto& f : d.fixits) {
    if (!inside(sources, f.range)) std::abort();
  }
}

inline void abort_unless_inside(const SourceManager& sources, const DiagnosticEngine& diags) {
  for (const Diagnostic& d : diags.diagnostics()) abort_unless_inside(sources, d);
}

}  // namespace nomec::fuzz
