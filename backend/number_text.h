// Number text for the text writers (write.cpp): the same characters as fmt's `{:e}` (C's
// `%e`: six decimals) and `{}` (the shortest text that reads back to the same double, fixed
// notation for decimal exponents −4…15), written straight into a buffer. The shortest
// digits come from fmt's own Dragonbox (`fmt::detail::dragonbox::to_decimal`, what `{}`
// runs), the six-decimal ones from one scaled multiplication with a to_chars fallback near
// ties. The writers format millions of numbers; these are several times faster than going
// through fmt, and tests/backend/number_text_test.cpp proves them equal to fmt on random bit
// patterns, short decimals, widened floats, powers of two and ten, and layout boundaries.
#pragma once

#include <cstdint>

namespace nomec::backend {

/// Room a number's text may need in the buffer.
inline constexpr int kNumberTextMax = 48;

/// Writes `x` as fmt's `{:e}` does (e.g. `-1.234568e+00`) at `p`; returns the end.
char* put_e6(char* p, double x);
/// Writes `x` as fmt's `{}` does (e.g. `0.30000000000000004`, `1e-05`) at `p`; returns the end.
char* put_shortest(char* p, double x);
/// Writes a whole number in decimal at `p`; returns the end.
char* put_int(char* p, int64_t v);

}  // namespace nomec::backend
