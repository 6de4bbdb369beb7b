// Internal helpers shared by the generator implementations: typed argument lookup and
// validation, and the quad-grid builder (with seam welding) most surfaces use. Not part
// of the public API (generators.h).
#pragma once

#include <cmath>
#include <functional>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include "backend/generators/generators.h"

namespace nomec::backend::detail {

/// Internal failure, thrown only inside this module and turned into a `GeneratorError`
/// by `generate` (the public API never throws).
struct Failure {
  GeneratorError error;
};
[[noreturn]] void fail(ir::ArgIndex arg, std::string message);

inline constexpr double kPi = std::numbers::pi;
inline double radians(double degrees) { return degrees * kPi / 180.0; }

/// A number as it appears in an error message (`%g`: `0.5`, `1e+06`).
inline std::string fmt_number(double v) { return ir::format_argument(v); }

/// Largest count accepted per dimension, and largest number of generated vertices.
inline constexpr int kMaxSegments = ir::kMaxCount;
inline constexpr long long kMaxVertices = 4000000;

/// Reads a generator's arguments by their typed names (`gen_arg::Funnel::ro`); a failure
/// names the argument as the dialect writes it.
class ArgReader {
 public:
  explicit ArgReader(const GeneratorInput& in) : in_(in), info_(ir::generator(in.kind)) {}
  const GeneratorInput& raw() const { return in_; }
  Dialect dialect() const { return in_.dialect; }

  /// `arg` as the dialect writes it, e.g. `radius` for a NOME3 funnel's `ro`.
  template <typename A>
  std::string name(A arg) const {
    return std::string(info_.display_name(ir::arg_index(arg), in_.dialect));
  }
  template <typename A>
  bool has(A arg) const {
    const size_t i = ir::arg_index(arg);
    return i < in_.numbers.size() && in_.numbers[i].has_value();
  }
  /// A finite number; fails when absent.
  template <typename A>
  double number(A arg) const {
    if (!has(arg)) fail(ir::arg_index(arg), "missing argument `" + name(arg) + "`");
    const double v = *in_.numbers[ir::arg_index(arg)];
    if (!std::isfinite(v)) fail(ir::arg_index(arg), "`" + name(arg) + "` must be a finite number");
    return v;
  }
  template <typename A>
  double number_or(A arg, double fallback) const {
    return has(arg) ? number(arg) : fallback;
  }
  /// A whole-number count >= `min` (rounded, and <= kMaxSegments).
  template <typename A>
  int count(A arg, int min) const {
    return as_count(ir::arg_index(arg), name(arg), number(arg), min);
  }
  template <typename A>
  int count_or(A arg, int min, int fallback) const {
    return has(arg) ? count(arg, min) : fallback;
  }
  /// A number > 0.
  template <typename A>
  double positive(A arg) const {
    const double v = number(arg);
    if (!(v > 0)) fail(ir::arg_index(arg), "`" + name(arg) + "` must be positive, got " + fmt_number(v));
    return v;
  }
  /// A Flag argument: present as a bare word, or given a non-zero value.
  template <typename A>
  bool flag(A arg) const {
    const size_t i = ir::arg_index(arg);
    if (i < in_.numbers.size() && in_.numbers[i].has_value()) return *in_.numbers[i] != 0.0;
    return i < in_.flags.size() && in_.flags[i] != 0;
  }
  /// A Function argument; fails when absent.
  template <typename A>
  const ScalarFunction& function(A arg) const {
    const size_t i = ir::arg_index(arg);
    if (i >= in_.functions.size() || !in_.functions[i]) {
      fail(ir::arg_index(arg), "missing function `" + name(arg) + " [ ... ]`");
    }
    return in_.functions[i];
  }

 private:
  static int as_count(ir::ArgIndex arg, const std::string& n, double v, int min);
  const GeneratorInput& in_;
  const ir::GeneratorInfo& info_;
};

/// True if an angular span in degrees covers the full circle (within 1e-9 degrees).
/// Spans above 360 fail naming `argument`; spans <= 0 too.
bool full_turn(double span_degrees, ir::ArgIndex arg, const std::string& name);

/// Adds `segs_i` x `segs_j` quads on a grid of vertices. Along a wrapped direction the
/// last row of vertices is the first one (welded seam, segs >= 3 required by callers);
/// otherwise there are segs+1 rows. Vertex (i, j) gets position `pos(i, j)` (with i, j
/// the unwrapped parameters 0…segs) and the name `v{i}_{j}`. Faces are
/// (i,j) (i+1,j) (i+1,j+1) (i,j+1), reversed if `flip`. Returns the index of vertex (0,0).
int32_t add_grid(kernel::PolygonSoup& soup, int segs_i, int segs_j, bool wrap_i, bool wrap_j,
                 const std::function<glm::dvec3(int, int)>& pos, bool flip = false);

/// A mesh as the original tool built it (its vertices, names and faces, coincident seam
/// copies and pole rings included), then cleaned: `weld(v, onto)` marks vertex v as a
/// copy of `onto` (an earlier vertex at the same position). `finish` keeps the other
/// vertices with their positions and names, turns a welded vertex's name into an alias,
/// drops repeated corners from the faces and the faces left with fewer than 3 corners, and
/// drops unused vertices (keeping their names as aliases).
class OriginalMesh {
 public:
  int32_t add(const glm::dvec3& position, std::string name);
  void face(std::vector<int32_t> corners) { faces_.push_back(std::move(corners)); }
  void weld(int32_t v, int32_t onto) { onto_[v] = onto; }
  const glm::dvec3& position(int32_t v) const { return positions_[v]; }
  Generated finish() const;

 private:
  std::vector<glm::dvec3> positions_;
  std::vector<std::string> names_;
  std::vector<int32_t> onto_;
  std::vector<std::vector<int32_t>> faces_;
};

/// The Dupin cyclide's standard parametrisation (NOME3's `dupin`, generators-original.md §7):
/// the point at angles u (around the ring) and v (around the tube), in radians. A ring
/// cyclide when b² = a² − c² and |c| < d < a; with c = 0 and b = a the torus of radii a, d.
glm::dvec3 dupin_point(double a, double b, double c, double d, double u, double v);

/// Fails if a grid of this size would exceed kMaxVertices.
void check_size(long long vertices, ir::ArgIndex arg);

}  // namespace nomec::backend::detail
