// Parse layer: NOME/NOME3/SLIDE text -> AST. The only code that includes ANTLR headers;
// every lexical and syntax problem becomes a nomec diagnostic (never an exception or a
// console print), and the parser recovers so one file reports all its problems.
#pragma once

#include "frontend/ast/ast.h"
#include "frontend/diagnostics/diagnostic.h"

namespace nomec {

/// Parses one file. Always returns an AST (possibly partial); problems go to `diags`.
ast::Ast parse_file(const SourceManager& sources, FileId file, DiagnosticEngine& diags);

}  // namespace nomec
