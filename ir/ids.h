// The IR's typed IDs (expressions, nodes, operands) and `Slice<T>`, a run of one of the
// module's shared arrays (vertex references, node lists, transforms …).
#pragma once

#include <cstdint>

#include "base/id.h"

namespace nomec::ir {

struct ExprTag;
struct NodeTag;
struct OperandTag;
using ExprId = Id<ExprTag>;
using NodeId = Id<NodeTag>;
using OperandId = Id<OperandTag>;

/// Elements [begin, begin + size) of the module's array of T (see `Module::refs`).
template <typename T>
struct Slice {
  uint32_t begin = 0;
  uint32_t size = 0;
  bool empty() const { return size == 0; }
};

}  // namespace nomec::ir
