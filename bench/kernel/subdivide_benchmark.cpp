// Catmull-Clark throughput and memory: ours (builder + `subdivide_last_level`, the path of
// the pipeline and of scene `subdivision` blocks: the last level with full winged-edge
// topology, face sources and border loops, intermediate levels freed as it goes) against
// OpenSubdiv (TopologyRefiner factory + RefineUniform + PrimvarRefiner::Interpolate of
// double positions, default options, i.e. without full topology in the last level) on the
// same soup. `BM_OursAllLevels_*` runs `subdivide`, which keeps every level with its
// child→parent maps, for comparison. `BM_Pair/*` runs both alternately, once with the
// allocator handing back memory already mapped and once with fresh pages (`Memory`).
#include <benchmark/benchmark.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <limits>
#include <memory>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "bench/kernel/bench_shapes.h"
#include "kernel/subdivide.h"

namespace nomec::kernel::bench {
namespace {

using namespace OpenSubdiv;

struct Point {
  double p[3];
  void Clear() { p[0] = p[1] = p[2] = 0; }
  void AddWithWeight(const Point& src, double w) {
    p[0] += w * src.p[0];
    p[1] += w * src.p[1];
    p[2] += w * src.p[2];
  }
};

void report(benchmark::State& state, size_t peak, int64_t faces, int64_t edges) {
  state.counters["bytes_per_face"] = double(peak) / double(faces);
  state.counters["bytes_per_edge"] = double(peak) / double(edges);
  state.counters["out_faces"] = double(faces);
  state.counters["faces_per_s"] =
      benchmark::Counter(double(faces), benchmark::Counter::kIsIterationInvariantRate);
}

// Which of our entry points a run measures.
enum class Path { LastLevel, AllLevels };

// One refinement with our kernel; returns the number of output faces (and edges).
int64_t ours_once(const PolygonSoup& soup, int levels, double* bytes_per_edge,
                  int64_t* edges = nullptr, Path path = Path::LastLevel,
                  Threading threading = Threading::Automatic) {
  auto mesh = build_mesh(soup);
  Mesh last_level;
  Result<std::vector<SubdivisionLevel>> all_levels = std::vector<SubdivisionLevel>();
  if (path == Path::LastLevel) {
    last_level = std::move(*subdivide_last_level(std::move(*mesh), {.levels = levels, .threading = threading}));
  } else {
    all_levels = subdivide(*mesh, {.levels = levels, .threading = threading});
  }
  const Mesh& last = path == Path::LastLevel ? last_level : all_levels->back().mesh;
  benchmark::DoNotOptimize(last.positions().data());
  if (bytes_per_edge != nullptr) {
    *bytes_per_edge = double(last.memory_bytes()) / last.edge_count();
  }
  if (edges != nullptr) {
    *edges = last.edge_count();
  }
  return last.face_count();
}

// One refinement with OpenSubdiv; returns the number of output faces (and edges).
int64_t osd_once(const PolygonSoup& soup, int levels, int64_t* edges = nullptr) {
  Far::TopologyDescriptor desc;
  desc.numVertices = soup.vertex_count();
  desc.numFaces = soup.face_count();
  desc.numVertsPerFace = soup.face_sizes.data();
  desc.vertIndicesPerFace = soup.face_vertices.data();
  Sdc::Options sdc;
  sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  std::unique_ptr<Far::TopologyRefiner> refiner(
      Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, sdc)));
  refiner->RefineUniform(Far::TopologyRefiner::UniformOptions(levels));
  std::vector<Point> points(refiner->GetNumVerticesTotal());
  for (int v = 0; v < soup.vertex_count(); ++v) {
    points[v] = {{soup.positions[v].x, soup.positions[v].y, soup.positions[v].z}};
  }
  Far::PrimvarRefinerReal<double> primvar(*refiner);
  Point* src = points.data();
  for (int level = 1; level <= levels; ++level) {
    Point* dst = src + refiner->GetLevel(level - 1).GetNumVertices();
    primvar.Interpolate(level, src, dst);
    src = dst;
  }
  benchmark::DoNotOptimize(points.data());
  if (edges != nullptr) {
    *edges = refiner->GetLevel(levels).GetNumEdges();
  }
  return refiner->GetLevel(levels).GetNumFaces();
}

void run_ours(benchmark::State& state, const PolygonSoup& soup, int levels, Path path = Path::LastLevel) {
  size_t peak = 0;
  int64_t faces = 0;
  int64_t edges = 0;
  double bytes_per_edge = 0;
  for (auto _ : state) {
    const size_t base = current_bytes();
    reset_peak_bytes();
    faces = ours_once(soup, levels, &bytes_per_edge, &edges, path);
    peak = peak_bytes() - base;
  }
  report(state, peak, faces, edges);
  state.counters["mesh_bytes_per_edge"] = bytes_per_edge;
}

void run_osd(benchmark::State& state, const PolygonSoup& soup, int levels) {
  size_t peak = 0;
  int64_t faces = 0;
  int64_t edges = 0;
  for (auto _ : state) {
    const size_t base = current_bytes();
    reset_peak_bytes();
    faces = osd_once(soup, levels, &edges);
    peak = peak_bytes() - base;
  }
  report(state, peak, faces, edges);
}

// CPU time of the whole process (both threads of a level split over two, and kernel time
// on its behalf, e.g. page faults), which other processes on a shared machine disturb far
// less than wall time.
double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

// The state of the C library's allocator a pair is measured in (bench_kernel runs on glibc
// malloc). Both sides' times depend on it more than on the mesh: filling memory the process
// has already mapped ("warm") costs a fraction of filling fresh pages, which the operating
// system must map and clear on first touch ("cold").
enum class Memory { Warm, Cold };

// Warm: large blocks come from the heap instead of their own mappings (`M_MMAP_MAX` 0) and
// the heap is never trimmed, so after one untimed run of each side every array reuses pages
// already mapped. Cold: blocks of 128 KiB and more get their own mapping, unmapped when
// freed, and the heap is trimmed (its free pages handed back) before every timed run, so
// every large array is fresh memory.
void set_memory(Memory memory) {
#if defined(__GLIBC__)
  if (memory == Memory::Warm) {
    mallopt(M_MMAP_MAX, 0);
    mallopt(M_TRIM_THRESHOLD, std::numeric_limits<int>::max());
  } else {
    mallopt(M_MMAP_THRESHOLD, 128 * 1024);
    malloc_trim(0);
  }
#else
  (void)memory;
#endif
}

// glibc's documented defaults (the thresholds then stay fixed instead of adapting).
void restore_memory() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_MAX, 65536);
  mallopt(M_MMAP_THRESHOLD, 128 * 1024);
  mallopt(M_TRIM_THRESHOLD, 128 * 1024);
  malloc_trim(0);
#endif
}

// Each side's total wall and process CPU seconds over the iterations of a pair, and its
// fastest iteration's wall seconds.
struct PairTimes {
  double first = 0, second = 0, first_cpu = 0, second_cpu = 0;
  double first_min = std::numeric_limits<double>::infinity(), second_min = std::numeric_limits<double>::infinity();
};

// Runs `first` and `second` alternately within each iteration, so that load from other
// processes on a shared machine affects both alike, swapping which goes first every
// iteration to cancel allocator-state effects, in the allocator regime `memory`; in the
// warm regime `warm` runs once first, untimed, to map the pages both sides will reuse.
template <typename Warm, typename First, typename Second>
PairTimes alternate(benchmark::State& state, Memory memory, Warm&& warm, First&& first, Second&& second) {
  using Clock = std::chrono::steady_clock;
  set_memory(memory);
  if (memory == Memory::Warm) warm();
  PairTimes t;
  bool is_first_first = true;
  for (auto _ : state) {
    for (int k = 0; k < 2; ++k) {
      const bool is_first = (k == 0) == is_first_first;
#if defined(__GLIBC__)
      if (memory == Memory::Cold) malloc_trim(0);
#endif
      const auto t0 = Clock::now();
      const double c0 = process_cpu_seconds();
      if (is_first) {
        first();
      } else {
        second();
      }
      const double dc = process_cpu_seconds() - c0;
      const double dt = std::chrono::duration<double>(Clock::now() - t0).count();
      (is_first ? t.first : t.second) += dt;
      (is_first ? t.first_cpu : t.second_cpu) += dc;
      double& fastest = is_first ? t.first_min : t.second_min;
      fastest = std::min(fastest, dt);
    }
    is_first_first = !is_first_first;
  }
  restore_memory();
  return t;
}

// Ours and OpenSubdiv alternately (see `alternate`); reports both times, the ratios of wall
// time (`ratio`) and of the process's CPU time (`cpu_ratio`), and each side's wall time per
// output face.
void run_pair(benchmark::State& state, const PolygonSoup& soup, int levels, Memory memory) {
  int64_t faces = 0;
  const PairTimes t = alternate(
      state, memory,
      [&] {
        faces = ours_once(soup, levels, nullptr);
        osd_once(soup, levels);
      },
      [&] { faces = ours_once(soup, levels, nullptr); }, [&] { osd_once(soup, levels); });
  const double n = double(state.iterations());
  state.counters["ours_ms"] = 1e3 * t.first / n;
  state.counters["osd_ms"] = 1e3 * t.second / n;
  state.counters["ratio"] = t.first / t.second;
  state.counters["cpu_ratio"] = t.first_cpu / t.second_cpu;
  // The fastest iteration of each side: on a shared or virtual machine a side's iterations
  // are slowed now and then by what it does not control, and the fastest one is closest to
  // what the code itself costs.
  state.counters["fastest_ratio"] = t.first_min / t.second_min;
  state.counters["ours_ns_face"] = 1e9 * t.first / n / double(faces);
  state.counters["osd_ns_face"] = 1e9 * t.second / n / double(faces);
}

// Ours with the automatic threading and ours on one thread alternately (`ratio` < 1: the
// second thread pays off), in the allocator regime `memory`.
void run_threads_pair(benchmark::State& state, const PolygonSoup& soup, int levels, Memory memory) {
  auto run = [&](Threading threading) { ours_once(soup, levels, nullptr, nullptr, Path::LastLevel, threading); };
  const PairTimes t = alternate(
      state, memory, [&] { run(Threading::OneThread); }, [&] { run(Threading::Automatic); },
      [&] { run(Threading::OneThread); });
  const double n = double(state.iterations());
  state.counters["auto_ms"] = 1e3 * t.first / n;
  state.counters["one_thread_ms"] = 1e3 * t.second / n;
  state.counters["ratio"] = t.first / t.second;
  state.counters["cpu_ratio"] = t.first_cpu / t.second_cpu;
}

const PolygonSoup& torus_2k() {
  static const PolygonSoup s = torus_soup(64, 32);  // 2048 quads
  return s;
}
const PolygonSoup& mixed() {
  static const PolygonSoup s = mixed_torus_soup(48, 24);
  return s;
}
const PolygonSoup& torus_100k() {
  static const PolygonSoup s = torus_soup(400, 250);  // 100000 quads
  return s;
}
const PolygonSoup& small() {
  static const PolygonSoup s = torus_soup(8, 6);
  return s;
}

void BM_Ours_Torus2k_L4(benchmark::State& s) { run_ours(s, torus_2k(), 4); }
void BM_Osd_Torus2k_L4(benchmark::State& s) { run_osd(s, torus_2k(), 4); }
void BM_Ours_Torus2k_L5(benchmark::State& s) { run_ours(s, torus_2k(), 5); }
void BM_Osd_Torus2k_L5(benchmark::State& s) { run_osd(s, torus_2k(), 5); }
void BM_Ours_Mixed_L4(benchmark::State& s) { run_ours(s, mixed(), 4); }
void BM_Osd_Mixed_L4(benchmark::State& s) { run_osd(s, mixed(), 4); }
void BM_Ours_Torus100k_L2(benchmark::State& s) { run_ours(s, torus_100k(), 2); }
void BM_Osd_Torus100k_L2(benchmark::State& s) { run_osd(s, torus_100k(), 2); }
void BM_Ours_Smoke_L2(benchmark::State& s) { run_ours(s, small(), 2); }
void BM_OursAllLevels_Torus2k_L4(benchmark::State& s) { run_ours(s, torus_2k(), 4, Path::AllLevels); }
void BM_OursAllLevels_Torus2k_L5(benchmark::State& s) { run_ours(s, torus_2k(), 5, Path::AllLevels); }
void BM_OursAllLevels_Mixed_L4(benchmark::State& s) { run_ours(s, mixed(), 4, Path::AllLevels); }
void BM_OursAllLevels_Torus100k_L2(benchmark::State& s) { run_ours(s, torus_100k(), 2, Path::AllLevels); }
void BM_OursAllLevels_Smoke_L2(benchmark::State& s) { run_ours(s, small(), 2, Path::AllLevels); }
void BM_Osd_Smoke_L2(benchmark::State& s) { run_osd(s, small(), 2); }

// `BM_Pair/<case>_warm` and `BM_Pair/<case>_cold`: the summary prints both regimes' ratios.
void BM_Pair(benchmark::State& s, const PolygonSoup& (*soup)(), int levels, Memory memory) {
  run_pair(s, soup(), levels, memory);
}

BENCHMARK(BM_Ours_Torus2k_L4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Osd_Torus2k_L4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Ours_Torus2k_L5)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Osd_Torus2k_L5)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Ours_Mixed_L4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Osd_Mixed_L4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Ours_Torus100k_L2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Osd_Torus100k_L2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Ours_Smoke_L2)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Osd_Smoke_L2)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_OursAllLevels_Torus2k_L4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OursAllLevels_Torus2k_L5)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OursAllLevels_Mixed_L4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OursAllLevels_Torus100k_L2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OursAllLevels_Smoke_L2)->Unit(benchmark::kMicrosecond);
// `BM_Threads/<case>_<regime>`: automatic threading against one thread, ours only.
void BM_Threads(benchmark::State& s, const PolygonSoup& (*soup)(), int levels, Memory memory) {
  run_threads_pair(s, soup(), levels, memory);
}
BENCHMARK_CAPTURE(BM_Threads, Torus2k_L4_warm, torus_2k, 4, Memory::Warm)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_CAPTURE(BM_Threads, Torus2k_L4_cold, torus_2k, 4, Memory::Cold)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_CAPTURE(BM_Threads, Torus2k_L5_warm, torus_2k, 5, Memory::Warm)->Unit(benchmark::kMillisecond)->MinTime(3.0);
BENCHMARK_CAPTURE(BM_Threads, Torus2k_L5_cold, torus_2k, 5, Memory::Cold)->Unit(benchmark::kMillisecond)->MinTime(3.0);
BENCHMARK_CAPTURE(BM_Threads, Mixed_L4_warm, mixed, 4, Memory::Warm)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_CAPTURE(BM_Threads, Mixed_L4_cold, mixed, 4, Memory::Cold)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_CAPTURE(BM_Threads, Torus100k_L2_warm, torus_100k, 2, Memory::Warm)->Unit(benchmark::kMillisecond)->MinTime(3.0);
BENCHMARK_CAPTURE(BM_Threads, Torus100k_L2_cold, torus_100k, 2, Memory::Cold)->Unit(benchmark::kMillisecond)->MinTime(3.0);

BENCHMARK_CAPTURE(BM_Pair, Torus2k_L4_warm, torus_2k, 4, Memory::Warm)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_CAPTURE(BM_Pair, Torus2k_L4_cold, torus_2k, 4, Memory::Cold)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_CAPTURE(BM_Pair, Torus2k_L5_warm, torus_2k, 5, Memory::Warm)->Unit(benchmark::kMillisecond)->MinTime(3.0);
BENCHMARK_CAPTURE(BM_Pair, Torus2k_L5_cold, torus_2k, 5, Memory::Cold)->Unit(benchmark::kMillisecond)->MinTime(3.0);
BENCHMARK_CAPTURE(BM_Pair, Mixed_L4_warm, mixed, 4, Memory::Warm)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_CAPTURE(BM_Pair, Mixed_L4_cold, mixed, 4, Memory::Cold)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_CAPTURE(BM_Pair, Torus100k_L2_warm, torus_100k, 2, Memory::Warm)->Unit(benchmark::kMillisecond)->MinTime(3.0);
BENCHMARK_CAPTURE(BM_Pair, Torus100k_L2_cold, torus_100k, 2, Memory::Cold)->Unit(benchmark::kMillisecond)->MinTime(3.0);
BENCHMARK_CAPTURE(BM_Pair, Smoke_L2_warm, small, 2, Memory::Warm)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Pair, Smoke_L2_cold, small, 2, Memory::Cold)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace nomec::kernel::bench
