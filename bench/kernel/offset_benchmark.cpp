// Offset scaling: offsets of quad tori, of Möbius bands and of rows of open tubes (many
// border edges, so many ribbons) of growing size, with
// Google Benchmark's complexity fit to check the construction is linear in the size.
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>

#include "bench/kernel/bench_shapes.h"
#include "kernel/offset.h"

namespace nomec::kernel::bench {
namespace {

// An n x 8 Möbius band (half twist at the seam).
PolygonSoup mobius_soup(int n) {
  const int m = 8;
  PolygonSoup s;
  const double pi = std::numbers::pi;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j <= m; ++j) {
      const double u = 2 * pi * i / n, t = double(j) / m - 0.5;
      s.add_vertex({(3 + t * std::cos(u / 2)) * std::cos(u),
                    (3 + t * std::cos(u / 2)) * std::sin(u), t * std::sin(u / 2)});
    }
  }
  auto id = [&](int i, int j) { return i == n ? m - j : i * (m + 1) + j; };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      s.add_face({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return s;
}

// `count` open tubes of 16 x 4 quads side by side: a border edge for every two faces (the
// pipeline scene, bench/pipeline, has one for every 2.3 after subdivision), so the ribbons
// are a large part of the slab.
PolygonSoup tubes_soup(int count) {
  const int ring = 16, rows = 4;
  PolygonSoup s;
  const double pi = std::numbers::pi;
  for (int k = 0; k < count; ++k) {
    const int first = s.vertex_count();
    for (int j = 0; j <= rows; ++j) {
      for (int i = 0; i < ring; ++i) {
        const double u = 2 * pi * i / ring;
        s.add_vertex({3.0 * k + std::cos(u), std::sin(u), 0.5 * j});
      }
    }
    auto id = [&](int i, int j) { return first + j * ring + i % ring; };
    for (int j = 0; j < rows; ++j) {
      for (int i = 0; i < ring; ++i) s.add_face({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return s;
}

void run_offset(benchmark::State& state, const PolygonSoup& soup, bool is_reference = false) {
  auto mesh = build_mesh(soup);
  int64_t faces = 0;
  for (auto _ : state) {
    auto slab = is_reference ? offset_through_builder(*mesh, {.distance = 0.01}) : offset(*mesh, {.distance = 0.01});
    benchmark::DoNotOptimize(slab->mesh.positions().data());
    faces = slab->mesh.face_count();
  }
  state.SetComplexityN(mesh->edge_count());
  state.counters["edges"] = mesh->edge_count();
  // Output faces per second, comparable with the Catmull-Clark benchmarks' `faces_per_s`.
  state.counters["faces_per_s"] = benchmark::Counter(double(faces), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_Offset_Torus(benchmark::State& state) {
  const int n = int(state.range(0));
  run_offset(state, torus_soup(n, n / 2));
}
void BM_Offset_Mobius(benchmark::State& state) {
  run_offset(state, mobius_soup(int(state.range(0))));
}

void BM_Offset_Tubes(benchmark::State& state) { run_offset(state, tubes_soup(int(state.range(0)))); }

// The reference construction (the slab's soup rebuilt by the builder), which `offset`
// replaced by writing the arrays directly: the before/after of one run.
void BM_OffsetThroughBuilder_Torus(benchmark::State& state) {
  const int n = int(state.range(0));
  run_offset(state, torus_soup(n, n / 2), true);
}

// The normals of large meshes are computed on two threads: the CPU column is the whole
// process's CPU time, and the rates (faces_per_s) use the wall time.
BENCHMARK(BM_Offset_Torus)
    ->RangeMultiplier(2)
    ->Range(32, 512)
    ->Complexity(benchmark::oN)
    ->MeasureProcessCPUTime()
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Offset_Mobius)
    ->RangeMultiplier(4)
    ->Range(64, 16384)
    ->Complexity(benchmark::oN)
    ->MeasureProcessCPUTime()
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Offset_Tubes)
    ->RangeMultiplier(8)
    ->Range(64, 4096)
    ->Complexity(benchmark::oN)
    ->MeasureProcessCPUTime()
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OffsetThroughBuilder_Torus)->Arg(512)->MeasureProcessCPUTime()->UseRealTime()->Unit(benchmark::kMillisecond);
void BM_Offset_Smoke(benchmark::State& state) { run_offset(state, torus_soup(8, 6)); }
BENCHMARK(BM_Offset_Smoke);

}  // namespace
}  // namespace nomec::kernel::bench
