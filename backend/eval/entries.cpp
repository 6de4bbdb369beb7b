// Scene entries for the evaluator (see context.h): each top-level instance, block, SLIDE
// world group or unplaced saved mesh becomes one output mesh. Incrementally, an entry made
// only of placed parts is patched in place when only positions changed, or assembled from
// the parts' meshes, instead of being built again.
#include <algorithm>

#include "backend/eval/context.h"

namespace nomec::backend::eval {

namespace {

// An update of an entry whose parts all equal the previous evaluation's, in the same
// order, except for the positions of some (a moved instance, a re-subdivided block with
// the same topology): the previous output mesh is copied and only those parts' vertex
// ranges are overwritten, instead of concatenating every part and reassembling the mesh.
// The result is exactly what reassembling gives, since everything but positions is a
// function of the parts' topology. False (nothing done) if there is no previous layout
// or some part differs in more than positions.
bool patch_entry(Context& c, ir::NodeId id, int32_t direct_curves, OutputMesh& out) {
  auto it = c.layouts.find(id.index);
  if (it == c.layouts.end()) return false;
  const EntryLayout& old = it->second;
  if (old.parts.size() != c.entry_parts.size() || old.direct_curves != direct_curves) return false;
  std::vector<uint8_t> changed(c.entry_parts.size(), 0);
  for (size_t i = 0; i < c.entry_parts.size(); ++i) {
    if (c.entry_parts[i].part == old.parts[i]) continue;
    if (!same_but_positions(*c.entry_parts[i].part, *old.parts[i])) return false;
    changed[i] = 1;
  }
  ++c.counters.outputs_patched;
  c.counters.parts_patched += static_cast<int32_t>(std::count(changed.begin(), changed.end(), 1));
  if (old.out.use_count() == 1) {
    // Nobody else holds the previous output (it was made non-const by `entry`): take
    // over its storage instead of copying it.
    out = std::move(const_cast<OutputMesh&>(*old.out));
  } else {
    out = *old.out;
  }
  auto& mesh_positions = kernel::MeshAccess::positions(out.mesh);
  size_t at = 0;
  for (size_t i = 0; i < c.entry_parts.size(); ++i) {
    const std::vector<glm::dvec3>& p = c.entry_parts[i].part->soup.positions;
    if (changed[i]) {
      std::copy(p.begin(), p.end(), out.soup.positions.begin() + static_cast<ptrdiff_t>(at));
      std::copy(p.begin(), p.end(), mesh_positions.begin() + static_cast<ptrdiff_t>(at));
    }
    at += p.size();
  }
  return true;
}

// The mesh of a scene entry made only of placed leaves, as the disjoint union of the
// leaves' meshes (each built once and kept with its placement) instead of building the
// whole entry again; nullopt if a leaf does not build (the caller builds the whole soup
// and reports the error at the right face).
std::optional<kernel::Mesh> assemble(Context& c, const kernel::PolygonSoup& whole) {
  std::vector<const kernel::Mesh*> meshes;
  for (const EntryPart& part : c.entry_parts) {
    if (part.mesh != nullptr) {
      meshes.push_back(part.mesh);
      continue;
    }
    Placement* p = part.placement;
    if (!p->mesh) {
      kernel::PolygonSoup s = p->part->soup;
      if (!s.names.empty()) s.names.resize(s.positions.size());
      auto built = kernel::build_mesh(s);
      if (!built) return std::nullopt;
      p->mesh = std::move(*built);
      // The entry's soup supplies names and colours for the whole union (below).
      kernel::MeshAccess::names(*p->mesh).clear();
      kernel::MeshAccess::face_colors(*p->mesh).clear();
    }
    meshes.push_back(&*p->mesh);
  }
  kernel::Mesh m = kernel::append_disjoint(meshes);
  if (m.vertex_count() != whole.vertex_count() || m.face_count() != whole.face_count()) return std::nullopt;
  // Faces and vertices are in the soup's order, so the soup's attributes apply as they are.
  kernel::MeshAccess::face_colors(m) = whole.face_colors;
  kernel::MeshAccess::face_sources(m).assign(whole.face_sources.begin(), whole.face_sources.end());
  if (whole.face_sources.empty()) kernel::MeshAccess::face_sources(m).assign(whole.face_count(), kernel::FaceSource{});
  kernel::MeshAccess::names(m) = whole.names;
  return m;
}

// Evaluates one scene entry into an output mesh (false if it produced nothing).
bool scene_entry(Context& c, ir::NodeId id, OutputMesh& out) {
  const ir::Node& n = c.m.node(id);
  Collected all;
  // Parts are appended to `c` only when needed: a patched update never copies them.
  Sink sink;
  sink.out = &all;
  sink.is_deferred = c.is_incremental && !c.has_deletes();
  Sink* const saved_sink = c.sink;
  c.sink = c.is_incremental ? &sink : nullptr;
  c.entry_parts.clear();
  Placing at;
  at.path = short_name(n.name);
  if (n.kind == ir::NodeKind::Instance) {
    instance(c, id, glm::dmat4(1.0), std::nullopt, "", all, 0);
  } else if (ir::is_block(n.kind)) {
    block(c, id, at, all, 0);
  } else if (n.kind == ir::NodeKind::Group) {
    // A SLIDE world group (see evaluate_scene).
    target(c, id, at, all, 0);
  } else if (n.kind == ir::NodeKind::Mesh) {
    // A saved consolidated mesh that nothing instances (its vertices are world positions).
    Collected m;
    mesh(c, id, at, m);
    sink.is_pure = false;
    if (c.sink != nullptr) make_eager(c);
    transform_into(all, m, glm::dmat4(1.0));
  } else {
    c.sink = saved_sink;
    return false;
  }
  c.sink = saved_sink;
  c.entry_parts = std::move(sink.parts);
  c.entry_direct_curves = sink.direct_curves;
  const bool can_assemble = c.is_incremental && sink.is_pure && !c.has_deletes() && !c.entry_parts.empty();
  if (sink.is_deferred) {
    c.entry_direct_curves = all.curve_count;
    // Patching copies the previous output and moves its faces' vertices, not its curves.
    const bool has_curves = !all.curves.empty() || std::any_of(c.entry_parts.begin(), c.entry_parts.end(),
                                                                [](const EntryPart& p) { return !p.part->curves.empty(); });
    if (can_assemble && !has_curves && patch_entry(c, id, all.curve_count, out)) {
      c.is_entry_assembled = true;
      return true;
    }
    for (const EntryPart& p : c.entry_parts) append_collected(all, *p.part);
  }
  apply_deletes(c, all);
  out.name = short_name(n.name);
  out.scene_node = id;
  out.curve_count = all.curve_count;
  out.curves = std::move(all.curves);
  if (all.soup.face_count() == 0 && all.curve_count == 0) {
    return false;
  }
  out.soup = finish(all);
  if (can_assemble) {
    if (auto m = assemble(c, out.soup)) {
      out.mesh = std::move(*m);
      c.is_entry_assembled = true;
      return true;
    }
  }
  auto built = kernel::build_mesh(out.soup);
  if (!built) {
    report(c, built.error(), out.soup, n.range, out.name);
    return false;
  }
  out.mesh = std::move(*built);
  return true;
}

}  // namespace

// Scene entry `id` as an output mesh (null if it produced nothing), memoized when
// incremental.
std::shared_ptr<const OutputMesh> entry(Context& c, ir::NodeId id) {
  if (auto it = c.cache.entries.find(id.index); it != c.cache.entries.end()) {
    return it->second.value;
  }
  c.cache.recorder.open();
  c.context = id.index;
  auto m = std::make_shared<OutputMesh>();
  c.is_entry_assembled = false;
  const bool ok = scene_entry(c, id, *m);
  Deps d = c.cache.recorder.close();
  std::shared_ptr<const OutputMesh> out = ok ? std::move(m) : nullptr;
  c.counters.nodes.insert(id.index);
  if (out) c.counters.new_outputs.push_back(out.get());
  if (c.is_incremental) {
    c.cache.entries[id.index] = {out, std::move(d)};
    // The layout an update may patch instead of reassembling (see `patch_entry`).
    if (ok && c.is_entry_assembled) {
      EntryLayout& l = c.layouts[id.index];
      l.out = out;
      l.direct_curves = c.entry_direct_curves;
      l.parts.clear();
      for (const EntryPart& p : c.entry_parts) l.parts.push_back(p.part);
    } else {
      c.layouts.erase(id.index);
    }
  }
  c.entry_parts.clear();
  return out;
}

}  // namespace nomec::backend::eval
