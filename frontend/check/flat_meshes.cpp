// Flat mesh files in a scene (see handlers.h; language.md §8, compat.md §G1): a `.sif`,
// `.obj` or `.stl` file read by frontend/flat becomes a `FlatMesh` node named after the
// file's stem (`Zero_6` for `zero/Zero_6.sif`). Given to nomec itself, or as the base scene
// of saved work, the file is a scene of that one mesh, instanced once under the same name;
// its vertices are then also reachable by their bare names `v0, v1, …`, as in NOME 2016,
// whose flat input became the master mesh itself. `include "file.sif"` in a NOME file
// defines the mesh for the file to `instance`.
#include <algorithm>
#include <cctype>
#include <fmt/format.h>

#include "frontend/check/handlers.h"
#include "frontend/flat/flat.h"

namespace nomec::check {

namespace {

std::string stem_of(std::string_view path) {
  const size_t slash = path.find_last_of('/');
  std::string_view name = slash == std::string_view::npos ? path : path.substr(slash + 1);
  const size_t dot = name.rfind('.');
  if (dot != std::string_view::npos && dot > 0) name = name.substr(0, dot);
  return std::string(name);
}

}  // namespace

ir::NodeId add_flat_mesh(Context& c, FileId file, ir::FlatFormat format, SourceRange name_range, std::string name) {
  ir::Module& m = c.module();
  const std::string_view path = c.sources().name(file);
  if (name.empty()) name = stem_of(path);
  ir::NodeId id = m.add_node(ir::NodeKind::FlatMesh, ir::flat_format_name(format), name, SourceRange{file, 0, 0});
  ir::FlatMeshData& d = m.get<ir::FlatMeshData>(id);
  d.format = format;
  d.geometry = flat::read(c.sources(), file, format, c.diags(), flat::ReadOptions{c.options().sif_quads});
  define(c, Ns::Shape, name, Symbol{id, name_range.is_valid() ? name_range : SourceRange{file, 0, 0}, c.order, "flat mesh"});
  return id;
}

void add_flat_scene(Context& c, FileId file, ir::FlatFormat format) {
  ir::Module& m = c.module();
  ir::NodeId mesh = add_flat_mesh(c, file, format, SourceRange{});
  m.get<ir::FlatMeshData>(mesh).is_scene = true;
  const std::string name = m.node(mesh).name;
  ir::NodeId inst = m.add_node(ir::NodeKind::Instance, "instance", name, SourceRange{file, 0, 0});
  m.get<ir::InstanceData>(inst).target = mesh;
  m.deps.add_edge(mesh, inst);
  c.instance_scopes[0][name] = inst;
  m.scene.push_back(inst);
  c.flat_scene = inst;
}

namespace {

// The quoted path of `include "…"` (the whole item if it has no quotes).
SourceRange path_range(Context& c, const ast::Item& it) {
  const std::string_view t = c.sources().text(it.range);
  const size_t open = t.find('"');
  const size_t close = t.rfind('"');
  if (open == std::string_view::npos || close <= open) return it.range;
  return SourceRange{it.range.file, it.range.begin + static_cast<uint32_t>(open), it.range.begin + static_cast<uint32_t>(close + 1)};
}

}  // namespace

bool include_flat(Context& c, const std::string& path, const std::string& rel, const ast::Item& it) {
  std::optional<ir::FlatFormat> format = flat::format_of_path(path);
  if (!format) return false;
  IncludeRead read = read_include(c, path, rel, it);
  if (!read.text) {
    if (!read.is_stopped) {
      c.diags().emit(DiagKind::IncludeFailed, path_range(c, it),
                     fmt::format("cannot read included mesh file `{}` (looked for `{}`){}", rel, path,
                                 read.problem.empty() ? "" : ": " + read.problem));
    }
    // The mesh is still defined (empty), so its instances do not add errors of their own.
    const std::string name = stem_of(path);
    if (!c.scopes[static_cast<int>(Ns::Shape)].contains(name)) {
      ir::NodeId id = c.module().add_node(ir::NodeKind::FlatMesh, ir::flat_format_name(*format), name, SourceRange{});
      c.module().get<ir::FlatMeshData>(id).format = *format;
      c.module().get<ir::FlatMeshData>(id).geometry = std::make_shared<const ir::FlatGeometry>();
      define(c, Ns::Shape, name, Symbol{id, it.range, c.order, "flat mesh"});
    }
    return true;
  }
  std::optional<std::string>& text = read.text;
  const std::string name = stem_of(path);
  const bool is_name = !name.empty() && (std::isalpha(static_cast<unsigned char>(name[0])) || name[0] == '_') &&
                       std::all_of(name.begin(), name.end(), [](char ch) {
                         return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '.';
                       });
  if (!is_name) {
    c.diags().emit(DiagKind::IncludeFailed, path_range(c, it),
                   fmt::format("`include \"{}\"` would define a mesh named `{}`, which is not a NOME name (letters, digits, "
                               "`_`, starting with a letter or `_`); rename the file",
                               rel, name));
    return true;
  }
  FileId f = c.sources().add_file(path, std::move(*text));
  if (auto prev = c.scopes[static_cast<int>(Ns::Shape)].find(name); prev != c.scopes[static_cast<int>(Ns::Shape)].end()) {
    c.diags()
        .emit(DiagKind::DuplicateDefinition, it.range,
              fmt::format("`include \"{}\"` defines the mesh `{}`, and `{}` is already defined as a {}", rel, name, name,
                          prev->second.keyword))
        .note(prev->second.range, "previous definition is here");
    return true;
  }
  add_flat_mesh(c, f, *format, it.range);
  return true;
}

ir::VertexRef flat_scene_vertex(Context& c, std::string_view text, SourceRange use) {
  ir::VertexRef ref;
  if (!c.flat_scene.is_valid()) return ref;
  const ir::Module& m = c.module();
  const ir::NodeId mesh = m.get<ir::InstanceData>(c.flat_scene).target;
  if (m.get<ir::FlatMeshData>(mesh).vertex_index(text) < 0) return ref;
  ref.text.assign(text);
  ref.range = use;
  ref.instances = {c.flat_scene};
  ref.vertex.assign(text);
  return ref;
}

}  // namespace nomec::check
