// The NOME writer of `--emit nome` (see save.h): source text with slider values replaced.
#include "backend/save.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <fmt/format.h>
#include <map>
#include <vector>

namespace nomec::backend {
namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

/// The number a value token spells, if it is a plain number (`8`, `-0.5`, `7.45e-009`).
std::optional<double> plain_number(std::string_view t) {
  double v = 0;
  auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (ec != std::errc() || p != t.data() + t.size()) return std::nullopt;
  return v;
}

// A flat mesh file's scene as NOME: its vertices as points `v0, v1, …` (global, as NOME
// 2016's saved work names them), one mesh of its faces, instanced once.
std::string flat_scene_text(const ir::Node& n) {
  const ir::FlatMeshData& d = n.as<ir::FlatMeshData>();
  std::string out = fmt::format("# The mesh of `{}`, written out as NOME.\n", n.name);
  if (d.geometry == nullptr) return out;
  const ir::FlatGeometry& g = *d.geometry;
  for (size_t k = 0; k < g.positions.size(); ++k) {
    out += fmt::format("point v{} ({} {} {}) endpoint\n", k, g.positions[k][0], g.positions[k][1], g.positions[k][2]);
  }
  out += fmt::format("mesh {}\n", n.name);
  for (int32_t f = 0; f < g.face_count(); ++f) {
    out += fmt::format("    face f{} (", f);
    for (int32_t i = g.face_starts[static_cast<size_t>(f)]; i < g.face_starts[static_cast<size_t>(f) + 1]; ++i) {
      out += fmt::format("{}v{}", i == g.face_starts[static_cast<size_t>(f)] ? "" : " ", g.corners[static_cast<size_t>(i)]);
    }
    out += ") endface\n";
  }
  out += fmt::format("endmesh\ninstance {} {} endinstance\n", n.name, n.name);
  return out;
}

}  // namespace

std::string to_nome(const ir::Module& module, const SourceManager& sources, std::string_view main_file) {
  // Replacements per file: byte range of a `set` value token -> the current value.
  struct Edit {
    uint32_t begin, end;
    std::string text;
  };
  std::map<int32_t, std::vector<Edit>> edits;
  std::vector<ir::NodeId> params = module.params();
  for (ir::NodeId id : params) {
    const ir::Node& p = module.node(id);
    const double value = module.param(id).value;
    if (!p.range.is_valid()) continue;
    std::string_view text = sources.text(p.range.file);
    // `set NAME value min max step`: the value is the token after the name.
    uint32_t b = p.range.end;
    while (b < text.size() && is_space(text[b])) ++b;
    uint32_t e = b;
    while (e < text.size() && !is_space(text[e])) ++e;
    std::optional<double> written = plain_number(text.substr(b, e - b));
    if (written && *written == value) continue;  // unchanged: keep the text as written
    edits[p.range.file.index].push_back(Edit{b, e, fmt::format("{}", value)});
  }
  // Files in order: the base scene(s) first, the compiled file last.
  std::vector<FileId> files;
  FileId main;
  for (size_t i = 0; i < sources.file_count(); ++i) {
    FileId f{static_cast<int32_t>(i)};
    if (sources.name(f) == main_file) {
      main = f;
    } else {
      files.push_back(f);
    }
  }
  if (main.is_valid()) files.push_back(main);

  std::string out = fmt::format("# Saved by nomec --emit nome from `{}`{}: sliders at their current values.\n",
                                main_file, files.size() > 1 ? " and its base scene" : "");
  // Flat mesh files: the scene's is written as NOME; an included one stays included.
  std::map<int32_t, const ir::Node*> flat_files;
  for (const ir::Node& n : module.nodes) {
    if (n.kind == ir::NodeKind::FlatMesh && n.range.is_valid()) flat_files[n.range.file.index] = &n;
  }
  for (FileId f : files) {
    if (auto flat = flat_files.find(f.index); flat != flat_files.end()) {
      if (!flat->second->as<ir::FlatMeshData>().is_scene) continue;
      if (files.size() > 1) out += fmt::format("\n# ---- from `{}` ----\n", sources.name(f));
      out += flat_scene_text(*flat->second);
      continue;
    }
    std::string_view text = sources.text(f);
    std::vector<Edit>& es = edits[f.index];
    std::sort(es.begin(), es.end(), [](const Edit& a, const Edit& b) { return a.begin < b.begin; });
    if (files.size() > 1) out += fmt::format("\n# ---- from `{}` ----\n", sources.name(f));
    uint32_t at = 0;
    for (const Edit& e : es) {
      out.append(text.substr(at, e.begin - at));
      out += e.text;
      at = e.end;
    }
    out.append(text.substr(at));
    if (!out.empty() && out.back() != '\n') out += '\n';
  }
  // NOME 2016 saved work may set sliders in `savedparameter` blocks, which win over the
  // banks; a final block with every current value wins over those in turn.
  if (module.dialect == Dialect::Nome && !params.empty()) {
    out += "\n# Current slider values (they override any earlier savedparameter block).\nsavedparameter\n";
    for (ir::NodeId id : params) {
      out += fmt::format("    {} {}\n", module.node(id).name, module.param(id).value);
    }
    out += "endsavedparameter\n";
  }
  return out;
}

}  // namespace nomec::backend
