// Shared edge-case builders for the kernel tests: small analytic shapes given as
// polygon soups (cube, grids glued into disks, annuli, Möbius bands, tori and Klein
// bottles, mixed triangle/quad/pentagon meshes). Every builder documents its exact
// V/E/F so tests can assert counts.
#pragma once

#include <fmt/format.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "kernel/mesh.h"

namespace nomec::kernel::testing {

/// Regular tetrahedron inscribed in the cube [-1, 1]³, 4 V, 6 E, 4 F, outward orientation.
inline PolygonSoup tetra_soup() {
  PolygonSoup s;
  s.add_vertex({1, 1, 1});
  s.add_vertex({1, -1, -1});
  s.add_vertex({-1, 1, -1});
  s.add_vertex({-1, -1, 1});
  s.add_face({0, 1, 2});
  s.add_face({0, 2, 3});
  s.add_face({0, 3, 1});
  s.add_face({1, 3, 2});
  return s;
}

/// Unit cube, 8 V, 12 E, 6 F, outward orientation.
inline PolygonSoup cube_soup() {
  PolygonSoup s;
  for (int i = 0; i < 8; ++i) {
    s.add_vertex({double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)},
                 fmt::format("v{}", i));
  }
  s.add_face({0, 2, 3, 1});  // z = 0
  s.add_face({4, 5, 7, 6});  // z = 1
  s.add_face({0, 1, 5, 4});  // y = 0
  s.add_face({2, 6, 7, 3});  // y = 1
  s.add_face({0, 4, 6, 2});  // x = 0
  s.add_face({1, 3, 7, 5});  // x = 1
  return s;
}

/// How the two pairs of sides of an n x m grid of quads are glued.
enum class Glue {
  None,      ///< disk: (n+1)(m+1) V, n(m+1)+m(n+1) E, nm F
  Cylinder,  ///< i wraps: annulus, 2 borders
  Mobius,    ///< i wraps with a flip of j: Möbius band, 1 border
  Torus,     ///< i and j wrap
  Klein,     ///< j wraps, i wraps with a flip of j: Klein bottle
};

/// An n x m quad grid with the given gluing. Positions come from a parametrisation in
/// which glued vertices coincide (Möbius band, torus, figure-8 Klein bottle), plus an
/// optional deterministic jitter per (glued) vertex so that distinct vertices never
/// coincide. Preconditions: n >= 3 when i wraps, m >= 3 when j wraps.
inline PolygonSoup grid_soup(int n, int m, Glue glue, double jitter = 0.0) {
  const bool wrap_i = glue != Glue::None;
  const bool flip_i = glue == Glue::Mobius || glue == Glue::Klein;
  const bool wrap_j = glue == Glue::Torus || glue == Glue::Klein;
  const int ni = wrap_i ? n : n + 1;
  const int nj = wrap_j ? m : m + 1;
  PolygonSoup s;
  const double pi = std::numbers::pi;
  for (int i = 0; i < ni; ++i) {
    for (int j = 0; j < nj; ++j) {
      const double u = 2 * pi * i / n;
      glm::dvec3 p;
      switch (glue) {
        case Glue::None:
          p = {double(i), double(j), 0.0};
          break;
        case Glue::Cylinder:
          p = {std::cos(u) * 3, std::sin(u) * 3, double(j) / m};
          break;
        case Glue::Mobius: {
          const double t = double(j) / m - 0.5;
          p = {(3 + t * std::cos(u / 2)) * std::cos(u), (3 + t * std::cos(u / 2)) * std::sin(u),
               t * std::sin(u / 2)};
          break;
        }
        case Glue::Torus: {
          const double v = 2 * pi * j / m;
          p = {(3 + std::cos(v)) * std::cos(u), (3 + std::cos(v)) * std::sin(u), std::sin(v)};
          break;
        }
        case Glue::Klein: {
          const double v = 2 * pi * j / m;
          const double r = 3 + std::cos(u / 2) * std::sin(v) - std::sin(u / 2) * std::sin(2 * v);
          p = {r * std::cos(u), r * std::sin(u),
               std::sin(u / 2) * std::sin(v) + std::cos(u / 2) * std::sin(2 * v)};
          break;
        }
      }
      if (jitter > 0) {
        const double h = std::sin(12.9898 * i + 78.233 * j) * 43758.5453;
        const double k = h - std::floor(h);
        p += jitter * glm::dvec3(k, std::fmod(k * 7.13, 1.0), std::fmod(k * 3.71, 1.0));
      }
      s.add_vertex(p);
    }
  }
  auto id = [&](int i, int j) {
    if (wrap_i && i == n) {
      i = 0;
      if (flip_i) {
        j = wrap_j ? (m - j) % m : m - j;
      }
    }
    if (wrap_j && j == m) {
      j = 0;
    }
    return i * nj + j;
  };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      s.add_face({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return s;
}

/// A disk of mixed polygons: a pentagon in the middle, surrounded by 5 quads, with 5
/// triangles filling the gaps: 15 V, 25 E, 11 F, one border of 10 edges.
inline PolygonSoup mixed_disk_soup() {
  PolygonSoup s;
  const double pi = std::numbers::pi;
  for (int i = 0; i < 5; ++i) {  // inner pentagon 0..4
    s.add_vertex({std::cos(2 * pi * i / 5), std::sin(2 * pi * i / 5), 0.2});
  }
  for (int i = 0; i < 10; ++i) {  // outer ring 5..14
    const double a = 2 * pi * (i - 0.5) / 10;
    s.add_vertex({2.5 * std::cos(a), 2.5 * std::sin(a), 0.3 * std::cos(3 * a)});
  }
  s.add_face({0, 1, 2, 3, 4});
  for (int i = 0; i < 5; ++i) {
    const int a = i, b = (i + 1) % 5;
    const int oa = 5 + 2 * i, ob = 5 + 2 * i + 1, oc = 5 + (2 * i + 2) % 10;
    s.add_face({oa, ob, b, a});  // quad on pentagon edge a-b
    s.add_face({ob, oc, b});     // triangle
  }
  return s;
}

/// The faces of an n x m torus `grid` (vertex (i, j) at index i * m + j, as `grid_soup`'s
/// Torus and the benchmarks' quad torus number them) made mixed: every third row split into
/// triangles, and in the row after it pairs of cells turned into pentagons by a vertex on
/// their shared edge (mixed polygons on a closed surface).
inline PolygonSoup mixed_torus_from(const PolygonSoup& grid, int n, int m) {
  PolygonSoup s;
  s.positions = grid.positions;
  auto id = [&](int i, int j) { return (i % n) * m + (j % m); };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      const int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if (i % 3 == 0) {
        s.add_face({a, b, c});
        s.add_face({a, c, d});
      } else if (i % 3 == 1 && j % 2 == 0 && j + 1 < m) {
        const int mid = s.add_vertex(0.5 * (grid.positions[c] + grid.positions[d]));
        s.add_face({a, b, c, mid, d});
        s.add_face({d, mid, c, id(i + 1, j + 2), id(i, j + 2)});
        ++j;
      } else {
        s.add_face({a, b, c, d});
      }
    }
  }
  return s;
}

}  // namespace nomec::kernel::testing
