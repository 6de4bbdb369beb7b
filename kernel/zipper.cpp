// Automatic zippering by dynamic programming over rungs (see zipper.h).
#include "kernel/zipper.h"

#include <algorithm>
#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <limits>

namespace nomec::kernel {
namespace {

enum class Step : uint8_t { None, Quad, AdvanceA, AdvanceB };

struct Strip {
  double cost = std::numeric_limits<double>::infinity();
  std::vector<Step> steps;  // in order from the first rung
};

// Open-chain DP between a[0..m] and b[0..n] (already rotated / unrolled).
// Arc-length fraction (0 at the first point, 1 at the last) of each point of `p`.
std::vector<double> fractions(const std::vector<glm::dvec3>& p) {
  std::vector<double> t(p.size(), 0.0);
  for (size_t i = 1; i < p.size(); ++i) t[i] = t[i - 1] + glm::length(p[i] - p[i - 1]);
  const double total = t.back();
  for (size_t i = 0; i < p.size(); ++i) {
    t[i] = total > 0 ? t[i] / total : static_cast<double>(i) / static_cast<double>(p.size() - 1);
  }
  return t;
}

Strip solve(const std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b, double scale,
            double tri_cost, double bound) {
  const size_t m = a.size(), n = b.size();
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> cost(m * n, inf);
  std::vector<Step> from(m * n, Step::None);
  auto at = [n](size_t i, size_t j) { return i * n + j; };
  auto d = [](const glm::dvec3& p, const glm::dvec3& q) { return glm::length(p - q); };
  const std::vector<double> ta = fractions(a), tb = fractions(b);
  // Length of the rung (i, j) plus its skew.
  auto rung = [&](size_t i, size_t j) { return d(a[i], b[j]) + scale * std::fabs(ta[i] - tb[j]); };
  cost[0] = rung(0, 0);
  for (size_t i = 0; i < m; ++i) {
    for (size_t j = 0; j < n; ++j) {
      const double c = cost[at(i, j)];
      if (c == inf || c > bound) continue;
      if (i + 1 < m && j + 1 < n) {
        double v = c + rung(i + 1, j + 1);
        if (v < cost[at(i + 1, j + 1)]) {
          cost[at(i + 1, j + 1)] = v;
          from[at(i + 1, j + 1)] = Step::Quad;
        }
      }
      if (i + 1 < m) {
        double v = c + rung(i + 1, j) + tri_cost;
        if (v < cost[at(i + 1, j)]) {
          cost[at(i + 1, j)] = v;
          from[at(i + 1, j)] = Step::AdvanceA;
        }
      }
      if (j + 1 < n) {
        double v = c + rung(i, j + 1) + tri_cost;
        if (v < cost[at(i, j + 1)]) {
          cost[at(i, j + 1)] = v;
          from[at(i, j + 1)] = Step::AdvanceB;
        }
      }
    }
  }
  Strip s;
  s.cost = cost[at(m - 1, n - 1)];
  if (s.cost == inf) return s;
  size_t i = m - 1, j = n - 1;
  while (i > 0 || j > 0) {
    Step st = from[at(i, j)];
    s.steps.push_back(st);
    if (st == Step::Quad) {
      --i;
      --j;
    } else if (st == Step::AdvanceA) {
      --i;
    } else {
      --j;
    }
  }
  std::reverse(s.steps.begin(), s.steps.end());
  return s;
}

KernelError invalid(std::string message) {
  KernelError e;
  e.kind = KernelError::Kind::InvalidArgument;
  e.message = std::move(message);
  return e;
}

}  // namespace

Result<ZipperResult> zipper(const ZipperChain& a, const ZipperChain& b, const ZipperOptions& options) {
  if (a.points.empty() || b.points.empty()) {
    return invalid(fmt::format("zipper chain {} is empty", a.points.empty() ? "A" : "B"));
  }
  if (a.is_closed != b.is_closed) {
    return invalid("zipper chains must both be open segments or both closed loops");
  }
  const size_t min_points = a.is_closed ? 3 : 2;
  if (a.points.size() < min_points || b.points.size() < min_points) {
    return invalid(fmt::format("a zipper {} needs at least {} points, got {}",
                               a.is_closed ? "loop" : "segment", min_points,
                               std::min(a.points.size(), b.points.size())));
  }
  if (!(options.penalty >= 0)) {
    return invalid(fmt::format("zipper penalty must be >= 0, got {}", options.penalty));
  }
  const bool closed = a.is_closed;
  double total = 0;
  int32_t edges = 0;
  for (const ZipperChain* c : {&a, &b}) {
    const size_t k = c->points.size();
    const size_t ne = closed ? k : k - 1;
    for (size_t i = 0; i < ne; ++i) {
      total += glm::length(c->points[(i + 1) % k] - c->points[i]);
      ++edges;
    }
  }
  double scale = edges > 0 ? total / edges : 0;
  if (!(scale > 0)) scale = 1;
  const double tri_cost = options.penalty * scale;

  const int32_t na = static_cast<int32_t>(a.points.size());
  const int32_t nb = static_cast<int32_t>(b.points.size());
  // Index sequences into A and B walked by the DP (closed loops are unrolled: the start
  // point repeats at the end).
  std::vector<int32_t> ia, ib;
  Strip best;
  int32_t best_start = 0;
  bool best_reversed = false;
  if (!closed) {
    for (int32_t i = 0; i < na; ++i) ia.push_back(i);
    for (int32_t j = 0; j < nb; ++j) ib.push_back(j);
    best = solve(a.points, b.points, scale, tri_cost, std::numeric_limits<double>::infinity());
  } else {
    std::vector<glm::dvec3> pa(a.points);
    pa.push_back(a.points[0]);
    for (int32_t i = 0; i <= na; ++i) ia.push_back(i % na);
    const int32_t starts = options.is_start_fixed ? 1 : nb;
    for (int dir = 0; dir < 2; ++dir) {
      for (int32_t s = 0; s < starts; ++s) {
        std::vector<glm::dvec3> pb;
        for (int32_t k = 0; k <= nb; ++k) {
          int32_t j = dir == 0 ? (s + k) % nb : ((s - k) % nb + nb) % nb;
          pb.push_back(b.points[j]);
        }
        Strip st = solve(pa, pb, scale, tri_cost, best.cost);
        if (st.cost < best.cost) {
          best = std::move(st);
          best_start = s;
          best_reversed = dir == 1;
        }
      }
    }
    for (int32_t k = 0; k <= nb; ++k) {
      ib.push_back(!best_reversed ? (best_start + k) % nb : ((best_start - k) % nb + nb) % nb);
    }
  }
  ZipperResult r;
  r.cost = best.cost;
  r.b_start = best_start;
  r.is_b_reversed = best_reversed;
  for (const glm::dvec3& p : a.points) r.soup.add_vertex(p);
  for (const glm::dvec3& p : b.points) r.soup.add_vertex(p);
  size_t i = 0, j = 0;
  auto A = [&](size_t k) { return ia[k]; };
  auto B = [&](size_t k) { return na + ib[k]; };
  for (Step st : best.steps) {
    if (st == Step::Quad) {
      r.soup.add_face({A(i + 1), A(i), B(j), B(j + 1)});
      ++r.quad_count;
      ++i;
      ++j;
    } else if (st == Step::AdvanceA) {
      r.soup.add_face({A(i + 1), A(i), B(j)});
      ++r.triangle_count;
      ++i;
    } else {
      r.soup.add_face({A(i), B(j), B(j + 1)});
      ++r.triangle_count;
      ++j;
    }
  }
  return r;
}

}  // namespace nomec::kernel
