// Topology report of a mesh, per connected component: counts, Euler characteristic,
// orientability (found by propagating face orientations across regular and Möbius
// edges), border loops and genus. Used by tests, mesh goldens and `--emit summary`.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "kernel/mesh.h"

namespace nomec::kernel {

/// Topology of one connected component (faces connected through shared edges), e.g. the
/// single band of `mobius_band_open.nome`.
struct ComponentTopology {
  int32_t vertex_count = 0;
  int32_t edge_count = 0;
  int32_t face_count = 0;
  int32_t mobius_edge_count = 0;
  int32_t border_loop_count = 0;
  /// V - E + F.
  int32_t euler_characteristic = 0;
  bool is_orientable = true;
  /// No border loops (every edge has two faces). Meshes are always 2-manifold, so a
  /// closed component is watertight.
  bool is_closed = true;
  /// Orientable genus g = (2 - χ - b) / 2, or non-orientable genus k = 2 - χ - b
  /// (the number of cross-caps) when `!is_orientable`.
  int32_t genus = 0;
  /// Smallest face index in the component (a stable identifier).
  FaceId first_face;
};

/// Whole-mesh report: one entry per component (ordered by first face) and totals.
struct TopologyReport {
  std::vector<ComponentTopology> components;
  int32_t vertex_count = 0;  ///< vertices used by faces
  int32_t edge_count = 0;
  int32_t face_count = 0;
  int32_t euler_characteristic = 0;
  int32_t border_loop_count = 0;
  int32_t isolated_vertex_count = 0;  ///< vertices no face uses (not in components)
  bool is_orientable = true;          ///< all components orientable
  bool is_closed = true;              ///< all components closed
};

/// Axis-aligned bounds of the vertices used by faces (min > max when there are none).
struct BoundingBox {
  glm::dvec3 min{std::numeric_limits<double>::infinity()};
  glm::dvec3 max{-std::numeric_limits<double>::infinity()};
};

/// Bounding box of the vertices used by faces. Never fails.
BoundingBox bounding_box(const Mesh& mesh);

/// Order-independent hash of the used vertex positions rounded to multiples of
/// `quantum` (> 0), for mesh goldens that must not depend on element numbering. Equal
/// meshes up to renumbering hash equally; coordinates within quantum/2 of a rounding
/// boundary may flip, so goldens should use a quantum well above their noise.
uint64_t position_hash(const Mesh& mesh, double quantum);

/// Computes the report in time linear in the number of edges. Never fails.
TopologyReport topology(const Mesh& mesh);

/// Per face, the index into `topology(mesh).components` of its component.
std::vector<int32_t> face_components(const Mesh& mesh);

/// The first broken winged-edge invariant of `mesh`, or "" when it has none: every face's
/// loop of uses closes (prev ∘ next = id, each use's head is the next use's tail, every use
/// belongs to the face), every edge has a face, every index is in range and every position
/// is finite. Linear in the mesh's size; never loops on a broken mesh. The fuzzers and
/// the kernel tests check results with it.
std::string mesh_problem(const Mesh& mesh);

}  // namespace nomec::kernel
