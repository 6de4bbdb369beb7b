// The second seed's fractal constructions: Sierpinski (tetrahedron) and Menger (cube) at
// level 3, time and peak heap bytes per output face, each next to our Catmull-Clark
// (builder + one level of `subdivide`) on a quad torus sized to give about the same number
// of output faces.
#include <benchmark/benchmark.h>

#include <cmath>

#include "bench/kernel/bench_shapes.h"
#include "kernel/highgenus.h"
#include "kernel/subdivide.h"
#include "tests/kernel/shapes.h"

namespace nomec::kernel::bench {
namespace {

using testing::tetra_soup;

PolygonSoup cube() {
  PolygonSoup s;
  for (int i = 0; i < 8; ++i) s.add_vertex({double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)});
  s.add_face({0, 2, 3, 1});
  s.add_face({4, 5, 7, 6});
  s.add_face({0, 1, 5, 4});
  s.add_face({2, 6, 7, 3});
  s.add_face({0, 4, 6, 2});
  s.add_face({1, 3, 7, 5});
  return s;
}

Result<Mesh> sierpinski_of(const Mesh& m, int levels) { return sierpinski(m, SierpinskiOptions{levels, 0}); }
Result<Mesh> menger_of(const Mesh& m, int levels) { return menger(m, MengerOptions{levels, 1.0 / 3.0, 0, 0}); }

template <typename Op>
void run_fractal(benchmark::State& state, const PolygonSoup& soup, int levels, Op op) {
  const Mesh input = *build_mesh(soup);
  size_t peak = 0;
  int64_t faces = 0;
  for (auto _ : state) {
    const size_t base = current_bytes();
    reset_peak_bytes();
    auto r = op(input, levels);
    if (!r) {
      state.SkipWithError(r.error().message.c_str());
      return;
    }
    faces = r->face_count();
    benchmark::DoNotOptimize(r->positions().data());
    peak = peak_bytes() - base;
  }
  state.counters["out_faces"] = double(faces);
  state.counters["bytes_per_face"] = double(peak) / double(faces);
  state.counters["ns_per_face"] =
      benchmark::Counter(double(faces), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// One Catmull-Clark level of a quad torus with about `faces` output faces.
void run_cc_like(benchmark::State& state, int64_t faces) {
  const int m = std::max(3, static_cast<int>(std::lround(std::sqrt(double(faces) / 8.0))));
  const int n = std::max(3, static_cast<int>(std::lround(double(faces) / 4.0 / m)));
  const PolygonSoup soup = torus_soup(n, m);
  size_t peak = 0;
  int64_t out = 0;
  for (auto _ : state) {
    const size_t base = current_bytes();
    reset_peak_bytes();
    auto mesh = build_mesh(soup);
    auto r = subdivide(*mesh, {.levels = 1});
    out = r->back().mesh.face_count();
    benchmark::DoNotOptimize(r->back().mesh.positions().data());
    peak = peak_bytes() - base;
  }
  state.counters["out_faces"] = double(out);
  state.counters["bytes_per_face"] = double(peak) / double(out);
  state.counters["ns_per_face"] =
      benchmark::Counter(double(out), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

int64_t faces_of(Result<Mesh> r) { return r ? r->face_count() : 1000; }

void BM_Sierpinski_Tetra_L3(benchmark::State& s) { run_fractal(s, tetra_soup(), 3, sierpinski_of); }
void BM_CatmullClark_LikeSierpinskiL3(benchmark::State& s) {
  static const int64_t faces = faces_of(sierpinski_of(*build_mesh(tetra_soup()), 3));
  run_cc_like(s, faces);
}
void BM_Menger_Cube_L3(benchmark::State& s) { run_fractal(s, cube(), 3, menger_of); }
void BM_CatmullClark_LikeMengerL3(benchmark::State& s) {
  static const int64_t faces = faces_of(menger_of(*build_mesh(cube()), 3));
  run_cc_like(s, faces);
}
void BM_Sierpinski_Smoke_L1(benchmark::State& s) { run_fractal(s, tetra_soup(), 1, sierpinski_of); }
void BM_Menger_Smoke_L1(benchmark::State& s) { run_fractal(s, cube(), 1, menger_of); }

BENCHMARK(BM_Sierpinski_Tetra_L3)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CatmullClark_LikeSierpinskiL3)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Menger_Cube_L3)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CatmullClark_LikeMengerL3)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Sierpinski_Smoke_L1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Menger_Smoke_L1)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace nomec::kernel::bench
