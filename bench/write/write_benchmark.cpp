// Writer throughput: every output format rendered from a quad torus of 160,000 faces
// (320,000 triangles), reported as bytes per second of output. `ToDevNull` and `ToFile` add
// the write itself (fwrite to /dev/null; the atomic writer to a file in the temporary
// directory), so the ratio of the two to the in-memory figure says whether formatting or
// the disk limits writing.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <span>
#include <functional>
#include <vector>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include <iterator>

#include "backend/write.h"
#include "base/file_io.h"

namespace {

using nomec::backend::OutputMesh;

std::vector<OutputMesh> torus(int n, int m) {
  std::vector<OutputMesh> out(1);
  out[0].name = "torus";
  nomec::kernel::PolygonSoup& s = out[0].soup;
  for (int i = 0; i < n; ++i) {
    const double u = 2 * M_PI * i / n;
    for (int j = 0; j < m; ++j) {
      const double v = 2 * M_PI * j / m;
      s.add_vertex({(2 + 0.7 * std::cos(v)) * std::cos(u), (2 + 0.7 * std::cos(v)) * std::sin(u), 0.7 * std::sin(v)},
                   "");
    }
  }
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      const int32_t a = i * m + j, b = ((i + 1) % n) * m + j, c = ((i + 1) % n) * m + (j + 1) % m,
                    d = i * m + (j + 1) % m;
      s.add_face({a, b, c, d});
    }
  }
  return out;
}

const std::vector<OutputMesh>& big() {
  static const std::vector<OutputMesh> t = torus(400, 400);
  return t;
}

template <typename F>
void render(benchmark::State& state, const std::vector<OutputMesh>& meshes, F to) {
  size_t bytes = 0;
  for (auto _ : state) {
    std::string s = to(meshes);
    bytes += s.size();
    benchmark::DoNotOptimize(s.data());
  }
  state.SetBytesProcessed(static_cast<int64_t>(bytes));
}

auto stl_binary = [](const std::vector<OutputMesh>& m) { return nomec::backend::to_stl_binary(m); };
auto stl_ascii = [](const std::vector<OutputMesh>& m) { return nomec::backend::to_stl_ascii(m); };
auto obj = [](const std::vector<OutputMesh>& m) { return nomec::backend::to_obj(m, ""); };
auto ply = [](const std::vector<OutputMesh>& m) { return nomec::backend::to_ply(m); };

void BM_StlBinary(benchmark::State& state) { render(state, big(), stl_binary); }
void BM_StlAscii(benchmark::State& state) { render(state, big(), stl_ascii); }
void BM_Obj(benchmark::State& state) { render(state, big(), obj); }
void BM_Ply(benchmark::State& state) { render(state, big(), ply); }

// The text writers as they were before number_text.h (fmt through a back inserter, every
// triangle's three points formatted anew): a reference measured in the same run.
std::string stl_ascii_fmt(const std::vector<OutputMesh>& meshes) {
  std::string out;
  for (const OutputMesh& m : meshes) {
    fmt::format_to(std::back_inserter(out), "solid {}\n", m.name);
    const nomec::kernel::PolygonSoup& s = m.soup;
    size_t at = 0;
    for (int32_t f = 0; f < s.face_count(); ++f) {
      const int32_t* v = s.face_vertices.data() + at;
      for (int32_t i = 1; i + 1 < s.face_sizes[f]; ++i) {
        const glm::dvec3 &a = s.positions[v[0]], &b = s.positions[v[i]], &c = s.positions[v[i + 1]];
        const glm::dvec3 n = glm::normalize(glm::cross(b - a, c - a));
        fmt::format_to(std::back_inserter(out), "  facet normal {:e} {:e} {:e}\n    outer loop\n", n.x + 0.0, n.y + 0.0,
                       n.z + 0.0);
        for (const glm::dvec3* p : {&a, &b, &c}) {
          fmt::format_to(std::back_inserter(out), "      vertex {:e} {:e} {:e}\n", p->x + 0.0, p->y + 0.0, p->z + 0.0);
        }
        out += "    endloop\n  endfacet\n";
      }
      at += static_cast<size_t>(s.face_sizes[f]);
    }
    fmt::format_to(std::back_inserter(out), "endsolid {}\n", m.name);
  }
  return out;
}

std::string obj_fmt(const std::vector<OutputMesh>& meshes) {
  std::string out = "# written by nomec\n";
  int64_t base = 1;
  for (const OutputMesh& m : meshes) {
    const nomec::kernel::PolygonSoup& s = m.soup;
    fmt::format_to(std::back_inserter(out), "o {}\n", m.name);
    for (const glm::dvec3& p : s.positions) fmt::format_to(std::back_inserter(out), "v {} {} {}\n", p.x + 0.0, p.y + 0.0, p.z + 0.0);
    size_t at = 0;
    for (int32_t f = 0; f < s.face_count(); ++f) {
      out += "f";
      for (int32_t i = 0; i < s.face_sizes[f]; ++i) fmt::format_to(std::back_inserter(out), " {}", base + s.face_vertices[at + i]);
      out += "\n";
      at += static_cast<size_t>(s.face_sizes[f]);
    }
    base += s.vertex_count();
  }
  return out;
}

void BM_StlAsciiFmtReference(benchmark::State& state) { render(state, big(), stl_ascii_fmt); }
void BM_ObjFmtReference(benchmark::State& state) { render(state, big(), obj_fmt); }

// A text format rendered and written to a file through the atomic writer.
template <typename F>
void text_to_file(benchmark::State& state, F to, const char* name) {
  const char* tmp = std::getenv("TMPDIR");
  const std::string path = std::string(tmp != nullptr ? tmp : "/tmp") + "/" + name;
  size_t bytes = 0;
  for (auto _ : state) {
    std::string s = to(big());
    const std::string error = nomec::write_file_atomically(path, s);
    if (!error.empty()) state.SkipWithError(error.c_str());
    bytes += s.size();
  }
  std::remove(path.c_str());
  state.SetBytesProcessed(static_cast<int64_t>(bytes));
}
void BM_StlAsciiToFile(benchmark::State& state) { text_to_file(state, stl_ascii, "nomec_bench_write_ascii.stl"); }
void BM_ObjToFile(benchmark::State& state) { text_to_file(state, obj, "nomec_bench_write.obj"); }

void BM_StlBinaryToDevNull(benchmark::State& state) {
  size_t bytes = 0;
  std::FILE* f = std::fopen("/dev/null", "wb");
  for (auto _ : state) {
    std::string s = nomec::backend::to_stl_binary(big());
    std::fwrite(s.data(), 1, s.size(), f);
    bytes += s.size();
  }
  std::fclose(f);
  state.SetBytesProcessed(static_cast<int64_t>(bytes));
}

void BM_StlBinaryToFile(benchmark::State& state) {
  const char* tmp = std::getenv("TMPDIR");
  const std::string path = std::string(tmp != nullptr ? tmp : "/tmp") + "/nomec_bench_write.stl";
  size_t bytes = 0;
  for (auto _ : state) {
    std::string s = nomec::backend::to_stl_binary(big());
    const std::string error = nomec::write_file_atomically(path, s);
    if (!error.empty()) state.SkipWithError(error.c_str());
    bytes += s.size();
  }
  std::remove(path.c_str());
  state.SetBytesProcessed(static_cast<int64_t>(bytes));
}

// The streamed writer `nomec --emit stl` uses: pieces of about a megabyte, formatted into
// one reused buffer, dropped (formatting alone), written to /dev/null, or written to a
// file through the atomic writer; the whole file is never in memory.
using PieceWriter = bool (*)(std::span<const OutputMesh>, const std::function<bool(std::string_view)>&);
void streamed(benchmark::State& state, const std::string& target, bool is_overlapped = false,
              PieceWriter text_writer = nullptr) {
  size_t bytes = 0;
  PieceWriter write = is_overlapped ? nomec::backend::write_stl_binary_overlapped : nomec::backend::write_stl_binary;
  if (text_writer != nullptr) write = text_writer;
  for (auto _ : state) {
    if (target.empty()) {
      write(big(), [&](std::string_view piece) {
        benchmark::DoNotOptimize(piece.data());
        bytes += piece.size();
        return true;
      });
      continue;
    }
    nomec::AtomicFileWriter file(target);
    write(big(), [&](std::string_view piece) {
      bytes += piece.size();
      return file.append(piece);
    });
    const std::string error = file.commit();
    if (!error.empty()) state.SkipWithError(error.c_str());
  }
  state.SetBytesProcessed(static_cast<int64_t>(bytes));
}

void BM_StlBinaryStreamed(benchmark::State& state) { streamed(state, ""); }
void BM_StlBinaryStreamedToDevNull(benchmark::State& state) { streamed(state, "/dev/null"); }
void BM_StlBinaryStreamedToFile(benchmark::State& state) {
  const char* tmp = std::getenv("TMPDIR");
  const std::string path = std::string(tmp != nullptr ? tmp : "/tmp") + "/nomec_bench_write_streamed.stl";
  streamed(state, path);
  std::remove(path.c_str());
}

// The same with the sink on a second thread (`write_stl_binary_overlapped`, what `nomec
// --emit stl` uses): formatting and writing overlap when both cores are free.
void BM_StlBinaryOverlappedToDevNull(benchmark::State& state) { streamed(state, "/dev/null", true); }
void BM_StlBinaryOverlappedToFile(benchmark::State& state) {
  const char* tmp = std::getenv("TMPDIR");
  const std::string path = std::string(tmp != nullptr ? tmp : "/tmp") + "/nomec_bench_write_overlapped.stl";
  streamed(state, path, true);
  std::remove(path.c_str());
}

// The text formats streamed the same way (`write_stl_ascii`, `write_obj`: what `nomec
// --emit stl --stl-ascii` and `--emit obj` use): formatting alone, to /dev/null, to a file.
bool obj_pieces(std::span<const OutputMesh> m, const std::function<bool(std::string_view)>& sink) {
  return nomec::backend::write_obj(m, "", sink);
}
std::string temp_path(const char* name) {
  const char* tmp = std::getenv("TMPDIR");
  return std::string(tmp != nullptr ? tmp : "/tmp") + "/" + name;
}
void BM_StlAsciiStreamed(benchmark::State& state) { streamed(state, "", false, nomec::backend::write_stl_ascii); }
void BM_StlAsciiStreamedToDevNull(benchmark::State& state) {
  streamed(state, "/dev/null", false, nomec::backend::write_stl_ascii);
}
void BM_StlAsciiStreamedToFile(benchmark::State& state) {
  const std::string path = temp_path("nomec_bench_write_streamed_ascii.stl");
  streamed(state, path, false, nomec::backend::write_stl_ascii);
  std::remove(path.c_str());
}
void BM_ObjStreamed(benchmark::State& state) { streamed(state, "", false, obj_pieces); }
void BM_ObjStreamedToDevNull(benchmark::State& state) { streamed(state, "/dev/null", false, obj_pieces); }
void BM_ObjStreamedToFile(benchmark::State& state) {
  const std::string path = temp_path("nomec_bench_write_streamed.obj");
  streamed(state, path, false, obj_pieces);
  std::remove(path.c_str());
}

void BM_Smoke(benchmark::State& state) {
  static const std::vector<OutputMesh> small = torus(12, 8);
  render(state, small, [](const std::vector<OutputMesh>& m) { return stl_binary(m) + obj(m); });
}

BENCHMARK(BM_StlBinary)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StlAscii)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Obj)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Ply)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StlAsciiFmtReference)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ObjFmtReference)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StlAsciiToFile)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ObjToFile)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StlBinaryToDevNull)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StlBinaryToFile)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StlBinaryStreamed)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StlBinaryStreamedToDevNull)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StlBinaryStreamedToFile)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StlBinaryOverlappedToDevNull)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_StlBinaryOverlappedToFile)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_StlAsciiStreamed)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StlAsciiStreamedToDevNull)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StlAsciiStreamedToFile)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ObjStreamed)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ObjStreamedToDevNull)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ObjStreamedToFile)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Smoke);

}  // namespace

BENCHMARK_MAIN();
