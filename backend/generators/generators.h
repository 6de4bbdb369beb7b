// Generators: pure functions from named numeric arguments to geometry in the generator's
// local frame, e.g. `funnel fun (8 0.4 -0.2 0.2) endfunnel` -> an open band of 8 quads with
// vertices named `bc0…bc7` and `hc0…hc7`. No knowledge of NOME syntax or the IR: the
// backend evaluates the arguments and passes them by the names of docs/generators.md.
#pragma once

#include <glm/vec3.hpp>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

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
};

/// Evaluated arguments: numbers by argument name (`n`, `ro`, `radius` …), raw texts
/// (`funcX` …), and named control points for curves, in order.
struct GeneratorArgs {
  std::map<std::string, double, std::less<>> numbers;
  std::map<std::string, std::string, std::less<>> texts;
  std::vector<glm::dvec3> points;
  std::vector<std::string> point_names;
  std::string dialect = "nome";  // "nome", "nome3" or "slide"
};

/// A problem with the arguments, e.g. `n` = 2 for a funnel: names the argument so the
/// backend can point at it.
struct GeneratorError {
  std::string argument;  // "" when it concerns the whole generator
  std::string message;   // lowercase, no trailing period
  std::string hint;      // what would be accepted, or "" (domain rules give one)
};

struct GeneratorResult {
  std::optional<Generated> value;
  GeneratorError error;
  bool ok() const { return value.has_value(); }
};

/// Runs the generator named by its NOME keyword (`funnel`, `tunnel`, `torus` …).
/// Unknown keywords and bad arguments give an error, never an exception.
GeneratorResult generate(std::string_view keyword, const GeneratorArgs& args);

/// Whether `keyword` names a generator this module implements.
bool is_generator(std::string_view keyword);

}  // namespace nomec::backend
