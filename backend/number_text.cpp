// Number text for the text writers (see number_text.h).
#include "backend/number_text.h"

#include <fmt/format.h>

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace nomec::backend {

namespace {

constexpr double kPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                             1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

char* put_exponent(char* p, int e) {
  *p++ = 'e';
  *p++ = e < 0 ? '-' : '+';
  if (e < 0) e = -e;
  if (e >= 100) *p++ = static_cast<char>('0' + e / 100);
  *p++ = static_cast<char>('0' + e / 10 % 10);
  *p++ = static_cast<char>('0' + e % 10);
  return p;
}

// |x| · 10^(6 − e), with one rounding (10^k is exact for k ≤ 22): the seven significant
// digits of |x| as a number in [10^6, 10^7) when e is |x|'s decimal exponent.
bool scaled(double a, int e, double* out) {
  const int k = 6 - e;
  if (k > 22 || k < -22) return false;
  *out = k >= 0 ? a * kPow10[k] : a / kPow10[-k];
  return true;
}

constexpr uint64_t kPow10Int[] = {1,
                                  10,
                                  100,
                                  1'000,
                                  10'000,
                                  100'000,
                                  1'000'000,
                                  10'000'000,
                                  100'000'000,
                                  1'000'000'000,
                                  10'000'000'000,
                                  100'000'000'000,
                                  1'000'000'000'000,
                                  10'000'000'000'000,
                                  100'000'000'000'000,
                                  1'000'000'000'000'000,
                                  10'000'000'000'000'000,
                                  100'000'000'000'000'000,
                                  1'000'000'000'000'000'000,
                                  10'000'000'000'000'000'000u};

// Number of decimal digits of `v` (1 for 0).
int digit_count(uint64_t v) {
  // floor(log10(2^(w-1))) from the bit width w (1233/4096 ≈ log10 2), then one comparison.
  const int t = (std::bit_width(v) * 1233) >> 12;
  return v == 0 ? 1 : t + (v >= kPow10Int[t] ? 1 : 0);
}

// Writes the last `count` decimal digits of `v` (zero-padded) so that they end at `end`,
// straight into the output: digits built in a scratch buffer and copied over would be read
// back before their two-byte stores have retired, which stalls the copy.
void put_digits(char* end, uint64_t v, int count) {
  static constexpr char kPairs[] =
      "0001020304050607080910111213141516171819202122232425262728293031323334353637383940414243444546474849"
      "5051525354555657585960616263646566676869707172737475767778798081828384858687888990919293949596979899";
  // Eight digits at a time split off in 64-bit arithmetic, the pairs in 32-bit.
  // The four pairs of a chunk come from two independent halves (a shorter dependency chain).
  while (count >= 8) {
    const uint32_t low = static_cast<uint32_t>(v % 100'000'000);
    v /= 100'000'000;
    const uint32_t hi = low / 10'000, lo = low % 10'000;
    std::memcpy(end - 8, kPairs + 2 * (hi / 100), 2);
    std::memcpy(end - 6, kPairs + 2 * (hi % 100), 2);
    std::memcpy(end - 4, kPairs + 2 * (lo / 100), 2);
    std::memcpy(end - 2, kPairs + 2 * (lo % 100), 2);
    end -= 8;
    count -= 8;
  }
  uint32_t w = static_cast<uint32_t>(v);
  for (; count >= 2; count -= 2) {
    end -= 2;
    std::memcpy(end, kPairs + 2 * (w % 100), 2);
    w /= 100;
  }
  if (count == 1) *--end = static_cast<char>('0' + w % 10);
}

}  // namespace

char* put_e6(char* p, double x) {
  if (!std::isfinite(x)) return fmt::format_to(p, "{:e}", x);
  if (std::signbit(x)) *p++ = '-';
  const double a = std::fabs(x);
  if (a == 0) {
    std::memcpy(p, "0.000000e+00", 12);
    return p + 12;
  }
  // a lies in [2^(b-1), 2^b), so its decimal exponent is floor((b - 1) · log10 2) or one
  // more (the interval spans 0.30103 decades); the scaled value says which.
  int b = 0;
  std::frexp(a, &b);
  int e = static_cast<int>(std::floor((b - 1) * 0.30102999566398120));
  double s = 0;
  bool fast = scaled(a, e, &s);
  if (fast && s < 1e6) fast = scaled(a, --e, &s);  // (guards an estimate rounded up)
  if (fast && s >= 1e7) fast = scaled(a, ++e, &s);
  // `s` is within half an ulp (≤ 1e-9 here) of the exact value, so unless its fraction lies
  // near one half, rounding it to a whole number rounds the exact value the same way.
  const double whole = std::floor(s);
  const double frac = s - whole;
  if (!fast || s < 1e6 || s >= 1e7 || std::fabs(frac - 0.5) < 1e-6) {
    return std::to_chars(p, p + kNumberTextMax, a, std::chars_format::scientific, 6).ptr;
  }
  uint32_t m = static_cast<uint32_t>(whole) + (frac > 0.5 ? 1 : 0);
  if (m == 10'000'000) {
    m = 1'000'000;
    ++e;
  }
  *p++ = static_cast<char>('0' + m / 1'000'000);
  *p++ = '.';
  put_digits(p + 6, m % 1'000'000, 6);
  return put_exponent(p + 6, e);
}

char* put_shortest(char* p, double x) {
  if (!std::isfinite(x)) return fmt::format_to(p, "{}", x);
  if (std::signbit(x)) *p++ = '-';
  const double a = std::fabs(x);
  if (a == 0) {
    *p++ = '0';
    return p;
  }
  // The shortest digits that read back to `a`, from fmt's own algorithm (Dragonbox, what
  // `{}` runs): a = significand · 10^exponent. fmt writes them in fixed notation when the
  // decimal exponent of the first digit is in −4…15, else as `d.ddde±XX`.
  const auto dec = fmt::detail::dragonbox::to_decimal(a);
  const uint64_t v = dec.significand;
  const int n = digit_count(v);
  const int e = dec.exponent + n - 1;
  if (e < -4 || e >= 16) {
    *p++ = static_cast<char>('0' + v / kPow10Int[n - 1]);
    if (n > 1) {
      *p++ = '.';
      put_digits(p + n - 1, v % kPow10Int[n - 1], n - 1);
      p += n - 1;
    }
    return put_exponent(p, e);
  }
  if (e < 0) {
    *p++ = '0';
    *p++ = '.';
    for (int i = -1; i > e; --i) *p++ = '0';
    put_digits(p + n, v, n);
    return p + n;
  }
  // e + 1 digits before the point (padded with zeros), the rest after it.
  if (n <= e + 1) {
    put_digits(p + n, v, n);
    p += n;
    for (int i = n; i <= e; ++i) *p++ = '0';
    return p;
  }
  const int fraction = n - e - 1;
  put_digits(p + e + 1, v / kPow10Int[fraction], e + 1);
  p += e + 1;
  *p++ = '.';
  put_digits(p + fraction, v % kPow10Int[fraction], fraction);
  return p + fraction;
}

char* put_int(char* p, int64_t v) {
  if (v < 0) {
    *p++ = '-';
    if (v == INT64_MIN) return std::to_chars(p, p + 24, static_cast<uint64_t>(INT64_MAX) + 1).ptr;
    v = -v;
  }
  const int n = digit_count(static_cast<uint64_t>(v));
  put_digits(p + n, static_cast<uint64_t>(v), n);
  return p + n;
}

}  // namespace nomec::backend
