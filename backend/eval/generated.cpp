// Generators and sweeps for the evaluator (see context.h): the generator of a node run once
// with its arguments evaluated (numbers, flags, functions, points), paths as point
// sequences, and sweeps (NOME3 semantics): the cross section, a curve in its xy plane, is
// carried along the path by rotation-minimising frames (parallel transport of the normal;
// for a closed path the holonomy is spread evenly so the tube closes), turned by `azimuth`
// at the start and by `twist` degrees in total along the path. Quads join consecutive
// rings; a closed cross section on an open path gets `begincap` / `endcap` faces; `reverse`
// flips faces.
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
  c.cache.recorder.note(Deps{c.cache.params_of(c.m, o.exprs[0]), false});
  const ir::Module* m = &c.m;
  const ir::ExprId e = o.exprs[0];
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
          if (!p.is_valid() || c.m.node(p).kind != ir::NodeKind::Point) continue;
          in.points.push_back(vec3(c, c.m.get<ir::PointData>(p).position));
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

// A sweep's inputs, read from its own options and its path and cross-section parts.
struct SweepInput {
  PathPoints cs, path;
  double azimuth = 0, twist = 0;
  bool begin_cap = false, end_cap = false, reverse = false;
  SourceRange cs_range, path_range;
};

bool flag_set(Context& c, const ir::FlagArg& f) {
  return f.is_present && (!f.value.is_valid() || scalar(c, f.value, 0, 0) != 0);
}

SweepInput sweep_input(Context& c, ir::NodeId sweep_id, std::string_view inst_path) {
  const ir::Node& sn = c.m.node(sweep_id);
  SweepInput in;
  in.cs_range = in.path_range = sn.range;
  const ir::SweepData& sd = sn.as<ir::SweepData>();
  if (sd.azimuth.is_valid()) in.azimuth = scalar(c, sd.azimuth, 0, 0);
  if (sd.twist.is_valid()) in.twist = scalar(c, sd.twist, 0, 0);
  for (ir::NodeId k : sn.children) {
    const ir::Node& kn = c.m.node(k);
    if (kn.kind == ir::NodeKind::SweepPath) {
      const ir::SweepPathData& p = kn.as<ir::SweepPathData>();
      if (p.curve.is_valid()) {
        in.path = path_points(c, p.curve, inst_path);
        in.path_range = p.curve_range;
      }
      if (p.azimuth.is_valid()) in.azimuth = scalar(c, p.azimuth, 0, 0);
      if (p.twist.is_valid()) in.twist = scalar(c, p.twist, 0, 0);
    } else if (kn.kind == ir::NodeKind::CrossSection) {
      const ir::CrossSectionData& x = kn.as<ir::CrossSectionData>();
      if (x.curve.is_valid()) {
        in.cs = path_points(c, x.curve, inst_path);
        in.cs_range = x.curve_range;
      }
      if (x.begin_cap.is_present) in.begin_cap = flag_set(c, x.begin_cap);
      if (x.end_cap.is_present) in.end_cap = flag_set(c, x.end_cap);
      in.reverse = in.reverse || x.reverse;
    }
  }
  return in;
}

std::optional<kernel::PolygonSoup> sweep_node(Context& c, ir::NodeId sweep_id, std::string_view inst_path) {
  SweepInput in = sweep_input(c, sweep_id, inst_path);
  const std::string name = short_name(c.m.node(sweep_id).name);
  const bool cs_closed = in.cs.is_closed;
  const bool path_closed = in.path.is_closed;
  const size_t nc = in.cs.points.size(), np = in.path.points.size();
  if (nc < 2 || (cs_closed && nc < 3)) {
    c.diags().emit(DiagKind::GeometryFailed, in.cs_range,
                   fmt::format("sweep `{}` needs a cross section of at least {} points, got {} (instance `{}`)", name,
                               cs_closed ? 3 : 2, nc, inst_path));
    return std::nullopt;
  }
  if (np < 2 || (path_closed && np < 3)) {
    c.diags().emit(DiagKind::GeometryFailed, in.path_range,
                   fmt::format("sweep `{}` needs a path of at least {} points, got {} (instance `{}`)", name,
                               path_closed ? 3 : 2, np, inst_path));
    return std::nullopt;
  }
  const auto& P = in.path.points;
  std::vector<glm::dvec3> tangent(np);
  for (size_t i = 0; i < np; ++i) {
    glm::dvec3 prev = i > 0 ? P[i - 1] : (path_closed ? P[np - 1] : P[i]);
    glm::dvec3 next = i + 1 < np ? P[i + 1] : (path_closed ? P[0] : P[i]);
    glm::dvec3 d = next - prev;
    if (glm::length(d) == 0) {
      c.diags().emit(DiagKind::GeometryFailed, in.path_range,
                  fmt::format("sweep `{}`: the path has repeated points (instance `{}`)",
                              short_name(c.m.node(sweep_id).name), inst_path));
      return std::nullopt;
    }
    tangent[i] = glm::normalize(d);
  }
  auto perpendicular = [](const glm::dvec3& t, glm::dvec3 v) {
    return v - glm::dot(v, t) * t;
  };
  glm::dvec3 n0 = std::fabs(tangent[0].z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
  n0 = glm::normalize(perpendicular(tangent[0], n0));
  n0 = glm::dvec3(glm::rotate(glm::dmat4(1.0), glm::radians(in.azimuth), tangent[0]) * glm::dvec4(n0, 0));
  std::vector<glm::dvec3> normal(np);
  normal[0] = n0;
  for (size_t i = 1; i < np; ++i) {
    glm::dvec3 n = perpendicular(tangent[i], normal[i - 1]);
    normal[i] = glm::length(n) > 1e-12 ? glm::normalize(n) : normal[i - 1];
  }
  double holonomy = 0;  // angle from the transported normal back to n0, closed paths
  if (path_closed) {
    glm::dvec3 back = glm::normalize(perpendicular(tangent[0], normal[np - 1]));
    holonomy = std::atan2(glm::dot(glm::cross(back, n0), tangent[0]), glm::dot(back, n0));
  }
  kernel::PolygonSoup out;
  const size_t rings = np;
  const double steps = path_closed ? static_cast<double>(np) : static_cast<double>(np - 1);
  for (size_t i = 0; i < rings; ++i) {
    double frac = static_cast<double>(i) / steps;
    double angle = glm::radians(in.twist) * frac + holonomy * frac;
    glm::dvec3 n = glm::dvec3(glm::rotate(glm::dmat4(1.0), angle, tangent[i]) * glm::dvec4(normal[i], 0));
    glm::dvec3 b = glm::cross(tangent[i], n);
    for (size_t j = 0; j < nc; ++j) {
      out.add_vertex(P[i] + in.cs.points[j].x * n + in.cs.points[j].y * b);
    }
  }
  auto vid = [&](size_t i, size_t j) { return static_cast<int32_t>((i % rings) * nc + (j % nc)); };
  auto add = [&](std::vector<int32_t> f) {
    if (in.reverse) std::reverse(f.begin(), f.end());
    out.add_face(f);
  };
  const size_t ring_edges = path_closed ? rings : rings - 1;
  const size_t cs_edges = cs_closed ? nc : nc - 1;
  for (size_t i = 0; i < ring_edges; ++i) {
    for (size_t j = 0; j < cs_edges; ++j) {
      // Outward for a cross section running counter-clockwise in its xy plane.
      add({vid(i, j), vid(i, j + 1), vid(i + 1, j + 1), vid(i + 1, j)});
    }
  }
  if (cs_closed && !path_closed) {
    if (in.begin_cap) {
      std::vector<int32_t> f;
      for (size_t j = nc; j-- > 0;) f.push_back(vid(0, j));
      add(f);
    }
    if (in.end_cap) {
      std::vector<int32_t> f;
      for (size_t j = 0; j < nc; ++j) f.push_back(vid(rings - 1, j));
      add(f);
    }
  }
  return out;
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
    out.is_closed = flag_set(c, p.closed);
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

std::optional<kernel::PolygonSoup> sweep(Context& c, ir::NodeId sweep_id, std::string_view inst_path) {
  std::string key = fmt::format("{}:{}", sweep_id.index, inst_path);
  if (auto it = c.cache.sweeps.find(key); it != c.cache.sweeps.end()) {
    c.cache.recorder.note(it->second.deps);
    return it->second.value;
  }
  c.cache.recorder.open();
  std::optional<kernel::PolygonSoup> made = sweep_node(c, sweep_id, inst_path);
  ++c.counters.generators_run;
  c.counters.nodes.insert(sweep_id.index);
  Deps d = c.cache.recorder.close();
  c.cache.sweeps.emplace(std::move(key), Memo<std::optional<kernel::PolygonSoup>>{made, std::move(d)});
  return made;
}

}  // namespace nomec::backend::eval
