// Helpers for the tests that type random edits into documents (parse cache, language server).
#pragma once

#include <cstddef>
#include <string>
#include <utility>

namespace nomec::testing_edits {

/// The line holding byte `at` of `text`, as [begin, end) with its line break: what deleting
/// or duplicating "the line the cursor is on" takes.
inline std::pair<size_t, size_t> line_around(const std::string& text, size_t at) {
  size_t b = text.rfind('\n', at == 0 ? 0 : at - 1);
  b = b == std::string::npos ? 0 : b + 1;
  size_t e = text.find('\n', at);
  e = e == std::string::npos ? text.size() : e + 1;
  return {b, e};
}

}  // namespace nomec::testing_edits
