// The plain helpers of types.h, shared by the engine (in the Tcl worker) and nomec.
#include "frontend/tcl/types.h"

namespace nomec::tcl {

std::string normalize_newlines(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\r') {
      size_t j = i;
      while (j < text.size() && text[j] == '\r') ++j;
      if (j < text.size() && text[j] == '\n') {
        i = j - 1;  // `\r*\n` → `\n`
        continue;
      }
      out += '\n';  // a lone `\r` ends a line too
      i = j - 1;
      continue;
    }
    out += text[i];
  }
  return out;
}

}  // namespace nomec::tcl
