// Typed integer handles for mesh elements. A `VertexId`, `EdgeId` or `FaceId` is an
// int32 index into the owning mesh's property arrays, passed by value, with an explicit
// `None` value; distinct tag types keep a face index from being used as an edge index.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>

#include "base/id.h"

namespace nomec::kernel {

/// The kernel's handles use the project's one typed index (base/id.h).
using nomec::Id;

struct VertexTag {};
struct EdgeTag {};
struct FaceTag {};

/// A vertex of a mesh, e.g. one declared by `point p1 (0 0 1) endpoint`.
using VertexId = Id<VertexTag>;
/// An edge of a mesh (shared by at most two faces).
using EdgeId = Id<EdgeTag>;
/// A face of a mesh, e.g. one declared by `face f1 (p1 p2 p3) endface`.
using FaceId = Id<FaceTag>;

/// One side of an edge, i.e. the use of an edge by one of its (at most two) faces:
/// `2 * edge + side`, where side 0 belongs to face F_a and side 1 to face F_b.
/// Rationale: the winged-edge wings must say on which side of the next edge the face
/// continues, which is ambiguous when both sides of an edge belong to the same face;
/// storing the side in the low bit keeps every wing a single int32.
struct EdgeUse {
  int32_t index = -1;

  constexpr EdgeUse() = default;
  constexpr explicit EdgeUse(int32_t i) : index(i) {}
  constexpr EdgeUse(EdgeId e, int side) : index(2 * e.index + side) {}
  static constexpr EdgeUse None() { return EdgeUse(); }
  constexpr bool is_valid() const { return index >= 0; }
  constexpr EdgeId edge() const { return EdgeId(index >> 1); }
  constexpr int side() const { return index & 1; }
  /// The use of the same edge on the other side.
  constexpr EdgeUse twin() const { return EdgeUse(index ^ 1); }
  friend constexpr bool operator==(EdgeUse a, EdgeUse b) = default;
};

}  // namespace nomec::kernel


