// Shared helpers for the generator tests: arguments by the catalogue's names (as a file
// writes them), running a generator, building its soup with the kernel, and looking up
// named vertices.
#pragma once

#include <gtest/gtest.h>

#include <glm/vec3.hpp>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "backend/generators/generators.h"
#include "kernel/mesh.h"
#include "kernel/topology.h"

namespace nomec::backend::testing {

/// A generator's arguments by name (canonical or as a dialect writes them).
struct Args {
  std::vector<std::pair<std::string, double>> numbers;
  std::string dialect = "nome";
  std::map<std::string, ScalarFunction> functions;
  std::vector<glm::dvec3> points;
  std::vector<std::string> point_names;
  std::set<std::string> flags;
  bool is_path_closed = false;
};

inline Args numbers(std::vector<std::pair<std::string, double>> values, std::string dialect = "nome") {
  Args a;
  a.numbers = std::move(values);
  a.dialect = std::move(dialect);
  return a;
}

/// A function of the generator's variables that cannot fail.
inline ScalarFunction fn(std::function<double(std::span<const double>)> f) {
  return [f = std::move(f)](std::span<const double> v, std::string*) -> std::optional<double> { return f(v); };
}

inline ir::GenKind kind_of(std::string_view keyword) {
  std::optional<ir::GenKind> k = ir::generator_by_keyword(keyword);
  EXPECT_TRUE(k.has_value()) << "no generator `" << keyword << "`";
  return k.value_or(ir::GenKind::Funnel);
}

/// The evaluated input for generator `keyword` (argument names resolved by the catalogue).
inline GeneratorInput input_for(std::string_view keyword, const Args& a) {
  const ir::GenKind kind = kind_of(keyword);
  const ir::GeneratorInfo& info = ir::generator(kind);
  GeneratorInput in = GeneratorInput::for_kind(kind, dialect_by_name(a.dialect).value_or(Dialect::Nome));
  auto arg = [&](const std::string& name) {
    std::optional<ir::ArgIndex> i = info.arg_named(name);
    EXPECT_TRUE(i.has_value()) << keyword << " has no argument `" << name << "`";
    return i.value_or(0);
  };
  for (const auto& [name, v] : a.numbers) in.numbers[arg(name)] = v;
  for (const auto& [name, f] : a.functions) in.functions[arg(name)] = f;
  for (const std::string& name : a.flags) in.flags[arg(name)] = 1;
  in.points = a.points;
  in.point_names = a.point_names;
  in.is_path_closed = a.is_path_closed;
  return in;
}

/// Runs the generator and expects success.
inline Generated run(std::string_view keyword, const Args& args) {
  GeneratorResult r = generate(input_for(keyword, args));
  EXPECT_TRUE(r.ok()) << keyword << ": " << r.error.message;
  return r.ok() ? *r.value : Generated{};
}

/// A generator error with its argument named as the dialect writes it.
struct NamedError {
  std::string argument;
  std::string message;
  std::string hint;
};

/// Runs the generator and expects an error.
inline NamedError run_error(std::string_view keyword, const Args& args) {
  GeneratorInput in = input_for(keyword, args);
  GeneratorResult r = generate(in);
  EXPECT_FALSE(r.ok()) << keyword << " should fail";
  NamedError e{"", r.error.message, r.error.hint};
  if (r.error.arg != ir::kNoArg) e.argument = std::string(ir::generator(in.kind).display_name(r.error.arg, in.dialect));
  return e;
}

/// Builds the soup into a mesh (expected to succeed) and reports its topology.
inline kernel::TopologyReport topo(const kernel::PolygonSoup& soup) {
  auto mesh = kernel::build_mesh(soup);
  EXPECT_TRUE(mesh.has_value()) << (mesh ? "" : mesh.error().message);
  if (!mesh) return {};
  return kernel::topology(*mesh);
}

inline glm::dvec3 named(const kernel::PolygonSoup& soup, const std::string& name) {
  for (size_t i = 0; i < soup.names.size(); ++i) {
    if (soup.names[i] == name) return soup.positions[i];
  }
  ADD_FAILURE() << "no vertex named " << name;
  return {};
}

inline void expect_near(const glm::dvec3& a, const glm::dvec3& b, double eps = 1e-9) {
  EXPECT_NEAR(a.x, b.x, eps);
  EXPECT_NEAR(a.y, b.y, eps);
  EXPECT_NEAR(a.z, b.z, eps);
}

// Signed volume enclosed by the soup's faces (fan-triangulated); > 0 for outward faces.
inline double signed_volume(const kernel::PolygonSoup& s) {
  double vol = 0;
  size_t off = 0;
  for (int32_t n : s.face_sizes) {
    const glm::dvec3 a = s.positions[s.face_vertices[off]];
    for (int32_t k = 1; k + 1 < n; ++k) {
      const glm::dvec3 b = s.positions[s.face_vertices[off + k]];
      const glm::dvec3 c = s.positions[s.face_vertices[off + k + 1]];
      vol += (a.x * (b.y * c.z - b.z * c.y) - a.y * (b.x * c.z - b.z * c.x) + a.z * (b.x * c.y - b.y * c.x)) / 6.0;
    }
    off += n;
  }
  return vol;
}

}  // namespace nomec::backend::testing
