// Shared helpers for the generator tests: run a generator, build its soup with the
// kernel, and look up named vertices.
#pragma once

#include <gtest/gtest.h>

#include <glm/vec3.hpp>
#include <string>
#include <utility>
#include <vector>

#include "backend/generators/generators.h"
#include "kernel/mesh.h"
#include "kernel/topology.h"

namespace nomec::backend::testing {

inline GeneratorArgs numbers(std::vector<std::pair<std::string, double>> values,
                             std::string dialect = "nome") {
  GeneratorArgs a;
  for (auto& [k, v] : values) a.numbers[k] = v;
  a.dialect = std::move(dialect);
  return a;
}

/// Runs the generator and expects success.
inline Generated run(std::string_view keyword, const GeneratorArgs& args) {
  GeneratorResult r = generate(keyword, args);
  EXPECT_TRUE(r.ok()) << keyword << ": " << r.error.argument << ": " << r.error.message;
  return r.ok() ? *r.value : Generated{};
}

/// Runs the generator and expects an error naming `argument`.
inline GeneratorError run_error(std::string_view keyword, const GeneratorArgs& args) {
  GeneratorResult r = generate(keyword, args);
  EXPECT_FALSE(r.ok()) << keyword << " should fail";
  return r.error;
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
      vol += (a.x * (b.y * c.z - b.z * c.y) - a.y * (b.x * c.z - b.z * c.x) +
              a.z * (b.x * c.y - b.y * c.x)) / 6.0;
    }
    off += n;
  }
  return vol;
}

}  // namespace nomec::backend::testing
