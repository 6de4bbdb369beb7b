// Generators: pure functions from evaluated arguments to geometry in the generator's local
// frame, e.g. funnel (n = 8, ro = 0.4, ratio = -0.2, h = 0.2) -> an open band of 8 quads with
// vertices named `bc0…bc7` and `hc0…hc7`. One `make_<Kind>` function per entry of the
// generator catalogue (ir/generators.def), dispatched by kind; arguments are addressed by the
// catalogue's typed argument names. No knowledge of NOME syntax or of IR nodes: the backend
// evaluates the arguments and hands them over as numbers, points and functions.
#pragma once

#include <functional>
#include <glm/vec3.hpp>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "ir/generator_catalogue.h"
#include "kernel/mesh.h"

namespace nomec::backend {

/// A generator's output. `soup` holds the faces (with every vertex named, so faces
/// elsewhere can reference `inst.hc3`); `curves` holds polylines (e.g. `circle`,
/// `helix`, a `bspline` path) as indices into `soup.positions`.
struct Generated {
  kernel::PolygonSoup soup;
  struct Curve {
    std::vector<int32_t> vertices;
    bool is_closed = false;
  };
  std::vector<Curve> curves;
  /// Names the original gave that name no vertex of `soup`: vertices nomec welded onto
  /// another (a seam copy, a pole ring) or did not make (a sphere's unused `center`).
  /// `inst.NAME` resolves to the position.
  std::vector<std::pair<std::string, glm::dvec3>> aliases;
};

/// A function argument (`funcX [cos(u)*v]`): its value at the variables' values, in the
/// order of the catalogue's variables; nullopt where it has none (with `problem` saying
/// why, e.g. "division by zero: 1 / 0").
using ScalarFunction = std::function<std::optional<double>(std::span<const double> variables, std::string* problem)>;

/// The evaluated arguments of one generator, by the catalogue's argument index: numbers,
/// flags, functions; and the points of its point list or path, in order.
struct GeneratorInput {
  ir::GenKind kind = ir::GenKind::Funnel;
  Dialect dialect = Dialect::Nome;
  std::vector<std::optional<double>> numbers;  // by ArgIndex
  std::vector<uint8_t> flags;                  // by ArgIndex: a Flag argument is set
  std::vector<ScalarFunction> functions;       // by ArgIndex
  std::vector<glm::dvec3> points;              // a Points or Path argument's points
  std::vector<std::string> point_names;
  bool is_path_closed = false;

  /// Input for `kind` with every argument unknown.
  static GeneratorInput for_kind(ir::GenKind kind, Dialect dialect);
  template <typename A>
  void set(A arg, double v) {
    numbers[ir::arg_index(arg)] = v;
  }
};

/// A problem with the arguments, e.g. `n` = 2 for a funnel: names the argument so the
/// backend can point at it.
struct GeneratorError {
  ir::ArgIndex arg = ir::kNoArg;  // kNoArg when it concerns the whole generator
  std::string message;            // lowercase, no trailing period
  std::string hint;               // what would be accepted, or ""
};

struct GeneratorResult {
  std::optional<Generated> value;
  GeneratorError error;
  bool ok() const { return value.has_value(); }
};

/// Runs the generator: first the catalogue's argument-domain rules (the same messages
/// `--check` gives), then its geometry. Bad arguments give an error, never an exception.
GeneratorResult generate(const GeneratorInput& input);

}  // namespace nomec::backend
