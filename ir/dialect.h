// The dialects of the language: NOME 2016 (`nome`), NOME3/JIPCAD (`nome3`) and the SLIDE
// subset (`slide`). The checker detects one per file (docs/dialects.md); the generator
// catalogue, the IR and the backend read it where the dialects differ.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace nomec {

enum class Dialect : uint8_t { Nome, Nome3, Slide };

/// Bit sets of dialects, e.g. `kNome | kSlide` (the generator catalogue's signatures).
using DialectSet = uint8_t;
inline constexpr DialectSet kNome = 1;
inline constexpr DialectSet kNome3 = 2;
inline constexpr DialectSet kSlide = 4;
inline constexpr DialectSet kAllDialects = kNome | kNome3 | kSlide;
constexpr DialectSet dialect_bit(Dialect d) { return static_cast<DialectSet>(1u << static_cast<unsigned>(d)); }

/// `nome`, `nome3` or `slide`.
std::string_view dialect_name(Dialect d);
std::optional<Dialect> dialect_by_name(std::string_view name);

}  // namespace nomec
