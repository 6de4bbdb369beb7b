// The evaluator's cache (see eval_cache.h): dependency frames and invalidation.
#include "backend/eval/eval_cache.h"

#include <algorithm>

namespace nomec::backend::eval {

void DepsRecorder::open() { frames_.push_back({{}, diags_->diagnostics().size(), false}); }

Deps DepsRecorder::close() {
  Frame f = std::move(frames_.back());
  frames_.pop_back();
  std::sort(f.params.begin(), f.params.end());
  f.params.erase(std::unique(f.params.begin(), f.params.end()), f.params.end());
  Deps d{std::move(f.params), f.is_tainted || diags_->diagnostics().size() != f.diag_mark};
  note(d);
  return d;
}

void DepsRecorder::note(const Deps& d) {
  if (frames_.empty()) return;
  Frame& f = frames_.back();
  f.params.insert(f.params.end(), d.params.begin(), d.params.end());
  f.is_tainted = f.is_tainted || d.is_tainted;
}

void EvalCache::invalidate(int32_t param) {
  auto stale = [param](const Deps& d) {
    return d.is_tainted || std::binary_search(d.params.begin(), d.params.end(), param);
  };
  auto drop = [&](auto& map) { std::erase_if(map, [&](const auto& kv) { return stale(kv.second.deps); }); };
  drop(exprs);
  drop(generated);
  drop(sweeps);
  drop(world);
  drop(placements);
  drop(blocks);
  drop(borders);
  drop(entries);
  drop(zippers);
  drop(plans);
}

const std::vector<int32_t>& EvalCache::params_of(const ir::Module& m, ir::ExprId id) {
  if (auto it = expr_params.find(id.index); it != expr_params.end()) return it->second;
  std::vector<int32_t> ps;
  std::vector<ir::ExprId> todo{id};
  while (!todo.empty()) {
    ir::ExprId e = todo.back();
    todo.pop_back();
    if (!e.is_valid()) continue;
    const ir::Expr& x = m.expr(e);
    if (x.kind == ir::ExprKind::Param && x.param.is_valid()) ps.push_back(x.param.index);
    const std::span<const ir::ExprId> subs = m.subexprs(x);
    todo.insert(todo.end(), subs.begin(), subs.end());
  }
  std::sort(ps.begin(), ps.end());
  ps.erase(std::unique(ps.begin(), ps.end()), ps.end());
  return expr_params.emplace(id.index, std::move(ps)).first->second;
}

}  // namespace nomec::backend::eval
