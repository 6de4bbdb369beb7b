// Faces named by `delete` blocks (see context.h). The checker resolved each entry to an
// instance chain and a face (a mesh's face node, or a generator's face number); a placed
// face is marked when its innermost instances end with that chain, and an entry's marked
// faces are removed at the end, with the kernel where the mesh builds (it also drops the
// edges and vertices left unused and splits vertices left pinched).
#include <algorithm>

#include "backend/eval/context.h"
#include "kernel/edit.h"

namespace nomec::backend::eval {

namespace {

// True if the instances on the walk's chain end with `d`'s (outer instances may be omitted
// in a `delete` entry, as 2016 files do), inside `d`'s group or block if it names one.
bool chain_matches(const Context& c, const ir::DeletedFace& d) {
  size_t k = d.instances.size();  // instances of `d` still to match, from the innermost
  size_t outermost = c.chain.size();  // where the outermost matched instance is on the chain
  for (size_t i = c.chain.size(); i > 0 && k > 0; --i) {
    const ir::NodeId n(c.chain[i - 1]);
    if (c.m.node(n).kind != ir::NodeKind::Instance) continue;
    if (n != d.instances[k - 1]) return false;
    --k;
    outermost = i - 1;
  }
  if (k != 0) return false;
  if (!d.scope.is_valid()) return true;
  // The group or block is on the chain above the instances.
  return std::find(c.chain.begin(), c.chain.begin() + static_cast<ptrdiff_t>(outermost), d.scope.index) !=
         c.chain.begin() + static_cast<ptrdiff_t>(outermost);
}

}  // namespace

void mark_deleted(Context& c, Collected& out, int32_t first_face, ir::NodeId inst) {
  for (const ir::DeletedFace* d : c.deletes) {
    if (d->instances.back() != inst || !chain_matches(c, *d)) continue;
    for (int32_t f = first_face; f < out.soup.face_count(); ++f) {
      const bool hit = d->face.is_valid() ? out.soup.face_sources[f].source_face == d->face.index : f - first_face == d->index;
      if (hit) out.is_deleted[f] = 1;
    }
  }
}

void apply_deletes(Context& c, Collected& in) {
  if (!c.has_deletes()) return;
  if (std::none_of(in.is_deleted.begin(), in.is_deleted.end(), [](uint8_t d) { return d != 0; })) return;
  // Prefer the kernel's deletion on the built mesh. If the full mesh cannot be built (e.g.
  // the deleted face is what made it non-manifold), drop the faces from the soup.
  if (auto full = kernel::build_mesh(in.soup)) {
    std::vector<kernel::FaceId> ids;
    for (int32_t f = 0; f < in.soup.face_count(); ++f) {
      if (in.is_deleted[f]) ids.push_back(kernel::FaceId(f));
    }
    ++c.counters.kernel_ops;
    if (auto del = kernel::delete_faces(*full, ids)) {
      Collected k;
      k.soup = kernel::to_soup(del->mesh);
      k.curve_count = in.curve_count;
      k.curves = std::move(in.curves);
      if (k.soup.face_colors.size() != static_cast<size_t>(k.soup.face_count())) {
        k.soup.face_colors.assign(k.soup.face_count(), kDefaultColor);
      }
      for (kernel::FaceId parent : del->face_parents) {
        k.has_color.push_back(in.has_color[parent.index]);
        k.is_deleted.push_back(0);
      }
      in = std::move(k);
      return;
    }
  }
  Collected k;
  k.soup.positions = in.soup.positions;
  k.soup.names = in.soup.names;
  k.soup.creases = in.soup.creases;
  k.soup.corners = in.soup.corners;
  k.curve_count = in.curve_count;
  k.curves = std::move(in.curves);
  size_t at = 0;
  for (int32_t f = 0; f < in.soup.face_count(); ++f) {
    int32_t n = in.soup.face_sizes[f];
    if (!in.is_deleted[f]) {
      k.soup.add_face(std::span<const int32_t>(in.soup.face_vertices.data() + at, n));
      k.soup.face_sources.push_back(in.soup.face_sources[f]);
      k.soup.face_colors.push_back(in.soup.face_colors[f]);
      k.has_color.push_back(in.has_color[f]);
      k.is_deleted.push_back(0);
    }
    at += n;
  }
  in = std::move(k);
}

}  // namespace nomec::backend::eval
