// Running a block's steps (see steps.h), whole or per connected component.
#include "backend/eval/steps.h"

#include <algorithm>
#include <glm/geometric.hpp>
#include <string>
#include <unordered_map>

#include "kernel/edit.h"
#include "kernel/topology.h"

namespace nomec::backend::eval {

namespace {

bool same_soup(const kernel::PolygonSoup& a, const kernel::PolygonSoup& b) {
  auto same_creases = [](const auto& x, const auto& y) {
    return x.size() == y.size() && std::equal(x.begin(), x.end(), y.begin(), [](const auto& c, const auto& d) {
             return c.a == d.a && c.b == d.b && c.sharpness == d.sharpness;
           });
  };
  auto same_corners = [](const auto& x, const auto& y) {
    return x.size() == y.size() && std::equal(x.begin(), x.end(), y.begin(), [](const auto& c, const auto& d) {
             return c.vertex == d.vertex && c.sharpness == d.sharpness;
           });
  };
  return a.positions == b.positions && a.face_sizes == b.face_sizes && a.face_vertices == b.face_vertices &&
         a.face_sources == b.face_sources && a.face_colors == b.face_colors && a.names == b.names &&
         same_creases(a.creases, b.creases) && same_corners(a.corners, b.corners);
}

uint64_t soup_hash(const kernel::PolygonSoup& s) {
  uint64_t h = 1469598103934665603ull;
  auto mix = [&](const void* data, size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  };
  mix(s.positions.data(), s.positions.size() * sizeof(glm::dvec3));
  mix(s.face_vertices.data(), s.face_vertices.size() * sizeof(int32_t));
  mix(s.face_sizes.data(), s.face_sizes.size() * sizeof(int32_t));
  return h;
}

// Splits `mesh` into one soup per connected component (faces in their original order).
std::vector<kernel::PolygonSoup> split_components(const kernel::Mesh& mesh) {
  std::vector<int32_t> comp = kernel::face_components(mesh);
  int32_t count = 0;
  for (int32_t c : comp) count = std::max(count, c + 1);
  kernel::PolygonSoup all = kernel::to_soup(mesh);
  std::vector<kernel::PolygonSoup> parts(count);
  std::vector<int32_t> local(all.vertex_count(), -1), owner(all.vertex_count(), -1);
  size_t at = 0;
  std::vector<int32_t> face;
  for (int32_t f = 0; f < all.face_count(); ++f) {
    kernel::PolygonSoup& p = parts[comp[f]];
    face.clear();
    for (int32_t i = 0; i < all.face_sizes[f]; ++i) {
      int32_t v = all.face_vertices[at + i];
      if (owner[v] != comp[f]) {
        owner[v] = comp[f];
        local[v] = p.add_vertex(all.positions[v], all.names.empty() ? std::string() : all.names[v]);
      }
      face.push_back(local[v]);
    }
    at += all.face_sizes[f];
    p.add_face(face);
    if (!all.face_sources.empty()) p.face_sources.push_back(all.face_sources[f]);
    if (!all.face_colors.empty()) p.face_colors.push_back(all.face_colors[f]);
  }
  for (kernel::PolygonSoup& p : parts) {
    if (all.names.empty()) p.names.clear();
  }
  for (const auto& c : all.creases) {
    if (owner[c.a] >= 0 && owner[c.a] == owner[c.b]) {
      parts[owner[c.a]].creases.push_back({local[c.a], local[c.b], c.sharpness});
    }
  }
  for (const auto& c : all.corners) {
    if (owner[c.vertex] >= 0) parts[owner[c.vertex]].corners.push_back({local[c.vertex], c.sharpness});
  }
  return parts;
}

}  // namespace

std::variant<kernel::Mesh, StepFailure> run_steps(kernel::Mesh mesh, const std::vector<Step>& steps,
                                                  int32_t& kernel_ops, int64_t max_vertices) {
  for (size_t i = 0; i < steps.size(); ++i) {
    const Step& s = steps[i];
    if (s.kind == Step::Kind::Subdivide) {
      if (s.subdivision.levels <= 0) continue;
      ++kernel_ops;
      kernel::SubdivisionOptions options = s.subdivision;
      options.max_vertices = max_vertices;
      auto r = kernel::subdivide_last_level(std::move(mesh), options);
      if (!r) return StepFailure{r.error(), i};
      mesh = std::move(*r);
    } else {
      ++kernel_ops;
      auto r = s.kind == Step::Kind::Lattice
                   ? kernel::lattice(mesh, kernel::LatticeOptions{s.width, s.height})
                   : kernel::offset_consuming(std::move(mesh),
                                              kernel::OffsetOptions{.distance = s.height, .has_parent_maps = false});
      if (!r) return StepFailure{r.error(), i};
      mesh = std::move(r->mesh);
    }
  }
  return mesh;
}

std::variant<kernel::Mesh, StepFailure> run_steps_by_component(const kernel::Mesh& mesh,
                                                               const std::vector<Step>& steps,
                                                               ComponentMemo& pool, ComponentMemo& next,
                                                               int32_t& kernel_ops, int64_t max_vertices) {
  std::vector<kernel::PolygonSoup> parts = split_components(mesh);
  size_t used_vertices = 0;
  for (const auto& p : parts) used_vertices += p.positions.size();
  if (used_vertices != static_cast<size_t>(mesh.vertex_count())) return run_steps(mesh, steps, kernel_ops, max_vertices);
  std::unordered_multimap<uint64_t, size_t> by_hash;
  for (size_t i = 0; i < pool.entries.size(); ++i) by_hash.emplace(pool.entries[i].hash, i);
  const size_t first = next.entries.size();
  for (kernel::PolygonSoup& p : parts) {
    const uint64_t h = soup_hash(p);
    ComponentMemo::Entry* hit = nullptr;
    auto [lo, hi] = by_hash.equal_range(h);
    for (auto it = lo; it != hi; ++it) {
      ComponentMemo::Entry& e = pool.entries[it->second];
      if (e.hash == h && e.steps == steps && same_soup(e.input, p)) {
        hit = &e;
        break;
      }
    }
    if (hit != nullptr) {
      next.entries.push_back(std::move(*hit));
      hit->hash = ~h;  // moved from; never matches again
      hit->input = {};
      continue;
    }
    auto built = kernel::build_mesh(p);
    if (!built) {
      next.entries.resize(first);
      return run_steps(mesh, steps, kernel_ops, max_vertices);
    }
    auto r = run_steps(std::move(*built), steps, kernel_ops, max_vertices);
    if (std::holds_alternative<StepFailure>(r)) {
      next.entries.resize(first);
      return run_steps(mesh, steps, kernel_ops, max_vertices);
    }
    next.entries.push_back({h, std::move(p), steps, std::move(std::get<kernel::Mesh>(r))});
  }
  std::vector<const kernel::Mesh*> outs;
  for (size_t i = first; i < next.entries.size(); ++i) outs.push_back(&next.entries[i].output);
  if (outs.size() == 1) return *outs[0];
  return kernel::append_disjoint(outs);
}

kernel::Result<kernel::MergeResult> merge_mesh(const kernel::Mesh& mesh, double tol) {
  if (tol < 0) {
    kernel::BoundingBox b = kernel::bounding_box(mesh);
    double diag = b.min.x <= b.max.x ? glm::length(b.max - b.min) : 0;
    tol = diag > 0 ? 1e-4 * diag : 1e-9;
  }
  return kernel::merge(mesh, kernel::MergeOptions{tol});
}

}  // namespace nomec::backend::eval
