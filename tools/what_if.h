// `nomec --what-if bank.param=value FILE`: builds the scene in a backend::Session, moves
// one slider, and prints as JSON what the incremental update re-evaluated (nodes,
// generators, instances, kernel operations) and its time next to the full build's,
// both measured in this process.
#pragma once

#include <ostream>
#include <string>

#include "backend/evaluate.h"
#include "frontend/diagnostics/diagnostic.h"
#include "frontend/source/source_manager.h"
#include "ir/ir.h"

namespace nomec::tools {

struct WhatIf {
  std::string parameter;  // `fp.z` or `fp_z`
  double value = 0;
};

/// Parses `bank.param=value`; returns an error message, empty on success.
std::string parse_what_if(const std::string& text, WhatIf& out);

/// Runs the what-if on a checked module and writes the JSON to `out`; geometry
/// diagnostics go to `diags`. Returns 0, or 1 if the slider change was refused.
int run_what_if(const std::string& path, ir::Module module, const WhatIf& change,
                const backend::PipelineOptions& pipeline, bool allow_out_of_range,
                DiagnosticEngine& diags, std::ostream& out);

}  // namespace nomec::tools
