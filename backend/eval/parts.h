// The pieces a scene entry is assembled from: `Collected`, faces gathered for one entry or
// one block's input (a polygon soup plus what the soup has no room for), and the helpers
// that append, compare and finish them.
#pragma once

#include <cstdint>
#include <glm/mat4x4.hpp>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "backend/evaluate.h"
#include "kernel/mesh.h"

namespace nomec::backend::eval {

/// The colour of faces no `surface` colours.
inline constexpr glm::vec3 kDefaultColor{0.8f, 0.8f, 0.8f};

/// Faces collected for one scene entry or one pipeline block's input.
///
/// Rationale: the soup is the kernel's input format, so faces are appended to it directly;
/// the parallel arrays hold what the soup has no room for: whether a face got a colour
/// (uncoloured faces get a neutral grey only if some face is coloured) and whether a
/// `delete` block names it (decided when the face is placed, applied to the whole entry).
struct Collected {
  kernel::PolygonSoup soup;
  std::vector<uint8_t> has_color;
  std::vector<uint8_t> is_deleted;
  int32_t curve_count = 0;
  std::vector<Curve> curves;  // the drawable ones among them, in this collection's frame
  // A pipeline block's result: `soup` already built (lets an incremental entry reuse it).
  std::shared_ptr<const kernel::Mesh> built;
};

/// Appends `part` (already in its own frame) to `out` transformed by `t` (faces reversed
/// when `t` mirrors). Faces get `part`'s colours when `part_colored`, else `color`.
void append_soup(Collected& out, const kernel::PolygonSoup& part, const glm::dmat4& t,
                 const std::optional<glm::vec3>& color, bool part_colored);
/// `append_soup` of a whole collection with the identity transform, in bulk copies.
void append_collected(Collected& out, const Collected& c);
/// Appends a curve through `points` (in the part's frame) transformed by `t`.
void append_curve(Collected& out, std::span<const glm::dvec3> points, bool is_closed, const glm::dmat4& t);
/// Appends `c` transformed by `t`, keeping its colour and deletion flags.
void transform_into(Collected& out, const Collected& c, const glm::dmat4& t);
/// Turns around every face of `out` from `first_face` on (NOME2's instance `reverse`).
void reverse_faces(Collected& out, int32_t first_face);
/// True if vertices `a` and `b` are consecutive in a face of `s`.
bool is_soup_edge(const kernel::PolygonSoup& s, int32_t a, int32_t b);
/// The soup of `c`, its colour array dropped when no face was given a colour.
kernel::PolygonSoup finish(Collected& c);
/// True if `a` equals `b` except for vertex positions (the same faces, sources, colours,
/// names, creases and, for a block's result, the same built topology).
bool same_but_positions(const Collected& a, const Collected& b);

}  // namespace nomec::backend::eval
