// `nomec --emit stl|obj|ply|summary` (see emit.h): evaluate, run the whole-scene pipeline,
// encode and write atomically, with a progress line on a terminal.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fmt/format.h>
#include <iostream>
#include <unistd.h>

#include "backend/summary.h"
#include "backend/write.h"
#include "base/file_io.h"
#include "lsp/summary_json.h"
#include "tools/emit.h"

namespace nomec::tools {

namespace {

namespace be = backend;

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// The file's bytes in the requested format, and the companion `.mtl` of a coloured OBJ.
struct Encoded {
  std::string content;
  std::string mtl;
};

Encoded encode(const Cli& cli, const std::string& path, const std::string& target, const std::vector<be::OutputMesh>& meshes) {
  Encoded e;
  if (cli.emit == "stl") {
    e.content = cli.stl_ascii ? be::to_stl_ascii(meshes) : be::to_stl_binary(meshes);
  } else if (cli.emit == "ply") {
    e.content = be::to_ply(meshes);
  } else if (cli.emit == "summary") {
    std::vector<be::MeshSummary> s;
    for (const auto& m : meshes) s.push_back(be::summarize(m));
    e.content = lsp::summary_json(path, s).dump(2) + "\n";
  } else {
    const bool colored = std::any_of(meshes.begin(), meshes.end(),
                                     [](const be::OutputMesh& m) { return !m.soup.face_colors.empty(); });
    std::string mtl_name;
    if (target != "-" && colored) {
      mtl_name = std::filesystem::path(target).stem().string() + ".mtl";
      e.mtl = be::to_mtl(meshes);
    }
    e.content = be::to_obj(meshes, mtl_name);
  }
  return e;
}

// Writes `e` to `target` (`-`: standard output); false after printing the error.
bool write(const std::string& target, const Encoded& e) {
  if (target == "-") {
    std::cout.write(e.content.data(), static_cast<std::streamsize>(e.content.size()));
    std::cout.flush();
    return true;
  }
  std::string err = write_file_atomically(target, e.content);
  if (err.empty() && !e.mtl.empty()) {
    err = write_file_atomically(std::filesystem::path(target).replace_extension(".mtl").string(), e.mtl);
  }
  if (err.empty()) return true;
  std::cerr << fmt::format("nomec: {}\n", err);
  return false;
}

// Binary STL straight to `target` a piece at a time (it is the format of large models: a
// whole-scene offset easily makes hundreds of megabytes); false after printing the error.
bool write_stl_streamed(const std::string& target, const std::vector<be::OutputMesh>& meshes) {
  if (target == "-") {
    be::write_stl_binary(meshes, [](std::string_view piece) {
      std::cout.write(piece.data(), static_cast<std::streamsize>(piece.size()));
      return static_cast<bool>(std::cout);
    });
    std::cout.flush();
    return true;
  }
  AtomicFileWriter file(target);
  be::write_stl_binary(meshes, [&](std::string_view piece) { return file.append(piece); });
  std::string err = file.commit();
  if (err.empty()) return true;
  std::cerr << fmt::format("nomec: {}\n", err);
  return false;
}

}  // namespace

int emit_meshes(const Cli& cli, const std::string& path, const SourceManager& sources, const ir::Module& module,
                double check_ms, DiagnosticOutput& out) {
  const bool progress = isatty(STDERR_FILENO) != 0;
  auto say = [&](std::string_view stage) {
    if (progress) std::cerr << fmt::format("\r\033[Knomec: {}: {}…", path, stage) << std::flush;
  };
  be::StageTimings timings;
  DiagnosticEngine geo;
  say("evaluate");
  std::vector<be::OutputMesh> meshes = be::evaluate_scene(module, geo, &timings, cli.pipeline.max_vertices);
  if (geo.error_count() == 0 && cli.pipeline.any()) {
    const std::string stem = std::filesystem::path(path).stem().string();
    const SourceRange where = module.scene.empty() ? SourceRange{} : module.node(module.scene.front()).range;
    meshes = be::run_pipeline(std::move(meshes), cli.pipeline, stem, where, geo, &timings, say);
  }
  if (progress) std::cerr << "\r\033[K" << std::flush;
  geo.sort_and_dedupe();
  out.show(sources, geo);
  if (geo.error_count() > 0) return geo.error_count();
  const auto write_start = std::chrono::steady_clock::now();
  std::string target = cli.output;
  if (target.empty()) {
    target = cli.emit == "summary" ? "-" : std::filesystem::path(path).stem().string() + "." + cli.emit;
  }
  const bool is_streamed = cli.emit == "stl" && !cli.stl_ascii;
  const int failed = (is_streamed ? write_stl_streamed(target, meshes) : write(target, encode(cli, path, target, meshes))) ? 0 : 1;
  if (cli.time_report) {
    const double write_ms = ms_since(write_start);
    const double total = check_ms + timings.evaluate_ms + timings.merge_ms + timings.subdivide_ms + timings.offset_ms + write_ms;
    std::cerr << fmt::format(
        "time report for {} (ms):\n  parse+check {:10.2f}\n  evaluate    {:10.2f}\n  merge       {:10.2f}\n"
        "  subdivide   {:10.2f}\n  offset      {:10.2f}\n  write       {:10.2f}\n  total       {:10.2f}\n",
        path, check_ms, timings.evaluate_ms, timings.merge_ms, timings.subdivide_ms, timings.offset_ms, write_ms,
        total);
  }
  return failed;
}

}  // namespace nomec::tools
