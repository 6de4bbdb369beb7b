// The kernel tests' one way to build a soup they expect to be a valid mesh: a failure is a
// test failure with the kernel's message, not a crash.
#pragma once

#include <gtest/gtest.h>

#include <utility>

#include "kernel/mesh.h"

namespace nomec::kernel::testing {

inline Mesh build(const PolygonSoup& s) {
  auto mesh = build_mesh(s);
  EXPECT_TRUE(mesh.has_value()) << (mesh ? "" : mesh.error().message);
  return mesh ? std::move(*mesh) : Mesh{};
}

}  // namespace nomec::kernel::testing
