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
#include <vector>

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
void streamed(benchmark::State& state, const std::string& target) {
  size_t bytes = 0;
  for (auto _ : state) {
    if (target.empty()) {
      nomec::backend::write_stl_binary(big(), [&](std::string_view piece) {
        benchmark::DoNotOptimize(piece.data());
        bytes += piece.size();
        return true;
      });
      continue;
    }
    nomec::AtomicFileWriter file(target);
    nomec::backend::write_stl_binary(big(), [&](std::string_view piece) {
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

void BM_Smoke(benchmark::State& state) {
  static const std::vector<OutputMesh> small = torus(12, 8);
  render(state, small, [](const std::vector<OutputMesh>& m) { return stl_binary(m) + obj(m); });
}

BENCHMARK(BM_StlBinary)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StlAscii)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Obj)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Ply)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StlBinaryToDevNull)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StlBinaryToFile)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StlBinaryStreamed)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StlBinaryStreamedToDevNull)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StlBinaryStreamedToFile)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Smoke);

}  // namespace

BENCHMARK_MAIN();
