// Collected parts (see parts.h): appending soups with a transform, colours and deletion
// flags; comparing parts for incremental updates.
#include "backend/eval/parts.h"

#include <algorithm>
#include <glm/mat3x3.hpp>
#include <span>
#include <string>

#include "kernel/topology.h"

namespace nomec::backend::eval {

// Appends `part` (already in its own frame) to `out` transformed by `t`.
void append_soup(Collected& out, const kernel::PolygonSoup& part, const glm::dmat4& t,
                 const std::optional<glm::vec3>& color, bool part_colored) {
  const int32_t base = out.soup.vertex_count();
  const bool flip = glm::determinant(glm::dmat3(t)) < 0;
  for (int32_t v = 0; v < part.vertex_count(); ++v) {
    glm::dvec3 p = glm::dvec3(t * glm::dvec4(part.positions[v], 1.0));
    std::string name = part.names.empty() ? std::string() : part.names[v];
    if (!out.soup.names.empty() || !name.empty()) {
      out.soup.names.resize(out.soup.positions.size());
      out.soup.names.push_back(std::move(name));
    }
    out.soup.positions.push_back(p);
  }
  size_t at = 0;
  std::vector<int32_t> face;
  for (int32_t f = 0; f < part.face_count(); ++f) {
    face.assign(part.face_vertices.begin() + at, part.face_vertices.begin() + at + part.face_sizes[f]);
    at += part.face_sizes[f];
    for (int32_t& v : face) {
      v += base;
    }
    if (flip) {
      std::reverse(face.begin() + 1, face.end());
    }
    out.soup.add_face(face);
    out.soup.face_sources.push_back(part.face_sources.empty() ? kernel::FaceSource{}
                                                              : part.face_sources[f]);
    if (part_colored && !part.face_colors.empty()) {
      out.soup.face_colors.push_back(part.face_colors[f]);
      out.has_color.push_back(1);
    } else {
      out.soup.face_colors.push_back(color.value_or(kDefaultColor));
      out.has_color.push_back(color.has_value() ? 1 : 0);
    }
    out.is_deleted.push_back(0);
  }
  for (const auto& c : part.creases) {
    out.soup.creases.push_back({c.a + base, c.b + base, c.sharpness});
  }
  for (const auto& c : part.corners) {
    out.soup.corners.push_back({c.vertex + base, c.sharpness});
  }
}

// `append_soup` of a whole collection with the identity transform (what reassembling a
// scene entry from cached parts does for every part), in bulk copies.
void append_collected(Collected& out, const Collected& c) {
  const kernel::PolygonSoup& part = c.soup;
  kernel::PolygonSoup& s = out.soup;
  const int32_t base = s.vertex_count();
  const bool part_named =
      std::any_of(part.names.begin(), part.names.end(), [](const std::string& n) { return !n.empty(); });
  if (!s.names.empty() || part_named) {
    s.names.resize(static_cast<size_t>(base));
    s.names.insert(s.names.end(), part.names.begin(), part.names.end());
    s.names.resize(static_cast<size_t>(base) + part.positions.size());
  }
  s.positions.insert(s.positions.end(), part.positions.begin(), part.positions.end());
  s.face_sizes.insert(s.face_sizes.end(), part.face_sizes.begin(), part.face_sizes.end());
  const size_t at = s.face_vertices.size();
  s.face_vertices.insert(s.face_vertices.end(), part.face_vertices.begin(), part.face_vertices.end());
  for (size_t i = at; i < s.face_vertices.size(); ++i) s.face_vertices[i] += base;
  const size_t faces = part.face_sizes.size();
  if (part.face_sources.empty()) {
    s.face_sources.insert(s.face_sources.end(), faces, kernel::FaceSource{});
  } else {
    s.face_sources.insert(s.face_sources.end(), part.face_sources.begin(), part.face_sources.end());
  }
  if (part.face_colors.empty()) {
    s.face_colors.insert(s.face_colors.end(), faces, kDefaultColor);
  } else {
    s.face_colors.insert(s.face_colors.end(), part.face_colors.begin(), part.face_colors.end());
  }
  out.has_color.insert(out.has_color.end(), c.has_color.begin(), c.has_color.end());
  out.is_deleted.insert(out.is_deleted.end(), c.is_deleted.begin(), c.is_deleted.end());
  for (const auto& k : part.creases) s.creases.push_back({k.a + base, k.b + base, k.sharpness});
  for (const auto& k : part.corners) s.corners.push_back({k.vertex + base, k.sharpness});
  out.curve_count += c.curve_count;
  out.curves.insert(out.curves.end(), c.curves.begin(), c.curves.end());
}

void append_curve(Collected& out, std::span<const glm::dvec3> points, bool is_closed, const glm::dmat4& t) {
  Curve curve{{}, is_closed};
  curve.points.reserve(points.size());
  for (const glm::dvec3& p : points) curve.points.push_back(glm::dvec3(t * glm::dvec4(p, 1.0)));
  out.curves.push_back(std::move(curve));
}

bool is_soup_edge(const kernel::PolygonSoup& s, int32_t a, int32_t b) {
  size_t at = 0;
  for (int32_t f = 0; f < s.face_count(); ++f) {
    const int32_t n = s.face_sizes[f];
    for (int32_t i = 0; i < n; ++i) {
      int32_t u = s.face_vertices[at + i], w = s.face_vertices[at + (i + 1) % n];
      if ((u == a && w == b) || (u == b && w == a)) return true;
    }
    at += n;
  }
  return false;
}

// Drops the colour array when no face was given a colour.
kernel::PolygonSoup finish(Collected& c) {
  if (std::none_of(c.has_color.begin(), c.has_color.end(), [](uint8_t b) { return b != 0; })) {
    c.soup.face_colors.clear();
  }
  if (!c.soup.names.empty()) {
    c.soup.names.resize(c.soup.positions.size());
  }
  return std::move(c.soup);
}

void transform_into(Collected& out, const Collected& c, const glm::dmat4& t) {
  if (t == glm::dmat4(1.0)) {
    append_collected(out, c);
    return;
  }
  const int32_t face_base = out.soup.face_count();
  const kernel::PolygonSoup& s = c.soup;
  append_soup(out, s, t, std::nullopt, true);
  for (int32_t f = 0; f < s.face_count(); ++f) {
    out.has_color[face_base + f] = c.has_color[f];
    out.is_deleted[face_base + f] = c.is_deleted[f];
  }
  out.curve_count += c.curve_count;
  for (const Curve& k : c.curves) append_curve(out, k.points, k.is_closed, t);
}

void reverse_faces(Collected& out, int32_t first_face) {
  kernel::PolygonSoup& s = out.soup;
  size_t at = 0;
  for (int32_t f = 0; f < s.face_count(); ++f) {
    const auto size = static_cast<size_t>(s.face_sizes[f]);
    if (f >= first_face && size > 2) {
      auto begin = s.face_vertices.begin() + static_cast<ptrdiff_t>(at);
      std::reverse(begin + 1, begin + static_cast<ptrdiff_t>(size));
    }
    at += size;
  }
}

bool same_but_positions(const Collected& a, const Collected& b) {
  const kernel::PolygonSoup& x = a.soup;
  const kernel::PolygonSoup& y = b.soup;
  auto same_creases = [](const auto& p, const auto& q) {
    return std::equal(p.begin(), p.end(), q.begin(), q.end(), [](const auto& c, const auto& d) {
      return c.a == d.a && c.b == d.b && c.sharpness == d.sharpness;
    });
  };
  auto same_corners = [](const auto& p, const auto& q) {
    return std::equal(p.begin(), p.end(), q.begin(), q.end(), [](const auto& c, const auto& d) {
      return c.vertex == d.vertex && c.sharpness == d.sharpness;
    });
  };
  if (x.positions.size() != y.positions.size() || x.face_sizes != y.face_sizes ||
      x.face_vertices != y.face_vertices || x.face_sources != y.face_sources ||
      x.face_colors != y.face_colors || x.names != y.names || !same_creases(x.creases, y.creases) ||
      !same_corners(x.corners, y.corners) || a.has_color != b.has_color || a.is_deleted != b.is_deleted ||
      a.curve_count != b.curve_count || a.curves.size() != b.curves.size() ||
      (a.built == nullptr) != (b.built == nullptr)) {
    return false;
  }
  return a.built == nullptr || kernel::has_same_topology(*a.built, *b.built);
}

}  // namespace nomec::backend::eval
