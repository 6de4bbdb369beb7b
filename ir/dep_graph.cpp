// Dependency graph algorithms (see dep_graph.h): edge collection, compressed adjacency,
// topological order, reachability.
#include "ir/dep_graph.h"

#include <algorithm>

namespace nomec::ir {

void DepGraph::add_edge(NodeId from, NodeId to) {
  if (!from.is_valid() || !to.is_valid() || from == to) {
    return;
  }
  resize(static_cast<size_t>(std::max(from.index, to.index)) + 1);
  // Duplicates are removed in `finalize`; skipping the common repeat here keeps lists short.
  if (last_to_[from.index] == to.index) {
    return;
  }
  last_to_[from.index] = to.index;
  edges_.emplace_back(from.index, to.index);
  stale_ = true;
}

void DepGraph::finalize() {
  sorted_ = true;
  stale_ = true;
  compact();
}

void DepGraph::compact() const {
  if (!stale_) {
    return;
  }
  const size_t n = last_to_.size();
  begin_.assign(n + 1, 0);
  for (const auto& [from, to] : edges_) {
    ++begin_[static_cast<size_t>(from) + 1];
  }
  for (size_t i = 0; i < n; ++i) {
    begin_[i + 1] += begin_[i];
  }
  items_.assign(edges_.size(), NodeId{});
  std::vector<uint32_t> fill(begin_.begin(), begin_.end() - 1);
  for (const auto& [from, to] : edges_) {  // stable: each list keeps insertion order
    items_[fill[from]++] = NodeId{to};
  }
  if (sorted_) {
    // Sort and deduplicate each list, then close the gaps left by removed duplicates.
    uint32_t out = 0;
    for (size_t i = 0; i < n; ++i) {
      auto first = items_.begin() + begin_[i];
      auto last = items_.begin() + begin_[i + 1];
      // Most nodes have one or two users: those need no call to sort.
      if (last - first == 2) {
        if (first[1].index < first[0].index) std::swap(first[0], first[1]);
        if (first[1] == first[0]) last = first + 1;
      } else if (last - first > 2) {
        std::sort(first, last, [](NodeId a, NodeId b) { return a.index < b.index; });
        last = std::unique(first, last);
      }
      begin_[i] = out;
      if (items_.begin() + out == first) {
        out += static_cast<uint32_t>(last - first);
      } else {
        out = static_cast<uint32_t>(std::move(first, last, items_.begin() + out) - items_.begin());
      }
    }
    begin_[n] = out;
    items_.resize(out);
  }
  stale_ = false;
}

std::vector<NodeId> DepGraph::topo_order(std::vector<NodeId>* cycle_nodes) const {
  compact();
  const size_t count = node_count();
  std::vector<int> indegree(count, 0);
  for (NodeId to : items_) {
    ++indegree[to.index];
  }
  std::vector<NodeId> order;
  order.reserve(count);
  std::vector<NodeId> ready;
  for (size_t i = count; i-- > 0;) {
    if (indegree[i] == 0) {
      ready.push_back(NodeId{static_cast<int32_t>(i)});
    }
  }
  while (!ready.empty()) {
    NodeId n = ready.back();
    ready.pop_back();
    order.push_back(n);
    for (NodeId to : users(n)) {
      if (--indegree[to.index] == 0) {
        ready.push_back(to);
      }
    }
  }
  if (cycle_nodes != nullptr) {
    cycle_nodes->clear();
    for (size_t i = 0; i < count; ++i) {
      if (indegree[i] > 0) {
        cycle_nodes->push_back(NodeId{static_cast<int32_t>(i)});
      }
    }
  }
  return order;
}

std::vector<NodeId> DepGraph::affected_by(NodeId start) const {
  std::vector<char> seen(node_count(), 0);
  std::vector<NodeId> stack{start};
  seen[start.index] = 1;
  while (!stack.empty()) {
    NodeId n = stack.back();
    stack.pop_back();
    for (NodeId to : users(n)) {
      if (!seen[to.index]) {
        seen[to.index] = 1;
        stack.push_back(to);
      }
    }
  }
  seen[start.index] = 0;
  std::vector<NodeId> out;
  for (NodeId n : topo_order()) {
    if (seen[n.index]) {
      out.push_back(n);
    }
  }
  return out;
}

}  // namespace nomec::ir
