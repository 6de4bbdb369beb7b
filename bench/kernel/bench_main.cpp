// Entry point of bench_kernel: counts heap allocations (for bytes per output face), runs
// the benchmarks, and prints the ours/OpenSubdiv time ratio for every pair of benchmarks
// named `BM_Ours_<case>` / `BM_Osd_<case>` measured in this run.
#include <benchmark/benchmark.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <new>
#include <numbers>
#include <string>
#include <utility>

#include "bench/kernel/bench_shapes.h"
#include "tests/kernel/shapes.h"

namespace {

std::atomic<size_t> g_current{0};
std::atomic<size_t> g_peak{0};
constexpr size_t kHeader = 16;

void* counted_alloc(size_t size) {
  void* raw = std::malloc(size + kHeader);
  if (raw == nullptr) {
    throw std::bad_alloc();
  }
  *static_cast<size_t*>(raw) = size;
  const size_t now = g_current.fetch_add(size, std::memory_order_relaxed) + size;
  size_t peak = g_peak.load(std::memory_order_relaxed);
  while (now > peak && !g_peak.compare_exchange_weak(peak, now, std::memory_order_relaxed)) {
  }
  return static_cast<char*>(raw) + kHeader;
}

void counted_free(void* p) noexcept {
  if (p == nullptr) {
    return;
  }
  void* raw = static_cast<char*>(p) - kHeader;
  g_current.fetch_sub(*static_cast<size_t*>(raw), std::memory_order_relaxed);
  std::free(raw);
}

}  // namespace

void* operator new(size_t size) { return counted_alloc(size); }
void* operator new[](size_t size) { return counted_alloc(size); }
void operator delete(void* p) noexcept { counted_free(p); }
void operator delete[](void* p) noexcept { counted_free(p); }
void operator delete(void* p, size_t) noexcept { counted_free(p); }
void operator delete[](void* p, size_t) noexcept { counted_free(p); }

namespace nomec::kernel::bench {

size_t current_bytes() { return g_current.load(); }
size_t peak_bytes() { return g_peak.load(); }
void reset_peak_bytes() { g_peak.store(g_current.load()); }

PolygonSoup torus_soup(int n, int m) {
  PolygonSoup s;
  const double pi = std::numbers::pi;
  s.positions.reserve(size_t(n) * m);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      const double u = 2 * pi * i / n, v = 2 * pi * j / m;
      s.positions.push_back(
          {(3 + std::cos(v)) * std::cos(u), (3 + std::cos(v)) * std::sin(u), std::sin(v)});
    }
  }
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      const int i1 = (i + 1) % n, j1 = (j + 1) % m;
      s.add_face({i * m + j, i1 * m + j, i1 * m + j1, i * m + j1});
    }
  }
  return s;
}

PolygonSoup mixed_torus_soup(int n, int m) { return testing::mixed_torus_from(torus_soup(n, m), n, m); }

}  // namespace nomec::kernel::bench

namespace {

// Console output plus a ratio table at the end.
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& run : runs) {
      if (run.run_type != Run::RT_Iteration || run.error_occurred) {
        continue;
      }
      std::string name = run.benchmark_name();
      times_[name] = run.GetAdjustedRealTime();
      auto it = run.counters.find("bytes_per_face");
      if (it != run.counters.end()) {
        bytes_[name] = it->second.value;
      }
      auto per_edge = run.counters.find("bytes_per_edge");
      if (per_edge != run.counters.end()) {
        edge_bytes_[name] = per_edge->second.value;
      }
      // Pairs are named by case and regime; drop the run options (e.g. "/min_time:2.000").
      const size_t options = name.find("/min_time");
      if (options != std::string::npos) name.resize(options);
      auto ratio = run.counters.find("ratio");
      if (ratio != run.counters.end()) {
        pair_ratios_[name] = ratio->second.value;
      }
      auto cpu_ratio = run.counters.find("cpu_ratio");
      if (cpu_ratio != run.counters.end()) {
        pair_cpu_ratios_[name] = cpu_ratio->second.value;
      }
      auto fastest = run.counters.find("fastest_ratio");
      if (fastest != run.counters.end()) {
        pair_fastest_ratios_[name] = fastest->second.value;
      }
      auto ns = run.counters.find("ours_ns_face");
      if (ns != run.counters.end()) {
        pair_ns_[name] = {ns->second.value, run.counters.at("osd_ns_face").value};
      }
    }
  }
  void Finalize() override {
    ConsoleReporter::Finalize();
    std::printf(
        "\nours / OpenSubdiv, separate runs (time ratio < 1 means ours is faster; bytes are "
        "peak heap bytes during the refinement per output face / edge)\n");
    for (const auto& [name, ours] : times_) {
      const std::string prefix = "BM_Ours_";
      if (name.rfind(prefix, 0) != 0) {
        continue;
      }
      const std::string rest = name.substr(prefix.size());
      auto osd = times_.find("BM_Osd_" + rest);
      if (osd == times_.end()) {
        continue;
      }
      std::printf(
          "  %-24s time ratio %.3f  peak bytes/face ours %.1f osd %.1f  bytes/edge ours %.1f "
          "osd %.1f\n",
          rest.c_str(), ours / osd->second, bytes_["BM_Ours_" + rest], bytes_["BM_Osd_" + rest],
          edge_bytes_["BM_Ours_" + rest], edge_bytes_["BM_Osd_" + rest]);
    }
    std::printf(
        "interleaved pairs (ours and OpenSubdiv alternating in each iteration; warm: the "
        "allocator reuses mapped memory, cold: fresh pages; cpu = the process's CPU time)\n");
    for (const auto& [name, ratio] : pair_ratios_) {
      const std::string warm = "_warm";
      if (name.size() < warm.size() || name.compare(name.size() - warm.size(), warm.size(), warm) != 0) {
        if (name.find("_cold") == std::string::npos) {
          std::printf("  %-32s time ratio %.3f  cpu time ratio %.3f\n", name.c_str(), ratio,
                      pair_cpu_ratios_[name]);
        }
        continue;
      }
      const std::string base = name.substr(0, name.size() - warm.size());
      const std::string cold = base + "_cold";
      // Wall time per output face, for the pairs against OpenSubdiv.
      auto per_face = [&](const std::string& run) {
        auto it = pair_ns_.find(run);
        if (it != pair_ns_.end()) std::printf(" (ns/face ours %.1f osd %.1f)", it->second.first, it->second.second);
      };
      // The ratio of each side's fastest iteration, for the pairs against OpenSubdiv.
      auto fastest = [&](const std::string& run) {
        auto it = pair_fastest_ratios_.find(run);
        if (it != pair_fastest_ratios_.end()) std::printf(" fastest %.3f", it->second);
      };
      std::printf("  %-26s warm: time ratio %.3f", base.c_str(), ratio);
      fastest(name);
      std::printf(" cpu %.3f", pair_cpu_ratios_[name]);
      per_face(name);
      if (pair_ratios_.count(cold) != 0) {
        std::printf("  cold: time ratio %.3f", pair_ratios_[cold]);
        fastest(cold);
        std::printf(" cpu %.3f", pair_cpu_ratios_[cold]);
        per_face(cold);
      }
      std::printf("\n");
    }
    for (const auto& [name, ratio] : pair_ratios_) {  // a cold run without its warm one
      const std::string cold = "_cold";
      if (name.size() < cold.size() || name.compare(name.size() - cold.size(), cold.size(), cold) != 0) continue;
      if (pair_ratios_.count(name.substr(0, name.size() - cold.size()) + "_warm") != 0) continue;
      std::printf("  %-26s cold: time ratio %.3f cpu %.3f\n", name.substr(0, name.size() - cold.size()).c_str(),
                  ratio, pair_cpu_ratios_[name]);
    }
  }

 private:
  std::map<std::string, double> times_;
  std::map<std::string, double> bytes_;
  std::map<std::string, double> edge_bytes_;
  std::map<std::string, double> pair_ratios_;
  std::map<std::string, double> pair_cpu_ratios_;
  std::map<std::string, double> pair_fastest_ratios_;
  std::map<std::string, std::pair<double, double>> pair_ns_;  // ours, OpenSubdiv
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) {
    return 1;
  }
  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();
  return 0;
}
