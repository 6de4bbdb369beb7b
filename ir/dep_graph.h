// The dependency graph of a module: an edge A -> B means B must be re-evaluated when A
// changes (parameter -> value -> point -> face -> mesh -> instance -> group …). Data, not
// callbacks: edges in one array while the checker builds it, compressed adjacency after.
#pragma once

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "ir/ids.h"

namespace nomec::ir {

/// The dependency graph: an edge A -> B means B must be re-evaluated when A changes
/// (parameter -> value -> point -> face -> mesh -> instance -> group …).
class DepGraph {
 public:
  /// Makes room for nodes 0..n-1 (the graph only grows).
  void resize(size_t n) {
    // Called for every node added, one at a time: a push_back each, rather than resize's
    // out-of-line fill.
    while (last_to_.size() < n) last_to_.push_back(-1);
  }
  void reserve(size_t n) { last_to_.reserve(n); }
  void add_edge(NodeId from, NodeId to);
  /// Sorts every adjacency list and removes duplicate edges; call once after building, and
  /// before sharing the graph between threads (the queries below build their arrays lazily).
  void finalize();
  std::span<const NodeId> users(NodeId n) const {
    compact();
    return {items_.data() + begin_[n.index], items_.data() + begin_[n.index + 1]};
  }
  size_t node_count() const { return last_to_.size(); }
  size_t edge_count() const {
    compact();
    return items_.size();
  }
  /// Kahn's topological order; nodes on cycles are returned in `cycle_nodes` instead.
  std::vector<NodeId> topo_order(std::vector<NodeId>* cycle_nodes = nullptr) const;
  /// Every node reachable from `start` (excluding `start`), in topological order.
  std::vector<NodeId> affected_by(NodeId start) const;

 private:
  // Rationale: edges are appended to one array while the checker builds the graph (no
  // allocation per node: a large scene has tens of thousands), and turned into compressed
  // adjacency arrays (CSR: users of n are items_[begin_[n] .. begin_[n+1]]) on first query.
  // `finalize` also sorts each list and removes duplicates (O(E log E)), so counts in
  // `--emit deps` and re-evaluation counts are exact without a search per insertion.
  void compact() const;
  std::vector<std::pair<int32_t, int32_t>> edges_;  // (from, to) in insertion order
  std::vector<int32_t> last_to_;                    // per node: the last `to` added from it
  bool sorted_ = false;                             // finalize() was called
  mutable bool stale_ = true;                       // begin_/items_ lag behind edges_
  mutable std::vector<uint32_t> begin_;
  mutable std::vector<NodeId> items_;
};

}  // namespace nomec::ir
