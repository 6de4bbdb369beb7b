// Argument lookup/validation and the quad-grid builder shared by the generators.
#include "backend/generators/common.h"

#include <cmath>
#include <cstdio>
#include <string>

namespace nomec::backend::detail {

void fail(std::string_view argument, std::string message) {
  throw Failure{GeneratorError{std::string(argument), std::move(message), ""}};
}

std::string fmt_number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

bool ArgReader::has(std::string_view name) const { return args_.numbers.find(name) != args_.numbers.end(); }

Arg ArgReader::number(std::initializer_list<std::string_view> names) const {
  for (std::string_view n : names) {
    auto it = args_.numbers.find(n);
    if (it != args_.numbers.end()) {
      if (!std::isfinite(it->second)) {
        fail(n, "`" + std::string(n) + "` must be a finite number");
      }
      return Arg{n, it->second};
    }
  }
  const std::string_view first = *names.begin();
  fail(first, "missing argument `" + std::string(first) + "`");
}

Arg ArgReader::number_or(std::initializer_list<std::string_view> names, double fallback) const {
  for (std::string_view n : names) {
    if (has(n)) {
      return number({n});
    }
  }
  return Arg{*names.begin(), fallback};
}

int as_count(const Arg& arg, int min) {
  const double v = arg.value;
  const std::string n(arg.name);
  // Counts are rounded to the nearest whole number (the checker's `NonIntegerCount`
  // warning says so).
  if (std::round(v) < min) {
    fail(n, "`" + n + "` must be at least " + std::to_string(min) + ", got " + fmt_number(v));
  }
  if (std::round(v) > kMaxSegments) {
    fail(n, "`" + n + "` must be at most " + std::to_string(kMaxSegments) + ", got " +
                fmt_number(v));
  }
  return static_cast<int>(std::lround(v));
}

int ArgReader::count(std::initializer_list<std::string_view> names, int min) const {
  return as_count(number(names), min);
}

int ArgReader::count_or(std::initializer_list<std::string_view> names, int min,
                        int fallback) const {
  for (std::string_view n : names) {
    if (has(n)) {
      return count({n}, min);
    }
  }
  return fallback;
}

double ArgReader::positive(std::initializer_list<std::string_view> names) const {
  Arg a = number(names);
  if (!(a.value > 0)) {
    const std::string n(a.name);
    fail(n, "`" + n + "` must be positive, got " + fmt_number(a.value));
  }
  return a.value;
}

std::string ArgReader::text(std::string_view name) const {
  auto it = args_.texts.find(name);
  if (it == args_.texts.end()) {
    fail(name, "missing function `" + std::string(name) + " [ ... ]`");
  }
  std::string t = it->second;
  size_t b = t.find_first_not_of(" \t\r\n");
  size_t e = t.find_last_not_of(" \t\r\n");
  if (b == std::string::npos) {
    return "";
  }
  t = t.substr(b, e - b + 1);
  if (t.size() >= 2 && t.front() == '[' && t.back() == ']') {
    t = t.substr(1, t.size() - 2);
  }
  return t;
}

bool full_turn(double span, std::string_view argument) {
  if (!(span > 0)) {
    fail(argument, "angle range `" + std::string(argument) + "` must be positive, got " +
                       fmt_number(span) + " degrees");
  }
  if (span > 360.0 + 1e-9) {
    fail(argument, "angle range `" + std::string(argument) + "` must be at most 360 degrees, got " +
                       fmt_number(span));
  }
  return span >= 360.0 - 1e-9;
}

void check_size(long long vertices, std::string_view argument) {
  if (vertices > kMaxVertices) {
    fail(argument, "too many vertices (" + std::to_string(vertices) + "; at most " +
                       std::to_string(kMaxVertices) + ")");
  }
}

int32_t add_grid(kernel::PolygonSoup& soup, int segs_i, int segs_j, bool wrap_i, bool wrap_j,
                 const std::function<glm::dvec3(int, int)>& pos, bool flip) {
  const int ni = wrap_i ? segs_i : segs_i + 1;
  const int nj = wrap_j ? segs_j : segs_j + 1;
  const int32_t base = soup.vertex_count();
  for (int i = 0; i < ni; ++i) {
    for (int j = 0; j < nj; ++j) {
      soup.add_vertex(pos(i, j), "v" + std::to_string(i) + "_" + std::to_string(j));
    }
  }
  auto at = [&](int i, int j) -> int32_t {
    return base + (i % ni) * nj + (j % nj);
  };
  for (int i = 0; i < segs_i; ++i) {
    for (int j = 0; j < segs_j; ++j) {
      if (flip) {
        soup.add_face({at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)});
      } else {
        soup.add_face({at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
      }
    }
  }
  return base;
}

}  // namespace nomec::backend::detail
