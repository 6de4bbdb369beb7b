// Test helper: a NOME text checked and evaluated in one step, with everything the result
// points into (sources, diagnostics, IR) kept alive together. The check must be clean.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "backend/evaluate.h"
#include "frontend/check/check.h"

namespace nomec::backend {

struct Evaluated {
  SourceManager sources;
  DiagnosticEngine diags;
  CheckResult check;
  std::vector<OutputMesh> meshes;
};

/// `text` checked as the file `path` (its extension and `options` choose the dialect) and
/// evaluated; a check error fails the calling test.
inline std::unique_ptr<Evaluated> evaluate_text(const std::string& path, const std::string& text,
                                                const CheckOptions& options = {}) {
  auto e = std::make_unique<Evaluated>();
  e->check = check_source(e->sources, path, text, options, e->diags);
  EXPECT_EQ(e->diags.error_count(), 0) << (e->diags.diagnostics().empty() ? "" : e->diags.diagnostics()[0].message);
  e->meshes = evaluate_scene(e->check.module, e->diags);
  return e;
}

}  // namespace nomec::backend
