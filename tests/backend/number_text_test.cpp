// The writers' number text (backend/number_text.h) against fmt, which the writers used
// before: the same characters for `{:e}` and `{}` on random bit patterns of every exponent,
// on random coordinates, and on the cases where a fast path could go wrong (powers of ten,
// seven-digit rounding that carries, exact halves, subnormals, signed zeros, inf and nan).
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <bit>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "backend/number_text.h"

namespace nomec::backend {
namespace {

std::string e6(double x) {
  char buf[kNumberTextMax];
  return std::string(buf, put_e6(buf, x));
}
std::string shortest(double x) {
  char buf[kNumberTextMax];
  return std::string(buf, put_shortest(buf, x));
}

void expect_like_fmt(double x) {
  ASSERT_EQ(e6(x), fmt::format("{:e}", x)) << std::bit_cast<uint64_t>(x);
  ASSERT_EQ(shortest(x), fmt::format("{}", x)) << std::bit_cast<uint64_t>(x);
}

TEST(NumberText, RandomBitPatternsOfEveryExponent) {
  std::mt19937_64 rng(18);
  for (int i = 0; i < 400000; ++i) {
    const double x = std::bit_cast<double>(rng());
    if (std::isnan(x)) continue;
    expect_like_fmt(x);
  }
}

TEST(NumberText, RandomCoordinates) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> d(-10, 10);
  std::uniform_int_distribution<int> scale(-30, 30);
  for (int i = 0; i < 400000; ++i) expect_like_fmt(d(rng) * std::pow(10.0, scale(rng)));
}

TEST(NumberText, EdgeCases) {
  std::vector<double> xs = {0.0,
                            -0.0,
                            1.0,
                            -1.0,
                            0.5,
                            0.1,
                            0.3,
                            0.30000000000000004,
                            1e-4,
                            9.9999e-5,
                            1e-5,
                            1e15,
                            9.999999999999999e15,
                            1e16,
                            1e17,
                            123456789012345678.0,
                            100000.0,
                            1048576.5,    // 1.0485765e6 exactly: a half at the seventh digit
                            1048577.5,
                            9999999.5,    // rounds up to 1.000000e+07
                            9999995.0,
                            0.99999995,
                            999999.95,
                            2.5e-7,
                            std::numeric_limits<double>::min(),
                            std::numeric_limits<double>::denorm_min(),
                            std::numeric_limits<double>::max(),
                            std::numeric_limits<double>::lowest(),
                            std::numeric_limits<double>::epsilon(),
                            std::numeric_limits<double>::infinity(),
                            -std::numeric_limits<double>::infinity()};
  for (int k = -320; k <= 308; ++k) {
    xs.push_back(std::pow(10.0, k));
    xs.push_back(std::nextafter(std::pow(10.0, k), 0.0));
    xs.push_back(std::nextafter(std::pow(10.0, k), std::numeric_limits<double>::infinity()));
    xs.push_back(9.9999995 * std::pow(10.0, k));
  }
  for (double x : xs) {
    expect_like_fmt(x);
    expect_like_fmt(-x);
  }
  EXPECT_EQ(e6(std::nan("")), fmt::format("{:e}", std::nan("")));
  EXPECT_EQ(shortest(std::nan("")), fmt::format("{}", std::nan("")));
  // A half at the seventh digit rounds to even, on the exact binary value.
  EXPECT_EQ(e6(1048576.5), "1.048576e+06");
  EXPECT_EQ(e6(1048577.5), "1.048578e+06");
  EXPECT_EQ(e6(9999999.5), "1.000000e+07");
}

// Numbers with few significant digits (whole numbers, short decimals, floats widened to
// double), where the shortest digits are padded with zeros on either side of the point,
// and the layout boundaries of `{}` (decimal exponents −5, −4, 15 and 16).
TEST(NumberText, ShortDigitsAndLayoutBoundaries) {
  std::mt19937_64 rng(2026);
  std::uniform_int_distribution<int64_t> whole(0, int64_t{1} << 62);
  std::uniform_int_distribution<int> digits(1, 17);
  std::uniform_int_distribution<int> exponent(-24, 24);
  for (int i = 0; i < 200000; ++i) {
    const int64_t w = whole(rng);
    expect_like_fmt(static_cast<double>(w));
    expect_like_fmt(static_cast<double>(w % 1000000));
    int64_t m = 1;
    for (int k = digits(rng); k > 0; --k) m *= 10;
    // A short decimal: up to 17 digits times a power of ten, and a float's value.
    const double x = static_cast<double>(w % m) * std::pow(10.0, exponent(rng));
    expect_like_fmt(x);
    expect_like_fmt(static_cast<double>(static_cast<float>(x)));
    expect_like_fmt(std::bit_cast<double>(std::bit_cast<uint64_t>(x) + 1));
  }
  for (int k = -6; k <= 17; ++k) {
    const double p = std::pow(10.0, k);
    for (double x : {p, 1.5 * p, 9.5 * p, 1.2345678901234567 * p, 9.999999999999999 * p}) {
      expect_like_fmt(x);
      expect_like_fmt(std::nextafter(x, 0.0));
    }
  }
}

// `{:e}` near powers of two, where the decimal exponent estimate from the binary exponent
// changes, over the whole range of exponents.
TEST(NumberText, ScientificAroundPowersOfTwo) {
  for (int b = -1074; b <= 1023; ++b) {
    const double x = std::ldexp(1.0, b);
    expect_like_fmt(x);
    expect_like_fmt(std::nextafter(x, 0.0));
    expect_like_fmt(std::nextafter(x, std::numeric_limits<double>::infinity()));
    expect_like_fmt(x * 1.5);
  }
}

TEST(NumberText, WholeNumbers) {
  for (int64_t v : {int64_t{0}, int64_t{7}, int64_t{-42}, int64_t{1234567890123}, std::numeric_limits<int64_t>::min()}) {
    char buf[kNumberTextMax];
    EXPECT_EQ(std::string(buf, put_int(buf, v)), fmt::format("{}", v));
  }
}

}  // namespace
}  // namespace nomec::backend
