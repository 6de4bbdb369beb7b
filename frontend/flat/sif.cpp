// `.sif` (SIF_SFF) as NOME 2016 read it (compat.md §G1): `(v x y z)` vertices, merged into
// an earlier vertex at most 0.001 away across all shells, the survivors named `v0, v1, …`
// in order; `(t a b c)` triangles with 0-based indices local to their shell, offset by the
// declared `(vertices N)` counts of the earlier shells; `(* … *)` comments, nesting; any
// number of shells, one mesh; triangles kept as triangles. The weld is O(n log n) at any
// coordinate magnitude (`detail::weld_points`, at the end).
//
// The file is read as nested parenthesised lists with an explicit stack (no recursion, so
// no input can exhaust the call stack); a list is interpreted when it closes, by its first
// word. Lists with other first words (`SIF_SFF`, `units`, `solid`, `bounds`, …) only hold
// the others.
#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cmath>
#include <fmt/format.h>
#include <optional>
#include <string>
#include <vector>

#include "frontend/flat/flat_internal.h"

namespace nomec::flat {

namespace {

struct Token {
  std::string_view text;
  uint32_t begin = 0;
};

// An open list: where its `(` is, its first word, the words after it, how many `v` / `t`
// lists it holds (for `vertices N` / `triangles M`).
struct Frame {
  uint32_t open = 0;
  Token head;
  bool has_head = false;
  std::vector<Token> args;
  int64_t children = 0;
};

struct Shell {
  int64_t base = 0;       // index of its first vertex among all vertices read
  int64_t declared = -1;  // `(vertices N)`, -1 if not declared yet
  int64_t read = 0;       // `v` lists read
};

struct Triangle {
  int64_t v[3];
  SourceRange range;
};

class SifReader {
 public:
  SifReader(const SourceManager& sources, FileId file, DiagnosticEngine& diags, const ReadOptions& options)
      : text_(sources.text(file)), file_(file), diags_(diags), options_(options) {}

  std::shared_ptr<const ir::FlatGeometry> run() {
    scan();
    return build();
  }

 private:
  SourceRange range(uint32_t b, uint32_t e) const { return SourceRange{file_, b, e}; }
  SourceRange range(const Token& t) const {
    return range(t.begin, t.begin + static_cast<uint32_t>(t.text.size()));
  }
  void error(SourceRange r, std::string msg) { diags_.emit(DiagKind::FlatSyntax, r, std::move(msg)); }

  // Skips a `(* … *)` comment starting at `i` (nesting); returns the offset after it.
  size_t skip_comment(size_t i) {
    const size_t open = i;
    int depth = 0;
    while (i < text_.size()) {
      if (text_.compare(i, 2, "(*") == 0) {
        ++depth;
        i += 2;
      } else if (text_.compare(i, 2, "*)") == 0) {
        i += 2;
        if (--depth == 0) return i;
      } else {
        ++i;
      }
    }
    diags_.emit(DiagKind::FlatSyntax, range(static_cast<uint32_t>(open), static_cast<uint32_t>(open + 2)),
                "this `(*` comment is never closed with `*)`; the rest of the file is part of it");
    return i;
  }

  void scan() {
    size_t i = utf8_bom_length(text_);  // a leading byte order mark is not part of the mesh
    while (i < text_.size()) {
      const char ch = text_[i];
      if (ch == ' ' || ch == '\t' || ch == '\n' || ch == '\r' || ch == '\f' || ch == '\v') {
        ++i;
      } else if (text_.compare(i, 2, "(*") == 0) {
        i = skip_comment(i);
      } else if (ch == '(') {
        stack_.push_back(Frame{static_cast<uint32_t>(i), {}, false, {}, 0});
        ++i;
      } else if (ch == ')') {
        if (stack_.empty()) {
          error(range(static_cast<uint32_t>(i), static_cast<uint32_t>(i + 1)), "`)` closes no open `(`");
        } else {
          Frame f = std::move(stack_.back());
          stack_.pop_back();
          close(f, static_cast<uint32_t>(i + 1));
        }
        ++i;
      } else {
        size_t j = i;
        while (j < text_.size() && text_[j] != '(' && text_[j] != ')' && !std::isspace(static_cast<unsigned char>(text_[j]))) ++j;
        word(Token{text_.substr(i, j - i), static_cast<uint32_t>(i)});
        i = j;
      }
    }
    if (!stack_.empty()) {
      const Frame& f = stack_.front();
      error(range(f.open, f.open + 1), fmt::format("this `(`{} is never closed with `)`",
                                                   f.has_head ? fmt::format(" of `{}`", f.head.text) : ""));
      // What was read inside the unclosed lists is kept, innermost first.
      while (!stack_.empty()) {
        Frame f2 = std::move(stack_.back());
        stack_.pop_back();
        if (f2.has_head && (f2.head.text == "v" || f2.head.text == "t")) close(f2, static_cast<uint32_t>(text_.size()));
      }
    }
  }

  void word(const Token& t) {
    if (stack_.empty()) {
      if (!reported_stray_) error(range(t), fmt::format("`{}` is outside the file's parentheses `(SIF_SFF …)`", clip(t.text)));
      reported_stray_ = true;
      return;
    }
    Frame& f = stack_.back();
    if (!f.has_head) {
      f.head = t;
      f.has_head = true;
      if (t.text == "shell") start_shell();
      return;
    }
    f.args.push_back(t);
  }

  static std::string clip(std::string_view t) {
    return t.size() > 40 ? std::string(t.substr(0, 40)) + "…" : std::string(t);
  }

  void start_shell() {
    if (!shells_.empty()) {
      const Shell& prev = shells_.back();
      shells_.push_back(Shell{prev.base + (prev.declared >= 0 ? prev.declared : prev.read), -1, 0});
    } else {
      shells_.push_back(Shell{});
    }
  }
  Shell& shell() {
    if (shells_.empty()) shells_.push_back(Shell{});  // `v`/`t` outside any `(shell …)`
    return shells_.back();
  }

  void close(const Frame& f, uint32_t end) {
    if (!f.has_head) return;
    if (!stack_.empty()) ++stack_.back().children;
    const SourceRange r = range(f.open, end);
    const std::string_view h = f.head.text;
    if (h == "v") return vertex(f, r);
    if (h == "t") return triangle(f, r);
    if (h == "vertices" || h == "triangles") return counted(f, r);
  }

  void vertex(const Frame& f, SourceRange r) {
    ++shell().read;
    std::array<double, 3> p{0, 0, 0};
    if (f.args.size() != 3) {
      error(r, fmt::format("a vertex is `(v x y z)` with 3 numbers, this one has {}", f.args.size()));
    }
    bool bad = f.args.size() != 3;
    for (size_t k = 0; k < f.args.size() && k < 3; ++k) {
      std::optional<double> x = detail::parse_number(f.args[k].text);
      if (!x) {
        error(range(f.args[k]), fmt::format("`{}` is not a number", clip(f.args[k].text)));
        bad = true;
        continue;
      }
      p[k] = *x;
    }
    raw_.push_back(p);
    bad_.push_back(bad ? 1 : 0);
  }

  void triangle(const Frame& f, SourceRange r) {
    Shell& s = shell();
    if (f.args.size() != 3) {
      error(r, fmt::format("a triangle is `(t a b c)` with 3 vertex indices, this one has {}", f.args.size()));
      return;
    }
    Triangle t{{0, 0, 0}, r};
    const int64_t count = s.declared >= 0 ? s.declared : s.read;
    for (size_t k = 0; k < 3; ++k) {
      std::optional<int64_t> v = detail::parse_integer(f.args[k].text);
      if (!v) {
        error(range(f.args[k]), fmt::format("`{}` is not a vertex index (a whole number from 0)", clip(f.args[k].text)));
        return;
      }
      if (*v < 0 || *v >= count || s.base + *v >= static_cast<int64_t>(raw_.size())) {
        diags_.emit(DiagKind::FlatIndexOutOfRange, range(f.args[k]),
                    fmt::format("vertex index {} is out of range: this shell has {} vertices, numbered from 0", *v,
                                std::min<int64_t>(count, static_cast<int64_t>(raw_.size()) - s.base)));
        return;
      }
      t.v[k] = s.base + *v;
    }
    triangles_.push_back(t);
  }

  // `(vertices N …)`, `(triangles M …)`: the declared count, checked against the lists.
  void counted(const Frame& f, SourceRange r) {
    const bool is_vertices = f.head.text == "vertices";
    std::optional<int64_t> n = f.args.empty() ? std::nullopt : detail::parse_integer(f.args[0].text);
    if (!n || *n < 0) {
      error(f.args.empty() ? range(f.head) : range(f.args[0]),
            fmt::format("`({} …)` starts with its count, a whole number", f.head.text));
      return;
    }
    if (is_vertices) shell().declared = *n;
    if (*n != f.children) {
      diags_.emit(DiagKind::FlatCountMismatch, r,
                  fmt::format("`({} {} …)` lists {} {}{}", f.head.text, *n, f.children, is_vertices ? "vertices" : "triangles",
                              is_vertices ? "; later shells' indices are offset by the declared count, as NOME 2016 did" : ""));
    }
  }

  // Welds the vertices (`detail::weld_points`) and maps the triangles onto the survivors.
  std::shared_ptr<const ir::FlatGeometry> build() {
    auto g = std::make_shared<ir::FlatGeometry>();
    static_assert(kSifWeldDistance < 1.0 / 512, "the weld grid's cells are 2^-9 wide");
    detail::Weld weld = detail::weld_points(raw_, bad_, kSifWeldDistance);
    g->positions = std::move(weld.survivors);
    const std::vector<int32_t>& map = weld.map;
    int dropped = 0;
    std::vector<int32_t> faces;  // the triangles kept, three vertices each
    for (const Triangle& t : triangles_) {
      if (bad_[static_cast<size_t>(t.v[0])] + bad_[static_cast<size_t>(t.v[1])] + bad_[static_cast<size_t>(t.v[2])] != 0) {
        continue;  // a misread vertex (reported)
      }
      const int32_t vs[3] = {map[static_cast<size_t>(t.v[0])], map[static_cast<size_t>(t.v[1])],
                             map[static_cast<size_t>(t.v[2])]};
      ir::FlatGeometry one;
      const std::string what = fmt::format("triangle `{}`", clip(text_.substr(t.range.begin, t.range.end - t.range.begin)));
      if (detail::add_face(one, vs, t.range, what, diags_, dropped)) {
        faces.insert(faces.end(), vs, vs + 3);
      }
    }
    add_faces(*g, faces);
    detail::report_dropped(dropped, file_, diags_);
    return g;
  }

  // Appends the triangles `t` (three vertices each) to `g`: as they are, or with
  // `sif_quads` each consecutive pair sharing an edge as one quad.
  void add_faces(ir::FlatGeometry& g, const std::vector<int32_t>& t) const {
    const size_t n = t.size() / 3;
    for (size_t i = 0; i < n; ++i) {
      const int32_t* a = &t[3 * i];
      if (options_.sif_quads && i + 1 < n) {
        if (std::optional<std::array<int32_t, 4>> q = pair(a, &t[3 * (i + 1)])) {
          g.corners.insert(g.corners.end(), q->begin(), q->end());
          g.face_starts.push_back(static_cast<int32_t>(g.corners.size()));
          ++i;
          continue;
        }
      }
      g.corners.insert(g.corners.end(), a, a + 3);
      g.face_starts.push_back(static_cast<int32_t>(g.corners.size()));
    }
  }

  // Triangles (u v w1) and (v u w2), in any rotation, are the quad (u w2 v w1).
  static std::optional<std::array<int32_t, 4>> pair(const int32_t* a, const int32_t* b) {
    for (int i = 0; i < 3; ++i) {
      const int32_t u = a[i], v = a[(i + 1) % 3], w1 = a[(i + 2) % 3];
      for (int j = 0; j < 3; ++j) {
        if (b[j] != v || b[(j + 1) % 3] != u) continue;
        const int32_t w2 = b[(j + 2) % 3];
        if (w2 == w1) return std::nullopt;
        return std::array<int32_t, 4>{u, w2, v, w1};
      }
    }
    return std::nullopt;
  }

  std::string_view text_;
  FileId file_;
  DiagnosticEngine& diags_;
  const ReadOptions& options_;
  std::vector<Frame> stack_;
  std::vector<Shell> shells_;
  std::vector<std::array<double, 3>> raw_;
  std::vector<uint8_t> bad_;  // per raw vertex: misread
  std::vector<Triangle> triangles_;
  bool reported_stray_ = false;
};

}  // namespace

std::shared_ptr<const ir::FlatGeometry> read_sif(const SourceManager& sources, FileId file, DiagnosticEngine& diags,
                                                 const ReadOptions& options) {
  return SifReader(sources, file, diags, options).run();
}

namespace detail {

namespace {

// The weld grid's cell of coordinate `x` (finite) along one axis. Cells are 2^-9 wide, more
// than the weld distance, so a vertex within it lies in the same or a neighbouring cell in
// each axis. Below 2^43 in magnitude the cell is floor(x · 512) (exact: a power of two);
// beyond, doubles are 2^-9 or more apart, so only equal coordinates weld, and each double
// is a cell of its own, numbered by its rank from 2^43 outwards (the bits of a positive
// double grow with it) and placed right after the last cell below, so that no two far
// coordinates share a cell however large they are and the cells around ±2^43 stay
// neighbours. Every value fits an int64_t with room for ±1.
int64_t weld_cell(double x) {
  constexpr double kExact = 8796093022208.0;  // 2^43
  if (x > -kExact && x < kExact) return static_cast<int64_t>(std::floor(x * 512));  // within ±2^52
  const int64_t rank = static_cast<int64_t>(std::bit_cast<uint64_t>(std::fabs(x)) - std::bit_cast<uint64_t>(kExact));
  constexpr int64_t kEdge = int64_t{1} << 52;
  return x > 0 ? kEdge + rank : -kEdge - 1 - rank;
}

}  // namespace

// Survivors are looked up in a grid of cells (see `weld_cell`) wider than the distance,
// numbered by sorting, not hashing, so no choice of coordinates makes many points share a
// bucket; survivors are more than the distance apart, so a cell holds a bounded number of
// them (a few dozen at most: a cell is 2^-9 wide), and the weld is
// O(n log n) at any coordinate magnitude.
Weld weld_points(std::span<const std::array<double, 3>> points, std::span<const uint8_t> apart, double distance) {
  Weld w;
  using Cell = std::array<int64_t, 3>;
  auto cell_of = [](const std::array<double, 3>& p) { return Cell{weld_cell(p[0]), weld_cell(p[1]), weld_cell(p[2])}; };
  auto is_welded = [&](size_t i) {
    return (i >= apart.size() || apart[i] == 0) && std::isfinite(points[i][0]) && std::isfinite(points[i][1]) &&
           std::isfinite(points[i][2]);
  };
  // The occupied cells, sorted.
  std::vector<Cell> cells;
  cells.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    if (is_welded(i)) cells.push_back(cell_of(points[i]));
  }
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  auto find_cell = [&](const Cell& k) { return std::lower_bound(cells.begin(), cells.end(), k); };
  // The survivors of each cell as a list: the cell's first, then each one's next.
  std::vector<int32_t> first(cells.size(), -1);
  std::vector<int32_t> next;  // by survivor; -1 ends a list
  w.map.resize(points.size());
  const double d2 = distance * distance;
  for (size_t i = 0; i < points.size(); ++i) {
    const std::array<double, 3>& p = points[i];
    int32_t found = -1;
    if (is_welded(i)) {
      const Cell c = cell_of(p);
      // The cells (x+dx, y+dy, z-1 … z+1) are consecutive in the sorted order.
      for (int64_t dx = -1; dx <= 1; ++dx) {
        for (int64_t dy = -1; dy <= 1; ++dy) {
          const Cell last{c[0] + dx, c[1] + dy, c[2] + 1};
          for (auto it = find_cell(Cell{c[0] + dx, c[1] + dy, c[2] - 1}); it != cells.end() && *it <= last; ++it) {
            for (int32_t s = first[static_cast<size_t>(it - cells.begin())]; s >= 0; s = next[static_cast<size_t>(s)]) {
              const std::array<double, 3>& q = w.survivors[static_cast<size_t>(s)];
              ++w.comparisons;
              const double dist2 = (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]);
              if (dist2 <= d2 && (found < 0 || s < found)) found = s;
            }
          }
        }
      }
      if (found < 0) {
        found = static_cast<int32_t>(w.survivors.size());
        w.survivors.push_back(p);
        int32_t& head = first[static_cast<size_t>(find_cell(c) - cells.begin())];
        next.push_back(head);
        head = found;
      }
    } else {  // kept apart: a survivor of its own, never a candidate
      found = static_cast<int32_t>(w.survivors.size());
      w.survivors.push_back(p);
      next.push_back(-1);
    }
    w.map[i] = found;
  }
  return w;
}

}  // namespace detail

}  // namespace nomec::flat
