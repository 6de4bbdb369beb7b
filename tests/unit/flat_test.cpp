// The flat mesh readers (frontend/flat), written from their rules: `.sif` welding within
// 0.001 across shells and per-shell index offsets by declared counts, nesting comments,
// errors with positions; `.obj` corners `v/vt/vn` and negative indices; binary and ASCII
// `.stl` with exact welding; the `.sif` weld against the quadratic rule at every magnitude,
// and its work bounded per point.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "frontend/flat/flat.h"
#include "frontend/flat/flat_internal.h"

namespace nomec::flat {
namespace {

struct Read {
  SourceManager sources;
  DiagnosticEngine diags;
  std::shared_ptr<const ir::FlatGeometry> g;
  FileId file;
  // The diagnostics as `line:col kind`.
  std::vector<std::string> where() const {
    std::vector<std::string> out;
    for (const Diagnostic& d : diags.diagnostics()) {
      LineCol lc = sources.line_col(d.range.file, d.range.begin);
      out.push_back(std::to_string(lc.line) + ":" + std::to_string(lc.column) + " " + std::string(diag_kind_name(d.kind)));
    }
    return out;
  }
  std::vector<int32_t> face(int32_t f) const {
    return {g->corners.begin() + g->face_starts[f], g->corners.begin() + g->face_starts[f + 1]};
  }
};

std::unique_ptr<Read> read(const std::string& name, std::string text, ReadOptions options = {}) {
  auto r = std::make_unique<Read>();
  r->file = r->sources.add_file(name, std::move(text));
  r->g = flat::read(r->sources, r->file, *format_of_path(name), r->diags, options);
  return r;
}

TEST(FlatFormat, ByExtension) {
  EXPECT_EQ(format_of_path("a/Zero_6.sif"), ir::FlatFormat::Sif);
  EXPECT_EQ(format_of_path("B.OBJ"), ir::FlatFormat::Obj);
  EXPECT_EQ(format_of_path("x.stl"), ir::FlatFormat::Stl);
  EXPECT_EQ(format_of_path("x.nome"), std::nullopt);
  EXPECT_EQ(format_of_path(".stl"), std::nullopt);
}

// Two shells: the second declares 3 vertices; its first lies 0.0005 from the first shell's
// v0 (welded), its second 0.0011 from v1 (kept). Its triangle indices are local.
TEST(Sif, WeldsWithinOneThousandthAcrossShellsAndOffsetsIndicesPerShell) {
  auto r = read("w.sif", R"((SIF_SFF 2 0 (units inches)
  (solid
    (shell (vertices 3 (v 0 0 0) (v 1 0 0) (v 0 1 0)) (triangles 1 (t 0 1 2)))
    (shell (vertices 3 (v 0.0005 0 0) (v 1.0011 0 0) (v 0 0 1)) (triangles 1 (t 0 1 2)))))
)");
  EXPECT_TRUE(r->diags.diagnostics().empty());
  ASSERT_EQ(r->g->positions.size(), 5u);  // v0 v1 v2 from shell 1, then 1.0011 and (0 0 1)
  EXPECT_EQ(r->g->positions[3][0], 1.0011);
  EXPECT_EQ(r->g->positions[4][2], 1.0);
  ASSERT_EQ(r->g->face_count(), 2);
  EXPECT_EQ(r->face(0), (std::vector<int32_t>{0, 1, 2}));
  EXPECT_EQ(r->face(1), (std::vector<int32_t>{0, 3, 4}));  // shell-2 vertex 0 welded into v0
}

TEST(Sif, WeldsIntoTheEarliestSurvivorAndKeepsTrianglesAsTriangles) {
  auto r = read("w.sif", "(shell (vertices 4 (v 0 0 0) (v 2 0 0) (v 0.0009 0 0) (v 0 2 0))"
                         " (triangles 2 (t 2 1 3) (t 0 3 1)))");
  EXPECT_TRUE(r->diags.diagnostics().empty());
  ASSERT_EQ(r->g->positions.size(), 3u);
  EXPECT_EQ(r->face(0), (std::vector<int32_t>{0, 1, 2}));
  EXPECT_EQ(r->face(1), (std::vector<int32_t>{0, 2, 1}));
}

TEST(Sif, OffsetsByTheDeclaredCountNotTheListedOne) {
  // Shell 1 declares 4 vertices but lists 3: shell 2's indices start at 4, as in NOME 2016,
  // so its `(t 0 1 2)` names vertices 4, 5, 6 of the file — and only 0…4 exist.
  auto r = read("c.sif", "(shell (vertices 4 (v 0 0 0) (v 1 0 0) (v 0 1 0)) (triangles 1 (t 0 1 2)))\n"
                         "(shell (vertices 2 (v 5 5 5) (v 6 5 5)) (triangles 1 (t 0 1 2)))");
  EXPECT_EQ(r->where(), (std::vector<std::string>{"1:8 FlatCountMismatch", "2:59 FlatIndexOutOfRange"}));
}

TEST(Sif, QuadPairingIsAnOptionForConsecutiveTrianglesSharingAnEdge) {
  const std::string t = "(shell (vertices 5 (v 0 0 0) (v 1 0 0) (v 1 1 0) (v 0 1 0) (v 2 0 0))"
                        " (triangles 4 (t 0 1 2) (t 0 2 3) (t 1 4 2) (t 0 3 1)))";
  EXPECT_EQ(read("q.sif", t)->g->face_count(), 4);  // off by default, as in NOME 2016
  auto r = read("q.sif", t, ReadOptions{true});
  ASSERT_EQ(r->g->face_count(), 3);
  EXPECT_EQ(r->face(0), (std::vector<int32_t>{2, 3, 0, 1}));  // (t 0 1 2) + (t 0 2 3) share 0-2
  EXPECT_EQ(r->face(1), (std::vector<int32_t>{1, 4, 2}));     // (t 1 4 2) and (t 0 3 1) share none
  EXPECT_EQ(r->face(2), (std::vector<int32_t>{0, 3, 1}));
}

TEST(Sif, CommentsNest) {
  auto r = read("n.sif", "(* outer (* inner (v 9 9 9) *) still comment (t 0 1 2) *)\n"
                         "(shell (vertices 3 (v 0 0 0) (* (v 7 7 7) *) (v 1 0 0) (v 0 1 0)) (triangles 1 (t 0 1 2)))");
  EXPECT_TRUE(r->diags.diagnostics().empty()) << r->where().front();
  EXPECT_EQ(r->g->positions.size(), 3u);
  EXPECT_EQ(r->g->face_count(), 1);
}

TEST(Sif, ErrorsCarryTheirPlace) {
  auto r = read("e.sif", "(shell (vertices 3 (v 0 0 0) (v 1 x 0) (v 0 1))\n"
                         "  (triangles 2 (t 0 1 5) (t 0 1 -1)))\n"
                         ")\n"
                         "(shell (vertices 1 (v 0 0 0)");
  EXPECT_EQ(r->where(), (std::vector<std::string>{"1:35 FlatSyntax", "1:40 FlatSyntax", "2:23 FlatIndexOutOfRange",
                                                  "2:33 FlatIndexOutOfRange", "3:1 FlatSyntax", "4:1 FlatSyntax"}));
}

TEST(Sif, AMisreadVertexIsNotWeldedAndItsTrianglesAreLeftOut) {
  auto r = read("m.sif", "(shell (vertices 4 (v 0 0 0) (v 1 0 0) (v 0 x 0) (v 0 1 0)) (triangles 2 (t 0 1 2) (t 0 1 3)))");
  EXPECT_EQ(r->where(), (std::vector<std::string>{"1:45 FlatSyntax"}));
  EXPECT_EQ(r->g->positions.size(), 4u);  // (0 ? 0) is not welded into (0 0 0)
  ASSERT_EQ(r->g->face_count(), 1);
  EXPECT_EQ(r->face(0), (std::vector<int32_t>{0, 1, 3}));
}

TEST(Sif, UnclosedCommentIsReportedAtItsOpening) {
  auto r = read("u.sif", "(shell (vertices 1 (v 0 0 0)))\n  (* never closed");
  EXPECT_EQ(r->where(), (std::vector<std::string>{"2:3 FlatSyntax"}));
}

TEST(Sif, ATriangleWeldedFlatIsDroppedWithAWarning) {
  auto r = read("d.sif", "(shell (vertices 3 (v 0 0 0) (v 0.0001 0 0) (v 0 1 0)) (triangles 1 (t 0 1 2)))");
  EXPECT_EQ(r->where(), (std::vector<std::string>{"1:69 FlatDegenerateFace"}));
  EXPECT_EQ(r->g->face_count(), 0);
}

TEST(Sif, NoInputCrashes) {
  for (std::string t : {"", "(", ")", "(((((", "(v)", "(t 0 0 0)", "(* (* *)", "(vertices -3)", "x y z",
                        "(v 1e400 0 0)", "(shell (vertices 99999999999999999999))", "(t 1 2 3 4)"}) {
    auto r = read("f.sif", t);
    EXPECT_NE(r->g, nullptr) << t;
  }
  std::string deep(100000, '(');
  EXPECT_NE(read("deep.sif", deep)->g, nullptr);
}

// The weld as NOME 2016 defined it, in quadratic time: each point into the earliest
// survivor within the distance. The reference for `detail::weld_points`.
std::vector<int32_t> weld_by_pairs(const std::vector<std::array<double, 3>>& points, double d) {
  std::vector<std::array<double, 3>> survivors;
  std::vector<int32_t> map;
  for (const auto& p : points) {
    int32_t found = -1;
    for (size_t s = 0; s < survivors.size() && found < 0; ++s) {
      const auto& q = survivors[s];
      const double d2 = (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]);
      if (d2 <= d * d) found = static_cast<int32_t>(s);
    }
    if (found < 0) {
      found = static_cast<int32_t>(survivors.size());
      survivors.push_back(p);
    }
    map.push_back(found);
  }
  return map;
}

// Clusters of points a little closer and a little farther than 0.001 apart, at every scale
// where welding changes character: near 0, across cell edges, around 2^43 (where doubles
// become 2^-9 apart and the grid switches from cells to values), near the largest doubles.
TEST(SifWeld, AgreesWithTheQuadraticWeldAtEveryScale) {
  std::mt19937_64 rng(45);
  for (const double centre : {0.0, 1.0 / 1024, 1e6, 4398046511104.0, 8796093022208.0, -8796093022208.0, 1e13, 1e20,
                              -1e20, 1e300, -1.7e308}) {
    std::vector<std::array<double, 3>> points;
    std::uniform_real_distribution<double> step(-0.0015, 0.0015);
    for (int cluster = 0; cluster < 40; ++cluster) {
      std::array<double, 3> base{centre, centre, centre};
      for (double& x : base) x += std::uniform_real_distribution<double>(-0.05, 0.05)(rng);
      for (int k = 0; k < 6; ++k) {
        std::array<double, 3> p = base;
        for (double& x : p) x += step(rng);
        if (k == 5) {  // the double next to the cluster's first point, in one axis
          const size_t axis = rng() % 3;
          p = points[points.size() - 5];
          p[axis] = std::nextafter(p[axis], HUGE_VAL);
        }
        points.push_back(p);
      }
    }
    const detail::Weld w = detail::weld_points(points, {}, kSifWeldDistance);
    EXPECT_EQ(w.map, weld_by_pairs(points, kSifWeldDistance)) << "around " << centre;
  }
}

// The weld once kept every vertex beyond 4e12 in one cell (200,000 vertices: 32 s). Now a
// point is compared with a bounded number of survivors at any magnitude: far fewer than the
// n²/2 comparisons of one crowded cell.
TEST(SifWeld, ComparesABoundedNumberOfSurvivorsPerPointAtAnyScale) {
  const int n = 200000;
  for (const double scale : {1.0, 1e13, 1e20, 1e300}) {
    std::vector<std::array<double, 3>> points;
    points.reserve(n);
    for (int i = 0; i < n; ++i) {
      // A grid of distinct points one unit apart (at 1e300, a unit is below the doubles'
      // spacing: the points are rounded together, and weld only where exactly equal).
      const double x = scale + (i % 100), y = scale + (i / 100 % 100), z = scale + (i / 10000);
      points.push_back({x, y, z});
    }
    const detail::Weld w = detail::weld_points(points, {}, kSifWeldDistance);
    EXPECT_LE(w.comparisons, int64_t{30} * n) << "at " << scale;
    if (scale < 1e15) {
      EXPECT_EQ(w.survivors.size(), static_cast<size_t>(n)) << "at " << scale;
    }
  }
  // Points exactly 0.001 apart along a line weld in chains into the earliest survivor.
  std::vector<std::array<double, 3>> line;
  for (int i = 0; i < n; ++i) line.push_back({1e12 + i * 0.0009, 0, 0});
  const detail::Weld w = detail::weld_points(line, {}, kSifWeldDistance);
  EXPECT_LE(w.comparisons, int64_t{30} * n);
}

// Misread vertices and non-finite coordinates stay apart and compare with nothing.
TEST(SifWeld, KeepsApartWhatCannotBeWelded) {
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<std::array<double, 3>> points{{0, 0, 0}, {inf, 0, 0}, {0, nan, 0}, {0, 0, 0}, {inf, 0, 0}, {0, 0, 0}};
  const std::vector<uint8_t> apart{0, 0, 0, 1, 0, 0};
  const detail::Weld w = detail::weld_points(points, apart, kSifWeldDistance);
  EXPECT_EQ(w.map, (std::vector<int32_t>{0, 1, 2, 3, 4, 0}));
}

TEST(Obj, CornersWithTextureAndNormalAndNegativeIndices) {
  auto r = read("q.obj", "# a quad and a triangle\no thing\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0 1.0\nvt 0 0\nvn 0 0 1\n"
                         "g top\ns off\nusemtl red\nf 1/1/1 2/1/1 3//1 4\nv 2 0 0\nf -4 -1 -3\n");
  EXPECT_TRUE(r->diags.diagnostics().empty()) << r->where().front();
  ASSERT_EQ(r->g->positions.size(), 5u);
  EXPECT_EQ(r->g->positions[3][1], 1.0);
  ASSERT_EQ(r->g->face_count(), 2);
  EXPECT_EQ(r->face(0), (std::vector<int32_t>{0, 1, 2, 3}));
  EXPECT_EQ(r->face(1), (std::vector<int32_t>{1, 4, 2}));
}

TEST(Obj, Errors) {
  auto r = read("e.obj", "v 0 0 0\nv 1 0 zz\nv 0 1 0\nf 1 2 9\nf 1 0 2\nf -5 1 2\nf 1 2\nl 1 2\nl 2 3\n");
  EXPECT_EQ(r->where(), (std::vector<std::string>{"2:7 FlatSyntax", "5:5 FlatSyntax", "7:1 FlatSyntax",
                                                  "8:1 FlatIgnoredStatement", "4:7 FlatIndexOutOfRange",
                                                  "6:3 FlatIndexOutOfRange"}));
}

std::string binary_stl(const std::vector<std::array<float, 9>>& tris) {
  std::string s(80, 'x');
  s.replace(0, 5, "solid");  // as some exporters write: still binary by its size
  const uint32_t n = static_cast<uint32_t>(tris.size());
  s.append(reinterpret_cast<const char*>(&n), 4);
  for (const auto& t : tris) {
    const float normal[3] = {0, 0, 1};
    s.append(reinterpret_cast<const char*>(normal), 12);
    s.append(reinterpret_cast<const char*>(t.data()), 36);
    s.append(2, '\0');
  }
  return s;
}

TEST(Stl, BinaryWeldsExactlyEqualCorners) {
  auto r = read("b.stl", binary_stl({{0, 0, 0, 1, 0, 0, 0, 1, 0}, {1, 0, 0, 1, 1, 0, 0, 1, 0}, {0, 0, 0, 1, 0, 0, 0, 0, 1e-6f}}));
  EXPECT_TRUE(r->diags.diagnostics().empty());
  ASSERT_EQ(r->g->positions.size(), 5u);  // (0 0 1e-6) is not (0 0 0)
  EXPECT_EQ(r->face(1), (std::vector<int32_t>{1, 3, 2}));
  EXPECT_EQ(r->face(2), (std::vector<int32_t>{0, 1, 4}));
}

TEST(Stl, Ascii) {
  auto r = read("a.stl", "solid t\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 1 0\n"
                         "  endloop\n endfacet\n facet normal 0 0 1\n  outer loop\n   vertex 1 0 0\n   vertex 1 1 0\n"
                         "   vertex -0 1 0\n  endloop\n endfacet\nendsolid t\n");
  EXPECT_TRUE(r->diags.diagnostics().empty());
  ASSERT_EQ(r->g->positions.size(), 4u);  // -0 equals 0
  EXPECT_EQ(r->face(1), (std::vector<int32_t>{1, 3, 2}));
}

TEST(Stl, NeitherFormIsAnErrorAndBadNumbersArePlaced) {
  EXPECT_EQ(read("n.stl", "hello")->where(), (std::vector<std::string>{"1:1 FlatSyntax"}));
  auto r = read("a.stl", "solid t\nfacet\nouter loop\nvertex 0 0 0\nvertex 1 q 0\nvertex 0 1 0\nendloop\nendfacet\n");
  EXPECT_EQ(r->where(), (std::vector<std::string>{"5:10 FlatSyntax"}));  // the facet is left out, quietly
  EXPECT_EQ(r->g->face_count(), 0);
}

}  // namespace
}  // namespace nomec::flat

namespace nomec::flat {
namespace {

// A face that uses a vertex twice is dropped, naming the first vertex (in the face's order)
// it repeats — also for a face of many corners, found in one pass rather than pair by pair
// (a hostile file's face of a million corners took hours).
TEST(FlatFaces, RepeatedVerticesAreFoundInLongFacesToo) {
  for (const int32_t n : {5, 40, 200'000}) {
    std::vector<int32_t> face(static_cast<size_t>(n));
    for (int32_t i = 0; i < n; ++i) face[static_cast<size_t>(i)] = i;
    ir::FlatGeometry g;
    DiagnosticEngine diags;
    int dropped = 0;
    EXPECT_TRUE(detail::add_face(g, face, SourceRange{}, "face f", diags, dropped)) << n;
    EXPECT_EQ(diags.error_count() + diags.warning_count(), 0u) << n;
    // v3 repeats near the end and v1 at the end: v1 comes first in the face.
    face[static_cast<size_t>(n - 2)] = 3;
    face[static_cast<size_t>(n - 1)] = 1;
    EXPECT_FALSE(detail::add_face(g, face, SourceRange{}, "face f", diags, dropped)) << n;
    ASSERT_EQ(diags.diagnostics().size(), 1u) << n;
    EXPECT_EQ(diags.diagnostics()[0].message, "face f uses vertex v1 twice (after welding); the face is dropped") << n;
    EXPECT_EQ(g.face_count(), 1) << n;  // the first face only
  }
}

}  // namespace
}  // namespace nomec::flat
