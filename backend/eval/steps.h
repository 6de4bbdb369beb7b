// The steps a pipeline block (or the command line's whole-scene pipeline) runs on a merged
// mesh: Catmull-Clark levels, an offset slab or a lattice; and running them per connected
// component, reusing components whose input did not change (docs/incremental.md).
#pragma once

#include <cstdint>
#include <variant>
#include <vector>

#include "kernel/mesh.h"
#include "kernel/merge.h"
#include "kernel/offset.h"
#include "kernel/subdivide.h"

namespace nomec::backend::eval {

/// One step applied to a merged mesh.
struct Step {
  enum class Kind : uint8_t { Subdivide, Offset, Lattice };
  Kind kind = Kind::Subdivide;
  kernel::SubdivisionOptions subdivision;
  double height = 0;
  double width = 0;
  friend bool operator==(const Step& a, const Step& b) {
    return a.kind == b.kind && a.height == b.height && a.width == b.width &&
           a.subdivision.levels == b.subdivision.levels && a.subdivision.vertex_rule == b.subdivision.vertex_rule &&
           a.subdivision.is_sharpness_honoured == b.subdivision.is_sharpness_honoured;
  }
};

/// A failed step: the kernel's error and which step it was.
struct StepFailure {
  kernel::KernelError error;
  size_t step = 0;
};

/// Runs `steps` in order on `mesh`; counts one kernel operation per step run. A
/// subdivision that would make more than `max_vertices` vertices (0: no limit) fails.
std::variant<kernel::Mesh, StepFailure> run_steps(kernel::Mesh mesh, const std::vector<Step>& steps, int32_t& kernel_ops,
                                                  int64_t max_vertices = 0);

/// The results of running steps on the connected components of one block's merged mesh,
/// kept for the next evaluation of the block.
struct ComponentMemo {
  struct Entry {
    uint64_t hash = 0;
    kernel::PolygonSoup input;
    std::vector<Step> steps;
    kernel::Mesh output;
  };
  std::vector<Entry> entries;
};

/// Runs `steps` on each connected component of `mesh` separately, reusing the result of a
/// component whose input soup and steps equal an entry of `pool` (which is moved out), and
/// concatenates the results in component order; every component used is appended to
/// `next`. Falls back to the whole mesh (so errors are exactly those of a one-shot run)
/// when a component fails or the mesh has vertices no face uses.
std::variant<kernel::Mesh, StepFailure> run_steps_by_component(const kernel::Mesh& mesh, const std::vector<Step>& steps,
                                                               ComponentMemo& pool, ComponentMemo& next,
                                                               int32_t& kernel_ops, int64_t max_vertices = 0);

/// Merges `mesh` with `tol`; a negative tolerance means 1e-4 × the bounding-box diagonal.
kernel::Result<kernel::MergeResult> merge_mesh(const kernel::Mesh& mesh, double tol);

}  // namespace nomec::backend::eval
