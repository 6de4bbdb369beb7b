// The dialects of the language: NOME 2016 (`nome`), NOME2 of 2017-18 (`nome2`, the 2016
// language with `$bank.param`, `closed`, `circle`, `bsplineK`, …: compat.md §A2), NOME3/JIPCAD
// (`nome3`) and the SLIDE subset (`slide`). The checker detects one per file (docs/dialects.md); the generator
// catalogue, the IR and the backend read it where the dialects differ.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace nomec {

enum class Dialect : uint8_t { Nome, Nome3, Slide, Nome2 };

/// Bit sets of dialects, e.g. `kNome | kSlide` (the generator catalogue's signatures).
using DialectSet = uint8_t;
inline constexpr DialectSet kNome = 1;
inline constexpr DialectSet kNome3 = 2;
inline constexpr DialectSet kSlide = 4;
inline constexpr DialectSet kNome2 = 8;
inline constexpr DialectSet kAllDialects = kNome | kNome3 | kSlide | kNome2;
constexpr DialectSet dialect_bit(Dialect d) { return static_cast<DialectSet>(1u << static_cast<unsigned>(d)); }

/// NOME 2016 or NOME2: the line-based family that shares the 2016 statements, `object`,
/// `(n ro ratio h)` rings and flat vertex names.
constexpr bool is_nome_family(Dialect d) { return d == Dialect::Nome || d == Dialect::Nome2; }

/// Every dialect, in the order tools list them.
inline constexpr Dialect kDialects[] = {Dialect::Nome, Dialect::Nome2, Dialect::Nome3, Dialect::Slide};

/// `nome`, `nome2`, `nome3` or `slide`.
std::string_view dialect_name(Dialect d);
std::optional<Dialect> dialect_by_name(std::string_view name);

}  // namespace nomec
