// High-genus constructions (see highgenus.h). Handles and Sierpinski levels are made of
// the DLFL operators in dlfl.h; rinds edit an offset slab; the Menger sponge writes its
// frames, tunnels and inner walls as a polygon soup.
#include "kernel/highgenus.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>
#include <numeric>
#include <unordered_map>

#include "kernel/dlfl.h"
#include "kernel/offset.h"

namespace nomec::kernel {

namespace {

// ---- handles ----

// TopMod's one-segment connectFaces: the non-co-facial insertion merges the two faces
// (a, …, a, b, …, b), then co-facial insertions peel off one quad after another.
Result<bool> pipe(LoopMesh& m, LoopCorner a, LoopCorner b) {
  auto taken = [&](LoopCorner x, LoopCorner y) {
    const int32_t u = m.face(x.face)[x.index], v = m.face(y.face)[y.index];
    KernelError e = invalid_argument("the handle would join two corners that an edge joins already; use more segments, "
                            "other corners or faces farther apart");
    e.vertices = {VertexId(u), VertexId(v)};
    return e;
  };
  if (m.edge_use_count(m.face(a.face)[a.index], m.face(b.face)[b.index]) > 0) return taken(a, b);
  auto merged = m.insert_edge(a, b);
  if (!merged) return merged.error();
  const int32_t f = *merged;
  while (m.face(f).size() > 4) {
    const int32_t n = static_cast<int32_t>(m.face(f).size());
    if (m.edge_use_count(m.face(f)[1], m.face(f)[n - 2]) > 0) return taken(LoopCorner{f, 1}, LoopCorner{f, n - 2});
    auto split = m.insert_edge(LoopCorner{f, 1}, LoopCorner{f, n - 2});
    if (!split) return split.error();
  }
  return true;
}

// The smaller face's longest edges are split until both faces have as many sides.
Result<bool> equalize(LoopMesh& m, int32_t fa, int32_t fb) {
  for (int guard = 0; m.face(fa).size() != m.face(fb).size() && guard < 1 << 20; ++guard) {
    const int32_t f = m.face(fa).size() < m.face(fb).size() ? fa : fb;
    const std::vector<int32_t>& l = m.face(f);
    int32_t longest = 0;
    double best = -1;
    for (size_t k = 0; k < l.size(); ++k) {
      const double d = glm::length(m.position(l[(k + 1) % l.size()]) - m.position(l[k]));
      if (d > best) best = d, longest = static_cast<int32_t>(k);
    }
    const glm::dvec3 mid = 0.5 * (m.position(l[longest]) + m.position(l[(longest + 1) % l.size()]));
    auto s = m.split_edge(LoopCorner{f, longest}, mid);
    if (!s) return s.error();
  }
  return true;
}

// The position of `v` in face loop `l`, or -1.
int32_t index_in(const std::vector<int32_t>& l, VertexId v) {
  auto it = std::find(l.begin(), l.end(), v.index);
  return it == l.end() ? -1 : static_cast<int32_t>(it - l.begin());
}

// Points of the rings between the two faces (ring k = 1 … segments−1), in the first
// face's order starting at its first paired corner.
std::vector<std::vector<glm::dvec3>> handle_rings(const std::vector<glm::dvec3>& pa, const std::vector<glm::dvec3>& pb,
                                                  const HandleOptions& o) {
  const size_t n = pa.size();
  const glm::dvec3 ca = std::accumulate(pa.begin(), pa.end(), glm::dvec3(0.0)) / double(n);
  const glm::dvec3 cb = std::accumulate(pb.begin(), pb.end(), glm::dvec3(0.0)) / double(n);
  const glm::dvec3 along = unit_or(cb - ca, {0, 0, 1});
  const double dist = glm::length(cb - ca);
  // pb runs against the second face's orientation, so its Newell normal points into it.
  const glm::dvec3 na = unit_or(newell_normal(pa), along), nb = unit_or(newell_normal(pb), along);
  const glm::dvec3 t0 = o.weights[0] * dist * na, t1 = o.weights[1] * dist * nb;
  auto point = [&](double t) {
    const double t2 = t * t, t3 = t2 * t;
    return (2 * t3 - 3 * t2 + 1) * ca + (t3 - 2 * t2 + t) * t0 + (-2 * t3 + 3 * t2) * cb + (t3 - t2) * t1;
  };
  auto tangent = [&](double t) {
    const double t2 = t * t;
    return unit_or((6 * t2 - 6 * t) * ca + (3 * t2 - 4 * t + 1) * t0 + (-6 * t2 + 6 * t) * cb + (3 * t2 - 2 * t) * t1,
                along);
  };
  // Polar coordinates of each ring in its own frame (z = the direction of travel).
  struct Polar {
    std::vector<double> angle, radius, height;
  };
  auto polar = [&](const std::vector<glm::dvec3>& p, const glm::dvec3& c, const glm::dvec3& z, glm::dvec3& x) {
    x = unit_or(p[0] - c - glm::dot(p[0] - c, z) * z, unit_or(glm::cross(z, {0.31, 0.53, 0.79}), {1, 0, 0}));
    const glm::dvec3 y = glm::cross(z, x);
    Polar r;
    for (size_t i = 0; i < n; ++i) {
      const glm::dvec3 d = p[i] - c;
      double a = std::atan2(glm::dot(d, y), glm::dot(d, x));
      while (i > 0 && a < r.angle.back()) a += 2 * std::numbers::pi;
      r.angle.push_back(a);
      r.radius.push_back(std::hypot(glm::dot(d, x), glm::dot(d, y)));
      r.height.push_back(glm::dot(d, z));
    }
    return r;
  };
  glm::dvec3 xa, xb;
  const Polar a = polar(pa, ca, na, xa), b = polar(pb, cb, nb, xb);
  // Rotation-minimising frames along the curve, then the mismatch with the end frame
  // (and the extra turns) spread evenly.
  const int32_t s = o.segments;
  std::vector<glm::dvec3> frame_x(s + 1), frame_z(s + 1);
  frame_z[0] = tangent(0.0);
  frame_x[0] = unit_or(xa - glm::dot(xa, frame_z[0]) * frame_z[0], xa);
  for (int32_t k = 1; k <= s; ++k) {
    frame_z[k] = tangent(double(k) / s);
    frame_x[k] = unit_or(frame_x[k - 1] - glm::dot(frame_x[k - 1], frame_z[k]) * frame_z[k], frame_x[k - 1]);
  }
  const glm::dvec3 xe = unit_or(xb - glm::dot(xb, frame_z[s]) * frame_z[s], xb);
  const double mismatch =
      std::atan2(glm::dot(glm::cross(frame_x[s], xe), frame_z[s]), glm::dot(frame_x[s], xe)) + 2 * std::numbers::pi * o.twist;
  std::vector<std::vector<glm::dvec3>> rings;
  for (int32_t k = 1; k < s; ++k) {
    const double t = double(k) / s;
    const glm::dvec3 z = frame_z[k];
    const glm::dvec3 x0 = frame_x[k], y0 = glm::cross(z, x0);
    const double turn = mismatch * t;
    const glm::dvec3 x = std::cos(turn) * x0 + std::sin(turn) * y0, y = glm::cross(z, x);
    const glm::dvec3 c = point(t);
    std::vector<glm::dvec3> ring;
    for (size_t i = 0; i < n; ++i) {
      const double ang = (1 - t) * a.angle[i] + t * b.angle[i];
      const double rad = (1 - t) * a.radius[i] + t * b.radius[i];
      const double h = (1 - t) * a.height[i] + t * b.height[i];
      ring.push_back(c + rad * (std::cos(ang) * x + std::sin(ang) * y) + h * z);
    }
    rings.push_back(std::move(ring));
  }
  return rings;
}

Result<bool> check_handle(const Mesh& mesh, const HandleOptions& o) {
  for (FaceId f : o.faces) {
    if (f.index < 0 || f.index >= mesh.face_count()) {
      return invalid_argument(fmt::format("face {} does not exist; the mesh has {} faces", f.index, mesh.face_count()));
    }
  }
  if (o.faces[0] == o.faces[1]) return invalid_argument("a handle needs two different faces");
  if (o.segments < 1) return invalid_argument(fmt::format("a handle needs at least 1 segment, not {}", o.segments));
  if (!std::isfinite(o.weights[0]) || !std::isfinite(o.weights[1]) || !std::isfinite(o.twist)) {
    return invalid_argument("handle weights and twist must be finite numbers");
  }
  const std::vector<VertexId> a = mesh.face_vertices(o.faces[0]), b = mesh.face_vertices(o.faces[1]);
  for (VertexId v : a) {
    if (std::find(b.begin(), b.end(), v) != b.end()) {
      KernelError e = invalid_argument("the two faces share a vertex; a handle joins faces that do not touch");
      e.faces = {o.faces[0], o.faces[1]};
      e.vertices = {v};
      return e;
    }
  }
  for (int side = 0; side < 2; ++side) {
    const std::vector<VertexId>& l = side == 0 ? a : b;
    if (o.corners[side].is_valid() && std::find(l.begin(), l.end(), o.corners[side]) == l.end()) {
      KernelError e = invalid_argument(fmt::format("vertex {} is not a corner of face {}", o.corners[side].index,
                                          o.faces[side].index));
      e.vertices = {o.corners[side]};
      return e;
    }
  }
  return true;
}

}  // namespace

Result<Mesh> connect_faces(const Mesh& mesh, const HandleOptions& o) {
  if (auto ok = check_handle(mesh, o); !ok) return ok.error();
  LoopMesh m = LoopMesh::from_mesh(mesh);
  const int32_t fa = o.faces[0].index, fb = o.faces[1].index;
  if (auto ok = equalize(m, fa, fb); !ok) return ok.error();
  const std::vector<int32_t> la = m.face(fa), lb = m.face(fb);
  const int32_t n = static_cast<int32_t>(la.size());
  int32_t ia = o.corners[0].is_valid() ? index_in(la, o.corners[0]) : 0;
  int32_t ib = o.corners[1].is_valid() ? index_in(lb, o.corners[1]) : -1;
  if (ib < 0) {
    // Automatic: the shift of the second loop (run backwards) nearest to the first.
    double best = std::numeric_limits<double>::infinity();
    for (int32_t j = 0; j < n; ++j) {
      double sum = 0;
      for (int32_t i = 0; i < n; ++i) {
        const glm::dvec3 d = m.position(la[(ia + i) % n]) - m.position(lb[((j - i) % n + n) % n]);
        sum += glm::dot(d, d);
      }
      if (sum < best) best = sum, ib = j;
    }
  }
  if (o.segments == 1) {
    if (auto ok = pipe(m, LoopCorner{fa, ia}, LoopCorner{fb, ib}); !ok) return ok.error();
    return m.to_mesh();
  }
  std::vector<glm::dvec3> pa, pb;
  for (int32_t i = 0; i < n; ++i) {
    pa.push_back(m.position(la[(ia + i) % n]));
    pb.push_back(m.position(lb[((ib - i) % n + n) % n]));
  }
  const std::vector<std::vector<glm::dvec3>> rings = handle_rings(pa, pb, o);
  LoopCorner from{fa, ia};
  for (const std::vector<glm::dvec3>& ring : rings) {
    std::vector<int32_t> fwd, back;
    for (const glm::dvec3& p : ring) fwd.push_back(m.add_vertex(p));
    back.push_back(fwd[0]);
    for (int32_t i = n - 1; i > 0; --i) back.push_back(fwd[i]);
    const int32_t f_fwd = m.add_face(fwd, m.source(fa)), f_back = m.add_face(back, m.source(fa));
    if (auto ok = pipe(m, from, LoopCorner{f_back, 0}); !ok) return ok.error();
    from = LoopCorner{f_fwd, 0};
  }
  if (auto ok = pipe(m, from, LoopCorner{fb, ib}); !ok) return ok.error();
  return m.to_mesh();
}

// ---- rind ----

namespace {

// Per face: 0, 1 punched or 2 peeled; refuses a face both punched and peeled, a punched
// face next to a peeled one, and regions whose edges pass a vertex twice.
Result<std::vector<uint8_t>> rind_roles(const Mesh& mesh, const RindOptions& o) {
  const int32_t F = mesh.face_count();
  std::vector<uint8_t> role(F, 0);  // 1 punched, 2 peeled
  for (int which = 1; which <= 2; ++which) {
    for (FaceId f : which == 1 ? o.punch : o.peel) {
      if (f.index < 0 || f.index >= F) return invalid_argument(fmt::format("face {} does not exist; the mesh has {} faces", f.index, F));
      if (role[f.index] != 0 && role[f.index] != which) {
        KernelError e = invalid_argument(fmt::format("face {} is both punched and peeled", f.index));
        e.faces = {f};
        return e;
      }
      role[f.index] = static_cast<uint8_t>(which);
    }
  }
  for (int32_t e = 0; e < mesh.edge_count(); ++e) {
    const FaceId a = mesh.edge_face(EdgeId(e), 0), b = mesh.edge_face(EdgeId(e), 1);
    if (b.is_valid() && role[a.index] + role[b.index] == 3) {
      KernelError err = invalid_argument(fmt::format("punched face {} shares an edge with peeled face {}",
                                            role[a.index] == 1 ? a.index : b.index, role[a.index] == 1 ? b.index : a.index));
      err.faces = {a, b};
      return err;
    }
  }
  // A region's edge may pass a vertex once: walls meeting at a vertex from two sides
  // would pinch the crust there.
  std::vector<int32_t> walls_at[3];
  walls_at[1].assign(mesh.vertex_count(), 0);
  walls_at[2].assign(mesh.vertex_count(), 0);
  for (int32_t e = 0; e < mesh.edge_count(); ++e) {
    const FaceId a = mesh.edge_face(EdgeId(e), 0), b = mesh.edge_face(EdgeId(e), 1);
    const uint8_t ra = role[a.index], rb = b.is_valid() ? role[b.index] : 0;
    for (uint8_t r : {uint8_t(1), uint8_t(2)}) {
      // Punched regions: their walls plus the ribbons that stay; peeled ones: their walls.
      const bool counts = b.is_valid() ? ((ra == r) != (rb == r)) : (r == 1 ? ra != 1 : ra == 2);
      if (!counts) continue;
      for (int end = 0; end < 2; ++end) ++walls_at[r][mesh.edge_vertex(EdgeId(e), end).index];
    }
  }
  for (int32_t v = 0; v < mesh.vertex_count(); ++v) {
    for (int r = 1; r <= 2; ++r) {
      if (walls_at[r][v] != 0 && walls_at[r][v] != 2) {
        KernelError e = invalid_argument(fmt::format("the {} faces meet at a corner from more than one side (their edges pass "
                                            "it {} times); the crust would be pinched there",
                                            r == 1 ? "punched" : "peeled", walls_at[r][v] / 2 + walls_at[r][v] % 2));
        e.vertices = {VertexId(v)};
        mesh.for_each_vertex_corner(VertexId(v), [&](const VertexCorner& k) {
          if (role[k.face.index] == r) e.faces.push_back(k.face);
        });
        return e;
      }
    }
  }
  return role;
}

}  // namespace

Result<Mesh> rind(const Mesh& mesh, const RindOptions& o) {
  if (!(o.thickness > 0) || !std::isfinite(o.thickness)) {
    return invalid_argument(fmt::format("rind thickness must be positive, not {}", o.thickness));
  }
  auto roles = rind_roles(mesh, o);
  if (!roles) return roles.error();
  const std::vector<uint8_t>& role = *roles;
  const int32_t F = mesh.face_count();
  auto slab = offset(mesh, OffsetOptions{o.thickness / 2});
  if (!slab) return slab.error();
  const Mesh& s = slab->mesh;
  std::vector<int32_t> positive(F, -1), negative(F, -1);
  PolygonSoup soup = to_soup(s);
  PolygonSoup out;
  out.positions = soup.positions;
  size_t at = 0;
  for (int32_t f = 0; f < s.face_count(); ++f) {
    const OffsetParent& p = slab->face_parents[f];
    const int32_t n = soup.face_sizes[f];
    const uint8_t r = role[p.face.index];
    if (p.kind == OffsetParent::Kind::PositiveFace) positive[p.face.index] = f;
    if (p.kind == OffsetParent::Kind::NegativeFace) negative[p.face.index] = f;
    const bool removed = (p.kind == OffsetParent::Kind::PositiveFace && r != 0) ||
                         (p.kind == OffsetParent::Kind::NegativeFace && r == 1) ||
                         (p.kind == OffsetParent::Kind::Ribbon && r == 1);
    if (!removed) {
      out.add_face(std::span<const int32_t>(soup.face_vertices.data() + at, n));
      out.face_sources.push_back(soup.face_sources[f]);
      if (!soup.face_colors.empty()) out.face_colors.push_back(soup.face_colors[f]);
    }
    at += n;
  }
  // Walls along the edges of the punched and peeled regions; peeled regions get a floor
  // midway between the sheets.
  std::unordered_map<int32_t, int32_t> floor;  // input vertex -> floor vertex
  for (int32_t f = 0; f < F; ++f) {
    if (role[f] == 0) continue;
    std::unordered_map<int32_t, int32_t> top, bottom;  // input vertex -> sheet vertex
    s.for_each_face_use(FaceId(positive[f]), [&](EdgeUse u) {
      top.emplace(slab->vertex_parents[s.use_tail(u).index].index, s.use_tail(u).index);
    });
    s.for_each_face_use(FaceId(negative[f]), [&](EdgeUse u) {
      bottom.emplace(slab->vertex_parents[s.use_tail(u).index].index, s.use_tail(u).index);
    });
    const FaceSource src = mesh.face_source(FaceId(f));
    const bool has_color = !soup.face_colors.empty();
    auto emit = [&](std::initializer_list<int32_t> loop) {
      out.add_face(loop);
      out.face_sources.push_back(src);
      if (has_color) out.face_colors.push_back(soup.face_colors[positive[f]]);
    };
    std::vector<int32_t> floor_loop;
    mesh.for_each_face_use(FaceId(f), [&](EdgeUse u) {
      const int32_t a = mesh.use_tail(u).index, b = mesh.use_head(u).index;
      if (role[f] == 2) {
        for (int32_t v : {a, b}) {
          if (!floor.contains(v)) {
            floor[v] = out.add_vertex(0.5 * (out.positions[top[v]] + out.positions[bottom[v]]));
          }
        }
        floor_loop.push_back(floor[a]);
      }
      const bool is_border = mesh.is_boundary(u.edge());
      if (!is_border && role[mesh.use_face(u.twin()).index] == role[f]) return;
      if (role[f] == 1 && is_border) return;  // the ribbon is removed instead
      if (role[f] == 1) emit({top[a], top[b], bottom[b], bottom[a]});
      if (role[f] == 2) emit({top[a], top[b], floor[b], floor[a]});
    });
    if (role[f] == 2) {
      out.add_face(floor_loop);
      out.face_sources.push_back(src);
      if (has_color) out.face_colors.push_back(soup.face_colors[positive[f]]);
    }
  }
  // Drop the vertices no face uses any more.
  std::vector<int32_t> remap(out.positions.size(), -1);
  std::vector<glm::dvec3> used;
  for (int32_t& v : out.face_vertices) {
    if (remap[v] < 0) {
      remap[v] = static_cast<int32_t>(used.size());
      used.push_back(out.positions[v]);
    }
    v = remap[v];
  }
  out.positions = std::move(used);
  return build_mesh(out);
}

}  // namespace nomec::kernel
