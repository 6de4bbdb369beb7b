// `nomec --emit stl|obj|ply|summary` (see emit.h): refuse an output that is an input,
// evaluate, run the whole-scene pipeline, encode and write atomically, with a progress
// line on a terminal.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <functional>
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

// The file's bytes for the formats written whole (PLY, the summary); STL and OBJ are
// streamed (`write_mesh_streamed`).
std::string encode(const Cli& cli, const std::string& path, const std::vector<be::OutputMesh>& meshes) {
  if (cli.emit == "ply") return be::to_ply(meshes);
  std::vector<be::MeshSummary> s;
  for (const auto& m : meshes) s.push_back(be::summarize(m));
  return lsp::summary_json(path, s).dump(2) + "\n";
}

// Writes `content` to `target` (`-`: standard output); false after printing the error.
bool write(const std::string& target, const std::string& content) {
  if (target == "-") {
    std::cout.write(content.data(), static_cast<std::streamsize>(content.size()));
    std::cout.flush();
    return true;
  }
  const std::string err = write_file_atomically(target, content);
  if (err.empty()) return true;
  std::cerr << fmt::format("nomec: {}\n", err);
  return false;
}

// A writer that hands its text to a sink a piece at a time (`be::write_stl_binary` and
// the like).
using PieceWriter = std::function<bool(const std::function<bool(std::string_view)>&)>;

// STL and OBJ straight to `target` a piece at a time (they are the formats of large
// models: a whole-scene offset easily makes hundreds of megabytes), then the OBJ's `mtl`
// when not empty; false after printing the error.
bool write_streamed(const std::string& target, const PieceWriter& writer, const std::string& mtl = {}) {
  if (target == "-") {
    const bool written = writer([](std::string_view piece) {
      std::cout.write(piece.data(), static_cast<std::streamsize>(piece.size()));
      return static_cast<bool>(std::cout);
    });
    std::cout.flush();
    return written;
  }
  AtomicFileWriter file(target);
  bool is_sink_ok = true;
  const bool written = writer([&](std::string_view piece) { return is_sink_ok = file.append(piece); });
  if (!written && is_sink_ok) {
    // The writer refused the meshes before writing (check_coordinates said why): the
    // temporary file goes, and an existing output stays as it was.
    std::cerr << fmt::format("nomec: {}: not written\n", target);
    return false;
  }
  std::string err = file.commit();
  if (err.empty() && !mtl.empty()) {
    err = write_file_atomically(std::filesystem::path(target).replace_extension(".mtl").string(), mtl);
  }
  if (err.empty()) return true;
  std::cerr << fmt::format("nomec: {}\n", err);
  return false;
}

// Writes `meshes` as STL (binary or ASCII) or OBJ with its MTL, streamed.
bool write_mesh_streamed(const Cli& cli, const std::string& target, const std::vector<be::OutputMesh>& meshes) {
  if (cli.emit == "stl") {
    return write_streamed(target, [&](const auto& sink) {
      return cli.stl_ascii ? be::write_stl_ascii(meshes, sink) : be::write_stl_binary(meshes, sink);
    });
  }
  const bool colored = std::any_of(meshes.begin(), meshes.end(),
                                   [](const be::OutputMesh& m) { return !m.soup.face_colors.empty(); });
  std::string mtl_name;
  std::string mtl;
  if (target != "-" && colored) {
    mtl_name = std::filesystem::path(target).stem().string() + ".mtl";
    mtl = be::to_mtl(meshes);
  }
  return write_streamed(target, [&](const auto& sink) { return be::write_obj(meshes, mtl_name, sink); }, mtl);
}

}  // namespace

int emit_meshes(const Cli& cli, const std::string& path, const SourceManager& sources, const ir::Module& module,
                const std::vector<std::string>& inputs, double check_ms, DiagnosticOutput& out) {
  // The output (and an OBJ's MTL beside it) must not be a file the check read: refused
  // before anything is built.
  std::string target = cli.output;
  if (target.empty()) {
    target = cli.emit == "summary" ? "-" : std::filesystem::path(path).stem().string() + "." + cli.emit;
  }
  std::string problem = output_is_input(target, inputs);
  if (problem.empty() && cli.emit == "obj" && target != "-") {
    problem = output_is_input(std::filesystem::path(target).replace_extension(".mtl").string(), inputs);
  }
  if (!problem.empty()) {
    std::cerr << fmt::format("nomec: {}\n", problem);
    return 1;
  }
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
    be::PipelineOptions pipeline = cli.pipeline;
    // Binary STL is written from the meshes (write_stl_binary), so their polygon lists,
    // copies of every output face, are not made.
    pipeline.polygon_lists = !(cli.emit == "stl" && !cli.stl_ascii);
    meshes = be::run_pipeline(std::move(meshes), pipeline, stem, where, geo, &timings, say);
  }
  if (progress) std::cerr << "\r\033[K" << std::flush;
  if (geo.error_count() == 0) {
    // The last check: no infinity or NaN (nor, in binary STL, a number past 32-bit floats).
    be::check_coordinates(meshes, module,
                          cli.emit == "stl" && !cli.stl_ascii ? be::kMaxStlBinaryCoordinate : be::kMaxTextCoordinate, geo);
  }
  geo.sort_and_dedupe();
  out.show(sources, geo);
  if (geo.error_count() > 0) return geo.error_count();
  const auto write_start = std::chrono::steady_clock::now();
  const bool is_streamed = cli.emit == "stl" || cli.emit == "obj";
  const int failed =
      (is_streamed ? write_mesh_streamed(cli, target, meshes) : write(target, encode(cli, path, meshes))) ? 0 : 1;
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
