// Generator signatures: the positional arguments of each generator statement (per dialect),
// which of them are whole-number counts, and what each argument means. Shared by the checker
// (arity and count checks) and the language index (hover, signature help); docs/dialects.md
// lists the same table for readers.
#pragma once

#include <string_view>
#include <vector>

#include "frontend/ast/ast.h"
#include "frontend/check/check.h"

namespace nomec {

/// Positional arguments of a generator, e.g. funnel (nome): `(n ro ratio h)`.
struct GenSignature {
  std::vector<std::string_view> args;      // names, in order
  std::vector<std::string_view> optional;  // extra trailing args that may follow
  std::vector<std::string_view> counts;    // names that are whole-number counts
};

/// The signature of a generator block kind in `dialect`, or nullptr when the kind takes no
/// positional argument list (e.g. `rimribbon`, SLIDE's `cylinder`).
const GenSignature* signature_for(ast::BlockKind kind, Dialect dialect);

/// What the argument `arg` of generator `kind` means, one sentence for hovers and signature
/// help, e.g. funnel `ro` → "radius of the base ring". Empty if unknown.
std::string_view argument_doc(ast::BlockKind kind, std::string_view arg);

}  // namespace nomec
