// Generators for the evaluator (see context.h): the generator of a node run once with its
// arguments evaluated (numbers, flags, functions, points — a controlpoint counts as its
// point), and paths as point sequences. Sweeps are in sweeps.cpp.
#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include "backend/eval/context.h"

namespace nomec::backend::eval {

namespace {

// A function argument as something the generator can evaluate at its variables' values.
ScalarFunction function_of(Context& c, const ir::Operand& o) {
  if (o.exprs.empty()) return {};
  // The parameters it reads count as read by the generator.
  const ir::ExprId e = c.m.refs(o.exprs)[0];
  c.cache.recorder.note(Deps{c.cache.params_of(c.m, e), false});
  const ir::Module* m = &c.m;
  return [m, e](std::span<const double> vars, std::string* problem) -> std::optional<double> {
    ir::EvalResult r = ir::evaluate(*m, e, vars);
    if (r.ok) return r.value;
    if (problem != nullptr) *problem = r.problem.empty() ? "the function could not be checked" : r.problem;
    return std::nullopt;
  };
}

// The evaluated arguments of generator node `gen_id`.
GeneratorInput input_of(Context& c, ir::NodeId gen_id, std::string_view inst_path) {
  const ir::GeneratorData& g = c.m.get<ir::GeneratorData>(gen_id);
  const ir::GeneratorInfo& info = ir::generator(g.gen);
  GeneratorInput in = GeneratorInput::for_kind(g.gen, c.m.dialect);
  for (const ir::GenArgBinding& b : c.m.refs(g.args)) {
    if (b.arg == ir::kNoArg) continue;
    switch (info.args[b.arg].type) {
      case ir::ArgType::Function:
        if (b.value.is_valid()) in.functions[b.arg] = function_of(c, c.m.operand(b.value));
        break;
      case ir::ArgType::Points:
        for (ir::NodeId p : c.m.refs(b.refs)) {
          if (!p.is_valid()) continue;
          std::optional<glm::dvec3> at = point_position(c, p);  // a point or a controlpoint
          if (!at) continue;
          in.points.push_back(*at);
          in.point_names.push_back(short_name(c.m.node(p).name));
        }
        break;
      case ir::ArgType::Path:
        if (b.ref.is_valid()) {
          PathPoints path = path_points(c, b.ref, inst_path);
          in.points = std::move(path.points);
          in.point_names = std::move(path.names);
          in.is_path_closed = path.is_closed;
        }
        break;
      case ir::ArgType::Flag:
        in.flags[b.arg] = 1;
        if (b.value.is_valid()) in.numbers[b.arg] = scalar(c, b.value, 0, 0);
        break;
      default:
        if (b.value.is_valid()) in.numbers[b.arg] = scalar(c, b.value, 0, 0);
        // A NOME 2016 / NOME2 count written as a number: `stoi` truncated it.
        if (b.is_truncated && in.numbers[b.arg]) in.numbers[b.arg] = std::trunc(*in.numbers[b.arg]);
        break;
    }
  }
  return in;
}

// Runs the generator of node `gen_id` (uncached; see `generated`).
std::optional<Generated> generate_node(Context& c, ir::NodeId gen_id, std::string_view inst_path) {
  const ir::Node& g = c.m.node(gen_id);
  GeneratorResult r = generate(input_of(c, gen_id, inst_path));
  ++c.counters.generators_run;
  c.counters.nodes.insert(gen_id.index);
  if (r.ok()) return std::move(r.value);
  SourceRange at = g.range;
  if (r.error.arg != ir::kNoArg) {
    if (const ir::GenArgBinding* b = c.m.gen_arg(gen_id, r.error.arg); b != nullptr && b->range.is_valid()) at = b->range;
  }
  auto d = c.diags().emit(DiagKind::GeometryFailed, at,
                          fmt::format("`{}` `{}`: {}{}", g.keyword, short_name(g.name), r.error.message,
                                      inst_path.empty() ? "" : fmt::format(" (in instance `{}`)", inst_path)));
  if (!r.error.hint.empty()) d.note(SourceRange{}, r.error.hint);
  return std::nullopt;
}

}  // namespace

const Generated* generated(Context& c, ir::NodeId gen_id, std::string_view inst_path) {
  if (auto it = c.cache.generated.find(gen_id.index); it != c.cache.generated.end()) {
    c.cache.recorder.note(it->second.deps);
    return it->second.value ? &*it->second.value : nullptr;
  }
  c.cache.recorder.open();
  std::optional<Generated> made = generate_node(c, gen_id, inst_path);
  Deps d = c.cache.recorder.close();
  auto [it, _] = c.cache.generated.emplace(gen_id.index, Memo<std::optional<Generated>>{std::move(made), std::move(d)});
  return it->second.value ? &*it->second.value : nullptr;
}

bool flag_set(Context& c, const ir::FlagArg& f) {
  return f.is_present && (!f.value.is_valid() || scalar(c, f.value, 0, 0) != 0);
}

PathPoints path_points(Context& c, ir::NodeId path_id, std::string_view inst_path) {
  PathPoints out;
  const ir::Node& pn = c.m.node(path_id);
  if (pn.kind == ir::NodeKind::Polyline) {
    const ir::PolylineData& p = pn.as<ir::PolylineData>();
    for (const ir::VertexRef& r : c.m.refs(p.points)) {
      if (auto pos = ref_position(c, r, inst_path)) {
        out.points.push_back(*pos);
        out.names.push_back(r.text);
      }
    }
    // SLIDE `pointlist ( p … )`: points or controlpoints by name.
    for (ir::NodeId id : c.m.refs(p.point_list)) {
      ir::NodeId point = id;
      if (id.is_valid() && c.m.node(id).kind == ir::NodeKind::ControlPoint) point = c.m.get<ir::ControlPointData>(id).point;
      if (!point.is_valid() || c.m.node(point).kind != ir::NodeKind::Point) continue;
      if (auto pos = point_position(c, point)) {
        out.points.push_back(*pos);
        out.names.push_back(c.m.node(point).name);
      }
    }
    out.is_closed = flag_set(c, p.closed);
  } else if (pn.kind == ir::NodeKind::CrossSection) {
    // SLIDE: a sweep's cross section names a top-level one, which names its curve or is a
    // circle or a star in the xy plane (defaults: docs/dialects.md).
    // Follow cross sections that name another one (at most a few: a cycle is no curve).
    ir::NodeId at = path_id;
    for (int hops = 0; hops < 8; ++hops) {
      const ir::CrossSectionData& y = c.m.get<ir::CrossSectionData>(at);
      if (!y.curve.is_valid() || y.curve == at) break;
      if (c.m.node(y.curve).kind != ir::NodeKind::CrossSection) return path_points(c, y.curve, inst_path);
      at = y.curve;
    }
    const ir::CrossSectionData& x = c.m.get<ir::CrossSectionData>(at);
    if (x.is_circle || x.is_star) {
      const double r = x.radius.is_valid() ? scalar(c, x.radius, 0, 0) : 1.0;
      const double inner = x.inner_radius.is_valid() ? scalar(c, x.inner_radius, 0, 0) : r / 2;
      const int n = std::clamp(static_cast<int>(x.slices.is_valid() ? scalar(c, x.slices, 0, 0) : (x.is_star ? 5 : 16)), 3, 10000);
      const int count = x.is_star ? 2 * n : n;
      for (int k = 0; k < count; ++k) {
        const double t = 2 * M_PI * k / count;
        const double rr = x.is_star && k % 2 == 1 ? inner : r;
        out.points.emplace_back(rr * std::cos(t), rr * std::sin(t), 0.0);
        out.names.emplace_back();
      }
      out.is_closed = true;
    }
  } else if (pn.kind == ir::NodeKind::Generator) {
    if (const Generated* g = generated(c, path_id, inst_path); g && !g->curves.empty()) {
      for (int32_t v : g->curves[0].vertices) {
        out.points.push_back(g->soup.positions[v]);
        out.names.push_back(g->soup.names.empty() ? std::string() : g->soup.names[v]);
      }
      out.is_closed = g->curves[0].is_closed;
    }
  }
  return out;
}

}  // namespace nomec::backend::eval
