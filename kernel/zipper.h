// Automatic zippering (seed report §7.3.3): fills the strip between two border chains,
// e.g. the base ring of one funnel and the top ring of another, with quads (preferred)
// and triangles chosen by dynamic programming.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <vector>

#include "kernel/mesh.h"
#include "kernel/result.h"

namespace nomec::kernel {

/// A border chain in world positions: an open segment a0..am, or a closed loop (the edge
/// a_m → a_0 is part of the chain).
struct ZipperChain {
  std::vector<glm::dvec3> points;
  bool is_closed = false;
};

/// Options for `zipper`, e.g. from NOME's `zipper z … penalty 2 endzipper`.
struct ZipperOptions {
  /// Extra cost of each triangle, in units of the mean chain edge length. Must be >= 0.
  double penalty = 1.3;
  /// Closed loops only: keep b0 paired with a0 (try both directions of B only) instead of
  /// trying every rotation of B's start.
  bool is_start_fixed = false;
};

/// The zipper faces. `soup` holds A's points (indices 0..|A|-1) followed by B's points
/// (|A|..|A|+|B|-1) and the faces between them.
struct ZipperResult {
  PolygonSoup soup;
  int32_t quad_count = 0;
  int32_t triangle_count = 0;
  /// Total cost of the chosen strip (see `zipper`).
  double cost = 0;
  /// Closed loops: the index of B's point paired with a0, and whether B was walked
  /// backwards. Open chains: 0 and false.
  int32_t b_start = 0;
  bool is_b_reversed = false;
};

/// Fills the strip between chains `a` and `b` with faces.
///
/// A state (i, j) means a "rung" edge joins a_i and b_j. Open chains start at the rung
/// (a0, b0) and end at (am, bn); closed loops are unrolled (the start point repeats at the
/// end) and start and end at (a0, b_s) for the rotation s and direction of B that give
/// the least cost. Each rung (i, j) costs
///   r(i, j) = |a_i − b_j| + s · |t_A(i) − t_B(j)|,
/// its length plus a vertex-skew term, where t_A(i) is the arc-length fraction of a_i
/// along (unrolled) A (0 at a0, 1 at the end), t_B likewise, and s is the mean length of
/// the chain edges of A and B (1 if that is 0); the skew term keeps the two chains
/// advancing in balance. The total cost is r(0, 0) plus, per step from (i, j),
/// - a quad a_i a_{i+1} b_{j+1} b_j to (i+1, j+1): r(i+1, j+1);
/// - a triangle a_i a_{i+1} b_j to (i+1, j): r(i+1, j) + penalty · s;
/// - a triangle a_i b_{j+1} b_j to (i, j+1): r(i, j+1) + penalty · s.
/// The minimum is found exactly: O(|A|·|B|) for open chains, O(|A|·|B|²) for closed
/// loops when every start is tried (both directions of B are always tried).
///
/// Orientation: every face traverses A's chain edges against the chain order
/// (a_{i+1} → a_i) and B's along it (b_j → b_{j+1}). So when chain A runs in the
/// direction its own mesh's faces traverse that border, welding the zipper faces to it
/// gives ordinary (non-Möbius) edges on A's side.
///
/// Fails with `InvalidArgument` if a chain is empty, an open chain has fewer than 2
/// points, a closed loop fewer than 3, one chain is closed and the other open, or the
/// penalty is negative.
Result<ZipperResult> zipper(const ZipperChain& a, const ZipperChain& b,
                            const ZipperOptions& options = {});

}  // namespace nomec::kernel
