// Formatter: canonical layout for NOME 2016, NOME3, SLIDE and .anom text. One
// implementation shared by `nomec fmt` and the language server's textDocument/formatting.
// It works from the parse layer's token stream (comments included) and the AST's block
// structure; it only changes whitespace, never the meaning, and keeps every comment.
#pragma once

#include <string>
#include <string_view>

namespace nomec {

struct FormatOptions {
  int indent_width = 4;
  bool insert_spaces = true;
};

struct FormatResult {
  bool ok = false;    // false: the text does not parse (nothing was formatted)
  std::string text;   // the formatted text when ok
  std::string error;  // when !ok: the first syntax error, "line:col: message"
};

/// Formats a whole file. Idempotent: format_source(format_source(x).text) == format_source(x).
FormatResult format_source(std::string_view text, const FormatOptions& options = {});

}  // namespace nomec
