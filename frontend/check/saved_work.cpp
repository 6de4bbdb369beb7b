// The base scene of 2016 saved work (`.anom`; see handlers.h, compat.md §G2). NOME 2016
// applied the file to whatever scene was open, so the base must be guessed. The rule:
//   1. `--base FILE` if given;
//   2. otherwise the sibling scenes (`.nom`, `.nome`) and flat meshes (`.sif`, `.obj`,
//      `.stl`) qualify when their banks define every `savedparameter` name (a flat mesh has
//      no banks: it qualifies when the saved work sets no slider);
//   3. among those, the ones in which the most saved vertex names (`vertex N endvertex` of
//      `consolidate` and `savedworkingmesh`) can resolve: `v<k>` within a flat mesh's
//      vertex count, or in a scene a point's name or a name that starts with an instance's
//      name and `_` or `.`;
//   4. a tie is broken by the file named like the folder, else by being the only one left;
//      when no sibling qualifies (the saved work names stale sliders), the same tie-break
//      picks among the scenes.
// With no base the saved work is checked alone and stays silent about names of the scene.
// A candidate is read only while the most it can score (known from its kind and the saved
// names alone) can still reach the best score read, so a mesh that cannot qualify is never
// parsed; the base scene read counts against the check's input bytes (--max-file-size).
#include <algorithm>
#include <fmt/format.h>
#include <set>

#include "base/input_limits.h"
#include "frontend/check/handlers.h"
#include "frontend/flat/flat.h"
#include "frontend/parse/parse.h"
#include "frontend/source/file_kinds.h"

namespace nomec::check {

namespace {

// What the saved work asks of its base: slider names and vertex names.
struct SavedNeeds {
  std::vector<std::string> params;
  std::vector<std::string> vertices;
};

SavedNeeds needs_of(const ast::Ast& a) {
  SavedNeeds n;
  for (const ast::Stmt& s : a.stmts) {
    if (s.kind == BlockKind::Savedparameter) {
      for (const ast::Item& it : s.items) {
        if (it.kind == ItemKind::Word) n.params.emplace_back(it.text);
      }
    } else if (s.kind == BlockKind::Vertex && s.items.size() == 1 && s.items[0].kind == ItemKind::Word) {
      n.vertices.emplace_back(s.items[0].text);
    }
  }
  return n;
}

// How well a candidate fits: -1 if it lacks a saved slider, else the vertex names it can resolve.
int score_scene(const ast::Ast& a, const SavedNeeds& needs) {
  std::set<std::string> sliders, points, instances;
  for (const ast::Stmt& s : a.stmts) {
    if (s.items.empty() || s.items[0].kind != ItemKind::Word) continue;
    const std::string name(s.items[0].text);
    if (s.kind == BlockKind::Bank) {
      for (size_t i = 1; i + 1 < s.items.size(); ++i) {
        if (s.items[i].kind == ItemKind::Word && s.items[i].text == "set" && s.items[i + 1].kind == ItemKind::Word) {
          sliders.insert(name + "_" + std::string(s.items[i + 1].text));
          sliders.insert(name + "." + std::string(s.items[i + 1].text));
        }
      }
    } else if (s.kind == BlockKind::Point || s.kind == BlockKind::Vertex) {
      points.insert(name);
    } else if (s.kind == BlockKind::Instance) {
      instances.insert(name);
    }
  }
  for (const std::string& p : needs.params) {
    if (!sliders.contains(p)) return -1;
  }
  int score = 0;
  for (std::string v : needs.vertices) {
    while (!v.empty() && (v[0] == '_' || v[0] == '.')) v.erase(0, 1);
    bool ok = points.contains(v);
    for (auto it = instances.begin(); !ok && it != instances.end(); ++it) {
      ok = v.size() > it->size() + 1 && v.compare(0, it->size(), *it) == 0 && (v[it->size()] == '_' || v[it->size()] == '.');
    }
    score += ok ? 1 : 0;
  }
  return score;
}

int score_flat(SourceManager& scratch_sources, const std::string& path, std::string text, const SavedNeeds& needs) {
  if (!needs.params.empty()) return -1;
  DiagnosticEngine scratch;
  FileId f = scratch_sources.add_file(path, std::move(text));
  ir::FlatMeshData d;
  d.geometry = flat::read(scratch_sources, f, *flat::format_of_path(path), scratch);
  return static_cast<int>(std::count_if(needs.vertices.begin(), needs.vertices.end(),
                                        [&](const std::string& v) { return d.vertex_index(v) >= 0; }));
}

// Could `name` be a vertex of some flat mesh (`v0`, `v17`; FlatMeshData::vertex_index)?
bool is_flat_vertex_name(std::string_view name) {
  return name.size() >= 2 && name.size() <= 11 && name[0] == 'v' && (name.size() == 2 || name[1] != '0') &&
         std::all_of(name.begin() + 1, name.end(), [](char ch) { return ch >= '0' && ch <= '9'; });
}

std::optional<std::string> find_base(const std::string& path, const CheckOptions& options, const ast::Ast& saved) {
  if (options.base_file) return options.base_file;
  if (!options.list_folder || !options.read_file) return std::nullopt;
  const size_t slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? "" : path.substr(0, slash == 0 ? 1 : slash);
  std::optional<FolderListing> listing = options.list_folder(dir);
  if (!listing) return std::nullopt;
  auto full = [&](const std::string& name) { return (dir.empty() ? std::string(".") : dir) + "/" + name; };
  const SavedNeeds needs = needs_of(saved);
  // The candidates with the most a file can score, known from its kind alone: a scene every
  // saved vertex name, a flat mesh only the `v<k>` names, and nothing when sliders are
  // saved (it has none). They are read best bound first, and only while their bound can
  // still reach the best score read: a mesh beside saved work that sets sliders is never
  // read, nor one that no saved name can name.
  struct Candidate {
    size_t order;  // in the listing (sorted by name), for the tie-break
    bool is_flat;
    int bound;
  };
  const int flat_bound = needs.params.empty() ? static_cast<int>(std::count_if(needs.vertices.begin(), needs.vertices.end(),
                                                                              [](const std::string& v) { return is_flat_vertex_name(v); }))
                                              : -1;
  std::vector<Candidate> candidates;
  std::vector<std::string> scenes;  // every `.nom`/`.nome`, for the fallback
  for (size_t i = 0; i < listing->files.size(); ++i) {
    const std::string& f = listing->files[i];
    if (is_base_scene_path(f)) scenes.push_back(f);
    const bool is_flat = flat::format_of_path(f).has_value();
    if (!is_base_scene_path(f) && !is_flat) continue;
    const int bound = is_flat ? flat_bound : static_cast<int>(needs.vertices.size());
    if (bound >= 0) candidates.push_back(Candidate{i, is_flat, bound});
  }
  std::stable_sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) { return a.bound > b.bound; });
  int best = -1;
  std::vector<size_t> tied;
  for (const Candidate& cand : candidates) {
    if (cand.bound < best) break;  // neither it nor any after it can reach the best
    const std::string& f = listing->files[cand.order];
    int score = 0;
    if (cand.bound == 0 && needs.params.empty()) {
      score = 0;  // asked for no slider, and no saved name can resolve in it: 0 whatever it holds
    } else {
      std::optional<std::string> text = options.read_file(full(f));
      if (!text) continue;
      SourceManager scratch_sources;
      if (cand.is_flat) {
        score = score_flat(scratch_sources, full(f), std::move(*text), needs);
      } else {
        DiagnosticEngine scratch;
        FileId id = scratch_sources.add_file(full(f), std::move(*text));
        score = score_scene(parse_file(scratch_sources, id, scratch), needs);
      }
    }
    if (score < 0 || score < best) continue;
    if (score > best) tied.clear();
    best = score;
    tied.push_back(cand.order);
  }
  std::sort(tied.begin(), tied.end());
  std::vector<std::string> chosen;
  for (size_t i : tied) chosen.push_back(listing->files[i]);
  // No sibling defines every saved slider (some are stale): the scenes are the candidates.
  if (chosen.empty()) chosen = scenes;
  for (const std::string& c : chosen) {
    if (c.substr(0, c.size() - path_extension(c).size()) == listing->name) return full(c);
  }
  if (chosen.size() == 1) return full(chosen[0]);
  return std::nullopt;
}

}  // namespace

std::unique_ptr<ast::Ast> load_base(Context& c, const std::string& path, const ast::Ast& saved, CheckResult& result) {
  c.is_saved_work = true;
  std::optional<std::string> base = find_base(path, c.options(), saved);
  std::optional<std::string> base_text = base && c.options().read_file ? c.options().read_file(*base) : std::nullopt;
  std::string problem;
  if (base && !base_text && c.options().read_problem) problem = c.options().read_problem(*base);
  // The base scene's text counts with the saved work's against CheckOptions::max_input_bytes
  // (a `.sif` base against max_mesh_bytes).
  const bool mesh = base && is_mesh_file_path(*base);
  int64_t& spent = mesh ? c.mesh_bytes : c.input_bytes;
  const int64_t cap = mesh ? c.options().max_mesh_bytes : c.options().max_input_bytes;
  const int64_t total = spent + (base_text ? static_cast<int64_t>(base_text->size()) : 0);
  if (base_text && total > cap) {
    problem = fmt::format("with it the scene's {} would be {}, more than the {} nomec reads (`{}`)",
                          mesh ? "mesh files" : "text", byte_size_text(total), byte_size_text(cap),
                          mesh ? "--max-mesh-size" : "--max-file-size");
    base_text.reset();
  }
  if (!base_text) {
    c.diags().emit(DiagKind::MissingBaseFile, SourceRange{saved.file, 0, 0},
                   base ? fmt::format("cannot read the base scene `{}`{}: the saved work's vertices cannot be resolved", *base,
                                      problem.empty() ? "" : " (" + problem + ")")
                        : "saved-work file without its base scene: its instance vertices cannot be resolved; pass `--base "
                          "SCENE.nom` (or the `.sif` it was saved over)");
    return nullptr;
  }
  spent = total;
  FileId bf = c.sources().add_file(*base, std::move(*base_text));
  result.base_file = *base;
  c.base_loaded = true;
  DiagnosticEngine base_diags;  // the base file is checked on its own; only its scope is reused
  if (std::optional<ir::FlatFormat> format = flat::format_of_path(*base)) {
    std::swap(base_diags, c.diags());
    add_flat_scene(c, bf, *format);
    std::swap(base_diags, c.diags());
    return nullptr;
  }
  return std::make_unique<ast::Ast>(parse_file(c.sources(), bf, base_diags));
}

}  // namespace nomec::check
