// Benchmark meshes shared by the kernel benchmarks (a quad torus of any size and a
// mixed triangle/quad/pentagon torus, made by tests/kernel/shapes.h's `mixed_torus_from`),
// and the allocation counter used to report bytes per output face.
#pragma once

#include <cstddef>
#include <cstdint>

#include "kernel/mesh.h"

namespace nomec::kernel::bench {

/// An n x m quad torus (n*m faces).
PolygonSoup torus_soup(int n, int m);

/// An n x m torus where every third row is split into triangles and every third row has
/// pairs of quads turned into pentagons (by a vertex on their shared edge).
PolygonSoup mixed_torus_soup(int n, int m);

/// Heap bytes currently allocated through operator new, and the peak since the last
/// `reset_peak_bytes()`.
size_t current_bytes();
size_t peak_bytes();
void reset_peak_bytes();

}  // namespace nomec::kernel::bench
