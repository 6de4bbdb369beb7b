// Internal helpers shared by the generator implementations: argument lookup and
// validation, and the quad-grid builder (with seam welding) most surfaces use. Not part
// of the public API (generators.h).
#pragma once

#include <cmath>
#include <functional>
#include <initializer_list>
#include <numbers>
#include <string>
#include <string_view>

#include "backend/generators/generators.h"

namespace nomec::backend::detail {

/// Internal failure, thrown only inside this module and turned into a `GeneratorError`
/// by `generate` (the public API never throws).
struct Failure {
  GeneratorError error;
};
[[noreturn]] void fail(std::string_view argument, std::string message);

inline constexpr double kPi = std::numbers::pi;
inline double radians(double degrees) { return degrees * kPi / 180.0; }

/// A number as it appears in an error message (`%g`: `0.5`, `1e+06`).
std::string fmt_number(double v);

/// Largest count accepted per dimension, and largest number of generated vertices.
inline constexpr int kMaxSegments = 100000;
inline constexpr long long kMaxVertices = 4000000;

/// A looked-up argument: the name it was found under and its value.
struct Arg {
  std::string_view name;
  double value = 0.0;
};

/// Reads numbers from `GeneratorArgs` by name. Each lookup takes the accepted names in
/// order of preference (the dialect's name first); a missing argument fails naming the
/// first one.
class ArgReader {
 public:
  explicit ArgReader(const GeneratorArgs& args) : args_(args) {}
  bool is_nome3() const { return args_.dialect == "nome3"; }
  const GeneratorArgs& raw() const { return args_; }

  Arg number(std::initializer_list<std::string_view> names) const;
  /// Like `number`, but returns `fallback` (under the first name) when absent.
  Arg number_or(std::initializer_list<std::string_view> names, double fallback) const;
  bool has(std::string_view name) const;
  /// A whole-number count >= `min` (and <= kMaxSegments).
  int count(std::initializer_list<std::string_view> names, int min) const;
  /// A count with a default when absent.
  int count_or(std::initializer_list<std::string_view> names, int min, int fallback) const;
  /// A number > 0.
  double positive(std::initializer_list<std::string_view> names) const;
  /// Raw text (e.g. `funcX`), with one pair of surrounding `[ ]` removed.
  std::string text(std::string_view name) const;

 private:
  const GeneratorArgs& args_;
};

/// Validates a whole-number value of `arg` (>= min).
int as_count(const Arg& arg, int min);

/// True if an angular span in degrees covers the full circle (within 1e-9 degrees).
/// Spans above 360 fail naming `argument`; spans <= 0 too.
bool full_turn(double span_degrees, std::string_view argument);

/// Adds `segs_i` x `segs_j` quads on a grid of vertices. Along a wrapped direction the
/// last row of vertices is the first one (welded seam, segs >= 3 required by callers);
/// otherwise there are segs+1 rows. Vertex (i, j) gets position `pos(i, j)` (with i, j
/// the unwrapped parameters 0…segs) and the name `v{i}_{j}`. Faces are
/// (i,j) (i+1,j) (i+1,j+1) (i,j+1), reversed if `flip`. Returns the index of vertex (0,0).
int32_t add_grid(kernel::PolygonSoup& soup, int segs_i, int segs_j, bool wrap_i, bool wrap_j,
                 const std::function<glm::dvec3(int, int)>& pos, bool flip = false);

/// Fails if a grid of this size would exceed kMaxVertices.
void check_size(long long vertices, std::string_view argument);

}  // namespace nomec::backend::detail
