// `nomec fmt`: formats files with the shared formatter (frontend/format). Separate from
// nomec.cpp so the main command line stays small.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "base/input_limits.h"

namespace nomec::tools {

struct FmtCommand {
  std::vector<std::string> files;  // `-` reads standard input
  bool in_place = false;           // -i/--in-place: rewrite changed files atomically
  bool check = false;              // --check: list files that would change, exit 1 if any
  int indent_width = 4;
  bool use_tabs = false;
  int64_t max_file_bytes = kDefaultMaxFileBytes;  // --max-file-size: the largest file read
};

/// Runs `nomec fmt`. Exit status: 0 done (or nothing would change), 1 a file would change
/// (--check) or does not parse, 2 usage or I/O error.
int run_fmt(const FmtCommand& command);

}  // namespace nomec::tools
