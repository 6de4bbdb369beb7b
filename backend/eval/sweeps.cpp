// Sweeps for the evaluator (see context.h). A sweep carries a cross section, a curve in its
// xy plane, along a path. In NOME3 files (and nome files) the rings' frames are NOME3's
// (generators-original.md §12, docs/generators.md "Sweeps"): the default frame N = T × x̂
// at path ends and collinear points, mitred joints (T = u_out + u_in, N = u_out − u_in, the
// N coordinate scaled by 1/cos(θ/2)), `mintorsion` carrying the last ring's frame back by
// parallel transport, `azimuth` and `twist` turning the rings; a closed path's closing ring
// is welded to the first when they coincide. SLIDE sweeps keep rotation-minimising frames.
// Quads join consecutive rings; a closed cross section on an open path gets `begincap` /
// `endcap` faces; `reverse` flips faces. The NOME3 controlpoints among the path's points
// (compat.md E2, F3) scale (`scale (x y _)`) and turn (`rotate (_ _ z)`) the cross section at
// their ring (a plain point has scale 1 and no turn; a curve's rings between its listed
// points interpolate linearly). A JIPCAD `sweepmorph` takes its cross section from those
// controlpoints too (`crosssection C`, NOME3 `cross C`): each ring's is interpolated point
// by point between the cross-sections of the controlpoints before and after it (F4). A
// `morphvisualizer` shows one of those rings as a line strip. Sweep vertices are named as
// NOME3 named them, `v{k}_{i}` for ring k (from 1) and cross-section point i; NOME3 repeats
// a closed cross-section's first point and a closed path's first ring, nomec welds both and
// resolves those repeated names to the welded vertices (`sweep_vertex`).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include "backend/eval/context.h"

namespace nomec::backend::eval {

namespace {

// A point the path lists: where it sits (fraction of the path, 0 … 1) and, for a
// controlpoint, what it carries for the sweep (a plain point has scale 1 and no turn).
struct Key {
  double t = 0;
  ir::NodeId node;
  glm::dvec2 scale{1.0, 1.0};
  double angle = 0;  // degrees, in the cross section's plane
  std::optional<PathPoints> section;
};

// The points a path lists (a polyline's, or a curve generator's control points), in order,
// with what their controlpoints carry.
std::vector<Key> path_keys(Context& c, ir::NodeId curve, std::string_view inst_path) {
  std::vector<ir::NodeId> listed;
  bool closed = false;
  const ir::Node& pn = c.m.node(curve);
  if (pn.kind == ir::NodeKind::Polyline) {
    for (const ir::VertexRef& r : c.m.refs(pn.as<ir::PolylineData>().points)) listed.push_back(r.point);
    closed = flag_set(c, pn.as<ir::PolylineData>().closed);
  } else if (pn.kind == ir::NodeKind::Generator) {
    for (const ir::GenArgBinding& b : c.m.refs(pn.as<ir::GeneratorData>().args)) {
      for (ir::NodeId p : c.m.refs(b.refs)) listed.push_back(p);
    }
  }
  std::vector<Key> keys;
  const double span = closed ? static_cast<double>(listed.size()) : static_cast<double>(listed.size()) - 1;
  for (size_t k = 0; k < listed.size(); ++k) {
    if (!listed[k].is_valid()) continue;
    Key key;
    key.t = span > 0 ? static_cast<double>(k) / span : 0.0;
    key.node = listed[k];
    if (c.m.node(listed[k]).kind != ir::NodeKind::ControlPoint) {
      keys.push_back(std::move(key));  // a plain point: scale 1, no turn (NOME3's defaults)
      continue;
    }
    const ir::ControlPointData& d = c.m.get<ir::ControlPointData>(listed[k]);
    if (d.scale.is_valid()) key.scale = {scalar(c, d.scale, 0, 1), scalar(c, d.scale, 1, 1)};
    if (d.rotate.is_valid()) {
      // `rotate (x y z)`: the z angle turns the cross section in its plane; with an angle
      // list, `rotate (0 0 1) (deg)`, the angle about the z axis.
      const size_t n = c.m.operand(d.rotate).exprs.size;
      key.angle = n >= 4 ? scalar(c, d.rotate, 3, 0) * (scalar(c, d.rotate, 2, 0) < 0 ? -1.0 : 1.0)
                         : scalar(c, d.rotate, 2, 0);
    }
    if (d.cross_section.is_valid()) key.section = path_points(c, d.cross_section, inst_path);
    keys.push_back(std::move(key));
  }
  return keys;
}

// The two keys around fraction `t` and the weight of the second (clamped at the ends).
std::pair<const Key*, std::pair<const Key*, double>> around(const std::vector<const Key*>& keys, double t) {
  if (t <= keys.front()->t) return {keys.front(), {keys.front(), 0.0}};
  for (size_t k = 0; k + 1 < keys.size(); ++k) {
    if (t <= keys[k + 1]->t) {
      const double w = keys[k + 1]->t > keys[k]->t ? (t - keys[k]->t) / (keys[k + 1]->t - keys[k]->t) : 1.0;
      return {keys[k], {keys[k + 1], w}};
    }
  }
  return {keys.back(), {keys.back(), 0.0}};
}

// One ring's frame: the path point, the directions the cross section's x and y map to, the
// factor on the x (N) coordinate at a mitred joint, and the ring's turn in radians
// (azimuth, twist and, with `mintorsion`, the torsion correction), applied before the
// miter scale.
struct Frame {
  glm::dvec3 origin, n, b;
  double miter = 1.0, angle = 0.0;
  glm::dvec3 t{0, 0, 1};
};

glm::dvec3 place(const Frame& f, const glm::dvec3& p) {
  const double x = p.x * std::cos(f.angle) - p.y * std::sin(f.angle);
  const double y = p.x * std::sin(f.angle) + p.y * std::cos(f.angle);
  return f.origin + f.miter * x * f.n + y * f.b;
}

// What a sweep or sweepmorph is made of.
struct SweepInput {
  std::string_view keyword;
  std::string name;
  PathPoints path;
  std::vector<Key> keys;
  double azimuth = 0, twist = 0;
  bool mintorsion = false;
  bool begin_cap = false, end_cap = false, reverse = false;
  SourceRange cs_range, path_range;
  PathPoints cs;  // a sweep's one cross section
};

void read_path(Context& c, ir::NodeId path_node, std::string_view inst_path, SweepInput& in) {
  const ir::SweepPathData& p = c.m.get<ir::SweepPathData>(path_node);
  if (p.curve.is_valid()) {
    in.path = path_points(c, p.curve, inst_path);
    in.path_range = p.curve_range;
    in.keys = path_keys(c, p.curve, inst_path);
  }
  if (p.azimuth.is_valid()) in.azimuth = scalar(c, p.azimuth, 0, 0);
  if (p.twist.is_valid()) in.twist = scalar(c, p.twist, 0, 0);
  in.mintorsion = in.mintorsion || p.mintorsion;
}

SweepInput sweep_input(Context& c, ir::NodeId sweep_id, std::string_view inst_path) {
  const ir::Node& sn = c.m.node(sweep_id);
  SweepInput in;
  in.keyword = sn.keyword;
  in.name = short_name(sn.name);
  in.cs_range = in.path_range = sn.range;
  if (sn.kind == ir::NodeKind::SweepMorph) {
    const ir::SweepMorphData& d = sn.as<ir::SweepMorphData>();
    in.begin_cap = d.begin_cap;
    in.end_cap = d.end_cap;
    in.reverse = d.reverse;
  } else {
    const ir::SweepData& sd = sn.as<ir::SweepData>();
    if (sd.azimuth.is_valid()) in.azimuth = scalar(c, sd.azimuth, 0, 0);
    if (sd.twist.is_valid()) in.twist = scalar(c, sd.twist, 0, 0);
    in.mintorsion = sd.mintorsion;
  }
  for (ir::NodeId k : c.m.children(sn)) {
    const ir::Node& kn = c.m.node(k);
    if (kn.kind == ir::NodeKind::SweepPath) {
      read_path(c, k, inst_path, in);
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

// SLIDE's frames (its sweep geometry is not established by the sources): rotation-
// minimising frames; nullopt after a reported error.
std::optional<std::vector<Frame>> slide_frames(Context& c, const SweepInput& in, std::string_view inst_path) {
  const bool closed = in.path.is_closed;
  const auto& P = in.path.points;
  const size_t np = P.size();
  if (np < 2 || (closed && np < 3)) {
    c.diags().emit(DiagKind::GeometryFailed, in.path_range,
                   fmt::format("{} `{}` needs a path of at least {} points, got {} (instance `{}`)", in.keyword, in.name,
                               closed ? 3 : 2, np, inst_path));
    return std::nullopt;
  }
  std::vector<glm::dvec3> tangent(np);
  for (size_t i = 0; i < np; ++i) {
    const glm::dvec3 prev = i > 0 ? P[i - 1] : (closed ? P[np - 1] : P[i]);
    const glm::dvec3 next = i + 1 < np ? P[i + 1] : (closed ? P[0] : P[i]);
    const glm::dvec3 d = next - prev;
    if (glm::length(d) == 0) {
      c.diags().emit(DiagKind::GeometryFailed, in.path_range,
                     fmt::format("{} `{}`: the path has repeated points (instance `{}`)", in.keyword, in.name, inst_path));
      return std::nullopt;
    }
    tangent[i] = glm::normalize(d);
  }
  auto perpendicular = [](const glm::dvec3& t, glm::dvec3 v) { return v - glm::dot(v, t) * t; };
  glm::dvec3 n0 = std::fabs(tangent[0].z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
  n0 = glm::normalize(perpendicular(tangent[0], n0));
  n0 = glm::dvec3(glm::rotate(glm::dmat4(1.0), glm::radians(in.azimuth), tangent[0]) * glm::dvec4(n0, 0));
  std::vector<glm::dvec3> normal(np);
  normal[0] = n0;
  for (size_t i = 1; i < np; ++i) {
    const glm::dvec3 n = perpendicular(tangent[i], normal[i - 1]);
    normal[i] = glm::length(n) > 1e-12 ? glm::normalize(n) : normal[i - 1];
  }
  double holonomy = 0;  // angle from the transported normal back to n0, closed paths
  if (closed) {
    const glm::dvec3 back = glm::normalize(perpendicular(tangent[0], normal[np - 1]));
    holonomy = std::atan2(glm::dot(glm::cross(back, n0), tangent[0]), glm::dot(back, n0));
  }
  std::vector<Frame> out(np);
  const double steps = closed ? static_cast<double>(np) : static_cast<double>(np - 1);
  for (size_t i = 0; i < np; ++i) {
    const double frac = static_cast<double>(i) / steps;
    const double angle = glm::radians(in.twist) * frac + holonomy * frac;
    const glm::dvec3 n = glm::dvec3(glm::rotate(glm::dmat4(1.0), angle, tangent[i]) * glm::dvec4(normal[i], 0));
    out[i] = {P[i], n, glm::cross(tangent[i], n), 1.0, 0.0, tangent[i]};
  }
  if (closed) out.push_back(out.front());  // the closing ring, welded to the first
  return out;
}

// NOME3's default frame (generators-original.md §12.2): N = T × x̂, or T × ŷ when T = ±x;
// B = T × N.
Frame default_frame(const glm::dvec3& origin, const glm::dvec3& t) {
  glm::dvec3 n = glm::cross(t, glm::dvec3(1, 0, 0));
  if (glm::length(n) < 1e-9) n = glm::cross(t, glm::dvec3(0, 1, 0));
  n = glm::normalize(n);
  return {origin, n, glm::normalize(glm::cross(t, n)), 1.0, 0.0, t};
}

// `v` turned by the smallest rotation that takes unit vector `a` to unit vector `b`.
glm::dvec3 transport(const glm::dvec3& v, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 axis = glm::cross(a, b);
  const double s = glm::length(axis), co = glm::dot(a, b);
  if (s < 1e-12) return v;  // parallel: reversals are refused before
  const glm::dvec3 k = axis / s;
  return v * co + glm::cross(k, v) * s + k * glm::dot(k, v) * (1 - co);
}

// The rings' frames as NOME3 made them (generators-original.md §12.2-4): the default frame at
// the ends of an open path and at collinear points; at a joint T = u_out + u_in, N = u_out −
// u_in and the N coordinate scaled by 1/cos(θ/2) (the miter); every point of a closed path
// is a joint and the path gets one more ring, a copy of the first. With `mintorsion`, each
// ring is turned so that its N is the last ring's N carried back along the path by parallel
// transport (NOME3 accumulates the joints' turns from the end backwards). Then `azimuth`
// turns every ring and `twist` the ring k of n by twist·k/(n−1). Nullopt after an error.
std::optional<std::vector<Frame>> nome3_frames(Context& c, const SweepInput& in, std::string_view inst_path) {
  const bool closed = in.path.is_closed;
  const auto& P = in.path.points;
  const size_t np = P.size();
  auto fail = [&](std::string what) {
    c.diags().emit(DiagKind::GeometryFailed, in.path_range,
                   fmt::format("{} `{}`: {} (instance `{}`)", in.keyword, in.name, what, inst_path));
    return std::nullopt;
  };
  if (np < 2 || (closed && np < 3)) {
    return fail(fmt::format("needs a path of at least {} points, got {}", closed ? 3 : 2, np));
  }
  const size_t segs = closed ? np : np - 1;
  std::vector<glm::dvec3> u(segs);
  for (size_t s = 0; s < segs; ++s) {
    const glm::dvec3 d = P[(s + 1) % np] - P[s];
    if (glm::length(d) == 0) return fail("the path has repeated points");
    u[s] = glm::normalize(d);
  }
  std::vector<Frame> out;
  for (size_t i = 0; i < np; ++i) {
    const glm::dvec3 ui = closed || i > 0 ? u[(i + segs - 1) % segs] : u[0];
    const glm::dvec3 uo = closed || i + 1 < np ? u[i % segs] : u[segs - 1];
    const glm::dvec3 sum = ui + uo;
    if (glm::length(sum) < 1e-9) return fail(fmt::format("the path turns back on itself at its point {}", i + 1));
    if (glm::length(glm::cross(ui, uo)) < 1e-9) {
      out.push_back(default_frame(P[i], uo));
      continue;
    }
    const glm::dvec3 t = glm::normalize(sum), n = glm::normalize(uo - ui);
    out.push_back({P[i], n, glm::cross(t, n), 2.0 / glm::length(sum), 0.0, t});
  }
  if (closed) out.push_back(out.front());
  const size_t rings = out.size();
  if (in.mintorsion) {
    glm::dvec3 e = out.back().n;
    for (size_t i = rings - 1; i-- > 0;) {
      const glm::dvec3& s = u[i % segs];  // the segment from ring i to ring i + 1
      e = transport(transport(e, out[i + 1].t, s), s, out[i].t);
      e = glm::normalize(e - glm::dot(e, out[i].t) * out[i].t);
      out[i].angle = std::atan2(glm::dot(glm::cross(out[i].n, e), out[i].t), glm::dot(out[i].n, e));
    }
  }
  for (size_t i = 0; i < rings; ++i) {
    out[i].angle += glm::radians(in.azimuth + in.twist * static_cast<double>(i) / static_cast<double>(rings - 1));
  }
  return out;
}

// The rings' frames for the file's dialect.
std::optional<std::vector<Frame>> frames(Context& c, const SweepInput& in, std::string_view inst_path) {
  return c.m.dialect == Dialect::Slide ? slide_frames(c, in, inst_path) : nome3_frames(c, in, inst_path);
}

// The cross section of every ring in its plane: the sweep's own, or (sweepmorph) the one
// interpolated between the controlpoints' cross-sections; then scaled and turned by the
// controlpoints. Also whether it is closed. Nullopt after a reported error.
std::optional<std::pair<std::vector<std::vector<glm::dvec3>>, bool>> sections(Context& c, const SweepInput& in,
                                                                             bool morph, std::string_view inst_path) {
  const size_t np = in.path.points.size();
  const double steps = in.path.is_closed ? static_cast<double>(np) : static_cast<double>(np - 1);
  std::vector<const Key*> shaped, carrying;
  for (const Key& k : in.keys) {
    shaped.push_back(&k);
    if (k.section) carrying.push_back(&k);
  }
  bool cs_closed = in.cs.is_closed;
  const std::vector<glm::dvec3>* fixed = &in.cs.points;
  SourceRange cs_range = in.cs_range;
  if (morph) {
    if (carrying.empty()) {
      c.diags().emit(DiagKind::GeometryFailed, in.path_range,
                     fmt::format("sweepmorph `{}` needs controlpoints with a `crosssection` on its path; none of its "
                                 "points has one (instance `{}`)",
                                 in.name, inst_path));
      return std::nullopt;
    }
    fixed = &carrying.front()->section->points;
    cs_closed = carrying.front()->section->is_closed;
    cs_range = c.m.get<ir::ControlPointData>(carrying.front()->node).cross_section_range;
    for (const Key* k : carrying) {
      if (k->section->points.size() == fixed->size()) continue;
      c.diags().emit(DiagKind::GeometryFailed, c.m.get<ir::ControlPointData>(k->node).cross_section_range,
                     fmt::format("sweepmorph `{}` interpolates cross-sections point by point, but `{}` has {} points "
                                 "and `{}` has {} (instance `{}`)",
                                 in.name, short_name(c.m.node(k->node).name), k->section->points.size(),
                                 short_name(c.m.node(carrying.front()->node).name), fixed->size(), inst_path));
      return std::nullopt;
    }
  }
  const size_t nc = fixed->size();
  if (nc < 2 || (cs_closed && nc < 3)) {
    c.diags().emit(DiagKind::GeometryFailed, cs_range,
                   fmt::format("{} `{}` needs a cross section of at least {} points, got {} (instance `{}`)", in.keyword,
                               in.name, cs_closed ? 3 : 2, nc, inst_path));
    return std::nullopt;
  }
  std::vector<std::vector<glm::dvec3>> out(np);
  for (size_t i = 0; i < np; ++i) {
    const double t = static_cast<double>(i) / steps;
    std::vector<glm::dvec3> cs = *fixed;
    if (morph) {
      auto [a, bw] = around(carrying, t);
      for (size_t j = 0; j < nc; ++j) cs[j] = (1.0 - bw.second) * a->section->points[j] + bw.second * bw.first->section->points[j];
    }
    if (!shaped.empty()) {
      auto [a, bw] = around(shaped, t);
      const glm::dvec2 s = (1.0 - bw.second) * a->scale + bw.second * bw.first->scale;
      const double ang = glm::radians((1.0 - bw.second) * a->angle + bw.second * bw.first->angle);
      for (glm::dvec3& p : cs) {
        const double x = p.x * s.x, y = p.y * s.y;
        p = {x * std::cos(ang) - y * std::sin(ang), x * std::sin(ang) + y * std::cos(ang), 0.0};
      }
    }
    out[i] = std::move(cs);
  }
  if (in.path.is_closed) out.push_back(out.front());  // the closing ring repeats the first
  return std::make_pair(std::move(out), cs_closed);
}

// Whether ring `last` (a closed path's closing ring) lies on ring 0.
bool closes(const std::vector<Frame>& fr, const std::vector<std::vector<glm::dvec3>>& cs, size_t last) {
  double size = 1.0, gap = 0.0;
  for (size_t j = 0; j < cs[0].size(); ++j) {
    const glm::dvec3 a = place(fr[0], cs[0][j]), b = place(fr[last], cs[last][j]);
    size = std::max({size, std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)});
    gap = std::max(gap, glm::length(a - b));
  }
  return gap <= 1e-9 * size;
}

std::optional<kernel::PolygonSoup> sweep_node(Context& c, ir::NodeId sweep_id, std::string_view inst_path) {
  const SweepInput in = sweep_input(c, sweep_id, inst_path);
  const bool morph = c.m.node(sweep_id).kind == ir::NodeKind::SweepMorph;
  auto fr = frames(c, in, inst_path);
  if (!fr) return std::nullopt;
  auto cs = sections(c, in, morph, inst_path);
  if (!cs) return std::nullopt;
  const auto& [rings_cs, cs_closed] = *cs;
  // A closed path: NOME3 repeats the first ring at the end; nomec welds the two when they
  // coincide, and otherwise keeps NOME3's open seam with a warning.
  bool path_closed = in.path.is_closed;
  size_t rings = std::min(fr->size(), rings_cs.size());
  if (path_closed && closes(*fr, rings_cs, rings - 1)) {
    --rings;
  } else if (path_closed) {
    path_closed = false;
    c.diags().emit(DiagKind::SweepSeamOpen, in.path_range,
                   fmt::format("{} `{}`: its last ring does not meet its first (the twist is not a multiple of 360° "
                               "or the path's torsion turns the cross section), so the tube is left open there as "
                               "NOME3 left it (instance `{}`)",
                               in.keyword, in.name, inst_path));
  }
  const size_t nc = rings_cs[0].size();
  kernel::PolygonSoup out;
  for (size_t i = 0; i < rings; ++i) {
    for (size_t j = 0; j < nc; ++j) {
      // NOME3's names: ring k counted from 1, then the cross-section's index.
      out.add_vertex(place((*fr)[i], rings_cs[i][j]), fmt::format("v{}_{}", i + 1, j));
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
  if (cs_closed && !in.path.is_closed) {
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

int32_t sweep_vertex(Context& c, ir::NodeId sweep_id, std::string_view inst_path, const kernel::PolygonSoup& soup,
                     std::string_view name) {
  auto find = [&](std::string_view n) {
    for (size_t v = 0; v < soup.names.size(); ++v) {
      if (soup.names[v] == n) return static_cast<int32_t>(v);
    }
    return -1;
  };
  if (const int32_t v = find(name); v >= 0) return v;
  size_t k = 0, i = 0, rings = 0, points = 0;
  auto parse = [](std::string_view n, size_t& ring, size_t& point) {
    return std::sscanf(std::string(n).c_str(), "v%zu_%zu", &ring, &point) == 2;
  };
  if (!parse(name, k, i) || name != fmt::format("v{}_{}", k, i)) return -1;
  for (const std::string& n : soup.names) {
    size_t a = 0, b = 0;
    if (parse(n, a, b)) rings = std::max(rings, a), points = std::max(points, b + 1);
  }
  const SweepInput in = sweep_input(c, sweep_id, inst_path);
  bool cs_closed = in.cs.is_closed;
  for (const Key& key : in.keys) {
    if (c.m.node(sweep_id).kind == ir::NodeKind::SweepMorph && key.section) {
      cs_closed = key.section->is_closed;
      break;
    }
  }
  if (cs_closed && i == points) i = 0;
  if (in.path.is_closed && rings == in.path.points.size() && k == rings + 1) k = 1;  // welded
  return find(fmt::format("v{}_{}", k, i));
}

std::optional<Generated> morph_visualizer(Context& c, ir::NodeId vis_id, std::string_view inst_path) {
  const ir::Node& vn = c.m.node(vis_id);
  const ir::MorphVisualizerData& d = vn.as<ir::MorphVisualizerData>();
  if (!d.sweep.is_valid() || !d.index.is_valid()) return std::nullopt;  // reported by the checker
  const SweepInput in = sweep_input(c, d.sweep, inst_path);
  auto fr = frames(c, in, inst_path);
  if (!fr) return std::nullopt;
  auto cs = sections(c, in, true, inst_path);
  if (!cs) return std::nullopt;
  const double index = scalar(c, d.index, 0, 0);
  const bool in_range = index > -0.5 && index < static_cast<double>(fr->size()) - 0.5;  // false for NaN
  const long k = in_range ? std::lround(index) : -1;
  if (!in_range || std::fabs(index - static_cast<double>(k)) > 1e-9) {
    c.diags().emit(DiagKind::GeometryFailed, c.m.operand(d.index).range,
                   fmt::format("morphvisualizer `{}`: `index` must be a whole number from 0 to {} (the rings of `{}`), "
                               "got {}",
                               short_name(vn.name), fr->size() - 1, in.name, ir::format_argument(index)));
    return std::nullopt;
  }
  Generated g;
  Generated::Curve curve;
  curve.is_closed = cs->second;
  const Frame& f = (*fr)[static_cast<size_t>(k)];
  const auto& ring = cs->first[static_cast<size_t>(k)];
  for (size_t j = 0; j < ring.size(); ++j) {
    curve.vertices.push_back(g.soup.add_vertex(place(f, ring[j]),
                                               fmt::format("v{}_{}", k, j)));
  }
  g.curves.push_back(std::move(curve));
  return g;
}

}  // namespace nomec::backend::eval
