// The finished dependency graph (see handlers.h): finalized once every statement is checked,
// and a cycle in it (a slider that depends on itself through `{expr}` values, an instance of
// a group that contains it …) reported once, in dependency order.
#include <algorithm>
#include <fmt/format.h>
#include <map>
#include <set>

#include "frontend/check/handlers.h"

namespace nomec::check {

namespace {

// One cycle of the graph, following its edges from a node that reaches itself, so the
// message reads in dependency order: `a` → `a.b` → `b` → `b.a` → `a`.
std::vector<ir::NodeId> find_cycle(const ir::Module& m, const std::vector<ir::NodeId>& cycle_nodes) {
  std::set<int32_t> in_cycle;
  for (ir::NodeId n : cycle_nodes) in_cycle.insert(n.index);
  // Kahn leaves nodes downstream of a cycle too; find a node that reaches itself.
  for (ir::NodeId start : cycle_nodes) {
    std::vector<ir::NodeId> stack{start};
    std::map<int32_t, int32_t> parent;
    while (!stack.empty()) {
      ir::NodeId n = stack.back();
      stack.pop_back();
      for (ir::NodeId to : m.deps.users(n)) {
        if (!in_cycle.contains(to.index)) continue;
        if (to == start) {
          std::vector<ir::NodeId> path;
          for (ir::NodeId p = n;; p = ir::NodeId(parent[p.index])) {
            path.push_back(p);
            if (p == start) break;
          }
          std::reverse(path.begin(), path.end());
          return path;
        }
        if (!parent.contains(to.index)) {
          parent[to.index] = n.index;
          stack.push_back(to);
        }
      }
    }
  }
  return {};
}

void report_cycle(Context& c, const std::vector<ir::NodeId>& cycle_nodes) {
  const ir::Module& m = c.module();
  std::vector<ir::NodeId> path = find_cycle(m, cycle_nodes);
  if (path.empty()) return;
  std::vector<std::string> names;
  for (ir::NodeId n : path) {
    if (m.node(n).kind != ir::NodeKind::Value) names.push_back(fmt::format("`{}`", m.node(n).name));
  }
  names.push_back(names.front());
  auto d = c.diags().emit(DiagKind::DependencyCycle, m.node(path.front()).range,
                          fmt::format("these definitions depend on each other in a cycle: {}", fmt::join(names, " → ")));
  for (size_t i = 1; i < path.size(); ++i) {
    const ir::Node& n = m.node(path[i]);
    if (n.kind != ir::NodeKind::Value) d.note(n.range, fmt::format("`{}` is part of the cycle", n.name));
  }
}

}  // namespace

void finish_dependencies(Context& c) {
  check_pending_lists(c);
  c.module().deps.finalize();
  std::vector<ir::NodeId> cycle;
  c.module().deps.topo_order(&cycle);
  if (!cycle.empty()) report_cycle(c, cycle);
}

}  // namespace nomec::check
