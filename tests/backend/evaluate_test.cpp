// Unit tests of scene evaluation: transform order (first written acts first, parent ·
// child), mirrors reversing face order, colour precedence, hidden instances, provenance,
// and geometry errors becoming diagnostics that name the instance path.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "backend/evaluate.h"
#include "backend/write.h"
#include "frontend/check/check.h"
#include "tests/backend/evaluated.h"

namespace nomec::backend {
namespace {

std::unique_ptr<Evaluated> eval(const std::string& text) { return evaluate_text("test.nome", text); }

void expect_near(const glm::dvec3& a, const glm::dvec3& b) {
  EXPECT_NEAR(a.x, b.x, 1e-9);
  EXPECT_NEAR(a.y, b.y, 1e-9);
  EXPECT_NEAR(a.z, b.z, 1e-9);
}

glm::dvec3 face_normal(const kernel::PolygonSoup& s, int32_t f) {
  int32_t at = 0;
  for (int32_t i = 0; i < f; ++i) at += s.face_sizes[i];
  glm::dvec3 a = s.positions[s.face_vertices[at]], b = s.positions[s.face_vertices[at + 1]],
             c = s.positions[s.face_vertices[at + 2]];
  return glm::normalize(glm::cross(b - a, c - a));
}

const std::string kTriangle =
    "mesh tri\n"
    "  point a (1 0 0) endpoint\n"
    "  point b (2 0 0) endpoint\n"
    "  point c (1 1 0) endpoint\n"
    "  face f (a b c) endface\n"
    "endmesh\n";

TEST(Transforms, FirstWrittenActsFirst) {
  auto e = eval(kTriangle +
                "instance i1 tri translate (1 0 0) rotate (0 0 1) (90) endinstance\n"
                "instance i2 tri rotate (0 0 1) (90) translate (1 0 0) endinstance\n");
  ASSERT_EQ(e->meshes.size(), 2u);
  // i1: (1,0,0) -> translate (2,0,0) -> rotate (0,2,0).
  expect_near(e->meshes[0].soup.positions[0], {0, 2, 0});
  // i2: (1,0,0) -> rotate (0,1,0) -> translate (1,1,0).
  expect_near(e->meshes[1].soup.positions[0], {1, 1, 0});
}

TEST(Transforms, ScaleAndNestingComposeParentTimesChild) {
  auto e = eval(kTriangle +
                "group g instance inner tri scale (2 2 2) endinstance endgroup\n"
                "instance outer g translate (0 0 5) endinstance\n");
  ASSERT_EQ(e->meshes.size(), 1u);
  // Child first (scale), then the parent (translate).
  expect_near(e->meshes[0].soup.positions[0], {2, 0, 5});
  expect_near(e->meshes[0].soup.positions[1], {4, 0, 5});
}

TEST(Transforms, ZeroRotationAxisIsIdentity) {
  auto e = eval(kTriangle + "instance i tri rotate (0 0 0) (45) endinstance\n");
  ASSERT_EQ(e->meshes.size(), 1u);
  expect_near(e->meshes[0].soup.positions[1], {2, 0, 0});
}

TEST(Transforms, MirrorReflectsAndReversesOrientation) {
  auto e = eval(kTriangle +
                "instance plain tri endinstance\n"
                "instance m tri mirror (1 0 0 0.5) endinstance\n");
  ASSERT_EQ(e->meshes.size(), 2u);
  // Reflection in x = 0.5: (1,0,0) -> (0,0,0), (2,0,0) -> (-1,0,0).
  const kernel::PolygonSoup& s = e->meshes[1].soup;
  expect_near(s.positions[0], {0, 0, 0});
  expect_near(s.positions[1], {-1, 0, 0});
  // Geometry reflected in a plane containing the z axis keeps a +z normal only if the
  // vertex order is reversed.
  expect_near(face_normal(e->meshes[0].soup, 0), {0, 0, 1});
  expect_near(face_normal(s, 0), {0, 0, 1});
  EXPECT_EQ(s.face_vertices[0], 0);
  EXPECT_EQ(s.face_vertices[1], 2);
  EXPECT_EQ(s.face_vertices[2], 1);
}

TEST(Transforms, NegativeScaleAlsoReversesOrientation) {
  auto e = eval(kTriangle + "instance m tri scale (1 1 -1) endinstance\n");
  ASSERT_EQ(e->meshes.size(), 1u);
  expect_near(face_normal(e->meshes[0].soup, 0), {0, 0, -1});
  EXPECT_EQ(e->meshes[0].soup.face_vertices[1], 2);
}

TEST(Colours, FaceBeatsInstanceAndInnermostInstanceWins) {
  auto e = eval(
      "surface red color (1 0 0) endsurface\n"
      "surface green color (0 1 0) endsurface\n"
      "surface blue color (0 0 1) endsurface\n"
      "mesh two\n"
      "  point a (0 0 0) endpoint point b (1 0 0) endpoint point c (1 1 0) endpoint\n"
      "  point d (0 1 0) endpoint point e (2 0 0) endpoint\n"
      "  face f1 (a b c d) surface red endface\n"
      "  face f2 (b e c) endface\n"
      "endmesh\n"
      "group g instance inner two surface green endinstance endgroup\n"
      "instance outer g surface blue endinstance\n"
      "instance plain two endinstance\n");
  ASSERT_EQ(e->meshes.size(), 2u);
  const auto& c = e->meshes[0].soup.face_colors;
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[0], glm::vec3(1, 0, 0));
  EXPECT_EQ(c[1], glm::vec3(0, 1, 0));
  // An uncoloured instance: only the face with a surface has a colour; others get grey.
  const auto& p = e->meshes[1].soup.face_colors;
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[0], glm::vec3(1, 0, 0));
  EXPECT_EQ(p[1], glm::vec3(0.8f, 0.8f, 0.8f));
}

TEST(Colours, NoSurfacesMeansNoColourArray) {
  auto e = eval(kTriangle + "instance i tri endinstance\n");
  ASSERT_EQ(e->meshes.size(), 1u);
  EXPECT_TRUE(e->meshes[0].soup.face_colors.empty());
}

TEST(Scene, HiddenInstanceIsReferenceableButNotOutput) {
  auto e = eval(
      "funnel fun (4 1 0 1) endfunnel\n"
      "instance h fun translate (0 0 3) hidden endinstance\n"
      "mesh cap face top (h.hc0 h.hc1 h.hc2 h.hc3) endface endmesh\n"
      "instance c cap endinstance\n");
  ASSERT_EQ(e->meshes.size(), 1u);
  EXPECT_EQ(e->meshes[0].name, "c");
  EXPECT_EQ(e->meshes[0].soup.face_count(), 1);
  // The funnel's top ring is at z = h = 1, moved up by 3.
  for (const glm::dvec3& p : e->meshes[0].soup.positions) EXPECT_NEAR(p.z, 4.0, 1e-9);
}

TEST(Scene, ProvenanceNamesFaceAndInstanceNodes) {
  auto e = eval(kTriangle + "instance i tri endinstance\n");
  ASSERT_EQ(e->meshes.size(), 1u);
  const ir::Module& m = e->check.module;
  const kernel::FaceSource& s = e->meshes[0].soup.face_sources.at(0);
  ASSERT_GE(s.source_face, 0);
  ASSERT_GE(s.instance, 0);
  EXPECT_EQ(m.nodes[s.source_face].kind, ir::NodeKind::Face);
  EXPECT_EQ(m.nodes[s.source_face].name, "tri.f");
  EXPECT_EQ(m.nodes[s.instance].name, "i");
}

TEST(Errors, NonManifoldFacesGiveADiagnosticWithTheInstancePath) {
  SourceManager sources;
  DiagnosticEngine diags;
  CheckResult r = check_source(sources, "t.nome",
                               "mesh fan\n"
                               "  point a (0 0 0) endpoint point b (1 0 0) endpoint\n"
                               "  point c (0 1 0) endpoint point d (0 -1 0) endpoint\n"
                               "  point e (0 0 1) endpoint\n"
                               "  face f1 (a b c) endface face f2 (b a d) endface\n"
                               "  face f3 (a b e) endface\n"
                               "endmesh\n"
                               "group g instance inner fan endinstance endgroup\n"
                               "instance outer g endinstance\n",
                               CheckOptions{}, diags);
  ASSERT_EQ(diags.error_count(), 0);
  std::vector<OutputMesh> meshes = evaluate_scene(r.module, diags);
  EXPECT_TRUE(meshes.empty());
  ASSERT_EQ(diags.error_count(), 1);
  const Diagnostic& d = diags.diagnostics()[0];
  EXPECT_EQ(d.kind, DiagKind::NonManifoldGeometry);
  EXPECT_NE(d.message.find("instance `outer.inner`"), std::string::npos) << d.message;
  EXPECT_EQ(d.notes.size(), 2u);
}

TEST(Errors, PipelineMergeOfTheWholeSceneReportsKernelErrors) {
  auto e = eval(kTriangle + "instance i tri endinstance\n");
  PipelineOptions o;
  o.is_merge = true;
  o.merge_tolerance = 0;
  auto out = run_pipeline(std::move(e->meshes), o, "x", {}, e->diags);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].mesh.face_count(), 1);
}

TEST(FunctionTexts, ProductsWithoutStarAreReadAsExprtkReadThem) {
  // generators-original.md §11.2: exprtk multiplies `2x`, `10(…)`, `(x+1)y` and `x y`.
  // z = 2xy + 10(x² + y²) − (x + 1)y on the 3 × 3 samples of [0, 1]², computed here.
  auto e = eval("gencartesiansurf a func [2x y + 10(x^2+y^2) - (x+1)y] (0 1 0 1 2 2) endgencartesiansurf\n"
                "instance ia a endinstance\n");
  EXPECT_EQ(e->diags.error_count(), 0);
  ASSERT_EQ(e->meshes.size(), 1u);
  const kernel::PolygonSoup& s = e->meshes[0].soup;
  ASSERT_EQ(s.vertex_count(), 9);
  for (const glm::dvec3& p : s.positions) {
    EXPECT_NEAR(p.z, 2 * p.x * p.y + 10 * (p.x * p.x + p.y * p.y) - (p.x + 1) * p.y, 1e-12);
  }
}

TEST(Write, TriangulatesNonConvexPolygonsByEarClipping) {
  kernel::PolygonSoup s;
  // An L shape (6 vertices, one reflex corner at index 3).
  for (glm::dvec3 p : {glm::dvec3(0, 0, 0), glm::dvec3(2, 0, 0), glm::dvec3(2, 1, 0),
                       glm::dvec3(1, 1, 0), glm::dvec3(1, 2, 0), glm::dvec3(0, 2, 0)}) {
    s.add_vertex(p);
  }
  s.add_face({0, 1, 2, 3, 4, 5});
  std::vector<int32_t> t = triangulate(s);
  ASSERT_EQ(t.size(), 12u);
  double area = 0;
  for (size_t k = 0; k < t.size(); k += 3) {
    glm::dvec3 n = glm::cross(s.positions[t[k + 1]] - s.positions[t[k]], s.positions[t[k + 2]] - s.positions[t[k]]);
    EXPECT_GT(n.z, 0) << "triangle " << k / 3 << " is flipped";
    area += n.z / 2;
  }
  EXPECT_NEAR(area, 3.0, 1e-12);
}

// The writers decide whether to fan or ear-clip a face with `is_convex` of its Newell
// normal, and a quad with `is_convex_quad`. Both are held to the definition (the loops over
// corners i, i + 1, i + 2 modulo n, written out here) to the bit, on quads of every shape:
// random ones, darts and bow ties, repeated and collinear corners (where a corner's test is
// exactly 0), planar ones on a lattice, tiny and huge coordinates, infinities and NaNs.
TEST(Write, QuadConvexityIsTheGeneralTestToTheBit) {
  auto newell_definition = [](const std::vector<glm::dvec3>& p) {
    glm::dvec3 nrm(0.0);
    const size_t n = p.size();
    for (size_t i = 0; i < n; ++i) {
      const glm::dvec3 &a = p[i], &b = p[(i + 1) % n];
      nrm.x += (a.y - b.y) * (a.z + b.z);
      nrm.y += (a.z - b.z) * (a.x + b.x);
      nrm.z += (a.x - b.x) * (a.y + b.y);
    }
    return nrm;
  };
  auto convex_definition = [](const std::vector<glm::dvec3>& p, glm::dvec3 nrm) {
    const size_t n = p.size();
    for (size_t i = 0; i < n; ++i) {
      const glm::dvec3 &a = p[i], &b = p[(i + 1) % n], &c = p[(i + 2) % n];
      if (glm::dot(glm::cross(b - a, c - b), nrm) < 0) return false;
    }
    return true;
  };
  // To the bit, except that a NaN is any NaN (which of two NaN operands an addition passes
  // on depends on the order the compiler writes them in; the writers only compare with it).
  auto same_bits = [](glm::dvec3 a, glm::dvec3 b) {
    for (int i = 0; i < 3; ++i) {
      if (std::isnan(a[i]) && std::isnan(b[i])) continue;
      if (std::memcmp(&a[i], &b[i], sizeof a[i]) != 0) return false;
    }
    return true;
  };
  std::mt19937_64 rng(18);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> lattice(-2, 2);
  const double specials[] = {0.0, -0.0, 1e-300, -1e-300, 1e300, -1e300,
                             std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN()};
  int convex = 0, clipped = 0;
  for (int round = 0; round < 200000; ++round) {
    std::vector<glm::dvec3> p(static_cast<size_t>(round % 7 == 6 ? 3 + round / 7 % 4 : 4));
    for (glm::dvec3& q : p) {
      switch (round % 6) {
        case 0: q = {unit(rng), unit(rng), unit(rng)}; break;                                      // any quad
        case 1: q = {unit(rng), unit(rng), 0.0}; break;                                            // planar
        case 2: q = {double(lattice(rng)), double(lattice(rng)), double(lattice(rng) & 1)}; break;  // exact zeros
        case 3: q = {unit(rng) * 1e-160, unit(rng) * 1e-160, unit(rng) * 1e-160}; break;           // underflow
        case 4: q = {unit(rng) * 1e150, unit(rng) * 1e150, unit(rng) * 1e150}; break;              // overflow
        default: q = {specials[rng() % 8], unit(rng), specials[rng() % 8]}; break;
      }
    }
    if (round % 11 == 0) p[rng() % p.size()] = p[rng() % p.size()];  // a repeated corner
    kernel::PolygonSoup s;
    std::vector<int32_t> v;
    for (const glm::dvec3& q : p) v.push_back(s.add_vertex(q));
    const int32_t n = static_cast<int32_t>(v.size());
    const glm::dvec3 nrm = newell_definition(p);
    ASSERT_TRUE(same_bits(write_detail::newell(s.positions.data(), v.data(), n), nrm)) << "round " << round;
    const bool expected = convex_definition(p, nrm);
    ASSERT_EQ(write_detail::is_convex(s.positions.data(), v.data(), n, nrm), expected) << "round " << round;
    if (n == 4) {
      ASSERT_EQ(write_detail::is_convex_quad(s.positions.data(), v.data()), expected) << "round " << round;
      ++(expected ? convex : clipped);
    }
  }
  // Both outcomes are exercised, many times.
  EXPECT_GT(convex, 10000);
  EXPECT_GT(clipped, 10000);
}

// `nomec --emit stl` runs the pipeline without polygon lists (PipelineOptions::polygon_lists)
// and writes binary STL from the meshes: the same bytes as from the lists, for a scene with
// an ear-clipped face (an L-shaped hexagon), triangles, borders and a Möbius band, merged
// only (the hexagon stays one face) and merged, subdivided and offset.
TEST(Write, BinaryStlFromTheMeshesEqualsTheListedPolygons) {
  const std::string scene =
      "mesh ell\n"
      "  point a (0 0 0) endpoint point b (2 0 0) endpoint point c (2 1 0) endpoint\n"
      "  point d (1 1 0) endpoint point e (1 2 0) endpoint point f (0 2 0) endpoint\n"
      "  point g (3 0 0) endpoint point h (3 1 0) endpoint point k (1 3 0) endpoint\n"
      "  face l (a b c d e f) endface face q (b g h c) endface face t (f e k) endface\n"
      "endmesh\n"
      "mesh band\n"
      "  point a0 (1 0 0.2) endpoint point b0 (1 0 -0.2) endpoint\n"
      "  point a1 (0 1 0.2) endpoint point b1 (0 1 -0.2) endpoint\n"
      "  point a2 (-1 0 0.2) endpoint point b2 (-1 0 -0.2) endpoint\n"
      "  point a3 (0 -1 0.2) endpoint point b3 (0 -1 -0.2) endpoint\n"
      "  face f0 (a0 b0 b1 a1) endface face f1 (a1 b1 b2 a2) endface\n"
      "  face f2 (a2 b2 b3 a3) endface face f3 (a3 b3 a0 b0) endface\n"
      "endmesh\n"
      "instance i ell endinstance\n"
      "instance j band translate (6 0 0) endinstance\n";
  PipelineOptions merge_only;
  merge_only.is_merge = true;
  PipelineOptions all = merge_only;
  all.subdivide_levels = 1;
  all.offset_height = 0.03;
  for (const PipelineOptions& base : {merge_only, all}) {
    std::string listed, from_meshes;
    for (const bool lists : {true, false}) {
      auto e = eval(scene);
      ASSERT_EQ(e->diags.error_count(), 0);
      PipelineOptions o = base;
      o.polygon_lists = lists;
      const std::vector<OutputMesh> out = run_pipeline(std::move(e->meshes), o, "x", {}, e->diags);
      ASSERT_EQ(e->diags.error_count(), 0);
      ASSERT_EQ(out.size(), 1u);
      ASSERT_GT(out[0].mesh.face_count(), 0);
      EXPECT_EQ(out[0].soup.face_count(), lists ? out[0].mesh.face_count() : 0);
      if (lists && base.subdivide_levels == 0) {
        // The hexagon is ear clipped, not fanned: the clipping path is exercised.
        const kernel::PolygonSoup& s = out[0].soup;
        std::vector<int32_t> fan;
        size_t at = 0;
        for (int32_t f = 0; f < s.face_count(); ++f) {
          for (int32_t i = 1; i + 1 < s.face_sizes[f]; ++i) {
            fan.insert(fan.end(), {s.face_vertices[at], s.face_vertices[at + i], s.face_vertices[at + i + 1]});
          }
          at += static_cast<size_t>(s.face_sizes[f]);
        }
        EXPECT_NE(triangulate(s), fan);
      }
      // The band is one-sided (so the offset takes its path for Möbius edges); its offset
      // is the boundary of a solid, two-sided.
      EXPECT_EQ(out[0].mesh.has_mobius_edges(), base.offset_height == 0);
      std::string& bytes = lists ? listed : from_meshes;
      ASSERT_TRUE(write_stl_binary(out, [&](std::string_view piece) {
        bytes.append(piece);
        return true;
      }));
    }
    EXPECT_GT(listed.size(), 84u + 50u * 10u);
    EXPECT_EQ(listed, from_meshes) << (base.offset_height > 0 ? "merged, subdivided, offset" : "merged");
  }
}

// The streamed binary STL: pieces of about a megabyte whose concatenation is the header,
// the triangle count and one record per triangle of `triangulate` (an ear-clipped L shape
// among 25,000 fanned quads, so the file spans several pieces); a sink that refuses stops
// the writer.
TEST(Write, StreamedBinaryStlHoldsEveryTriangleInOrder) {
  OutputMesh m;
  kernel::PolygonSoup& s = m.soup;
  for (glm::dvec3 p : {glm::dvec3(0, 0, 0), glm::dvec3(2, 0, 0), glm::dvec3(2, 1, 0),
                       glm::dvec3(1, 1, 0), glm::dvec3(1, 2, 0), glm::dvec3(0, 2, 0)}) {
    s.add_vertex(p);
  }
  for (int i = 0; i < 25000; ++i) {
    const int32_t a = s.add_vertex({i, 5, 0.5 * i});
    s.add_vertex({i + 1, 5, 0});
    s.add_vertex({i + 1, 6, 0.25});
    s.add_vertex({i, 6, 0});
    s.add_face({a, a + 1, a + 2, a + 3});
    if (i == 100) s.add_face({0, 1, 2, 3, 4, 5});
  }
  const std::vector<int32_t> t = triangulate(s);
  std::string bytes;
  int pieces = 0;
  ASSERT_TRUE(write_stl_binary(std::span<const OutputMesh>(&m, 1), [&](std::string_view piece) {
    EXPECT_LE(piece.size(), 1'100'000u);
    bytes.append(piece);
    ++pieces;
    return true;
  }));
  EXPECT_GT(pieces, 1);
  const size_t count = t.size() / 3;
  ASSERT_EQ(bytes.size(), 84 + 50 * count);
  uint32_t header_count = 0;
  std::memcpy(&header_count, bytes.data() + 80, 4);
  EXPECT_EQ(header_count, count);
  for (size_t k = 0; k < count; ++k) {
    float f[12];
    std::memcpy(f, bytes.data() + 84 + 50 * k, sizeof f);
    for (int j = 0; j < 3; ++j) {
      const glm::dvec3& p = s.positions[t[3 * k + j]];
      ASSERT_EQ(glm::vec3(f[3 + 3 * j], f[4 + 3 * j], f[5 + 3 * j]), glm::vec3(p)) << "triangle " << k;
    }
    ASSERT_EQ(bytes[84 + 50 * k + 48] | bytes[84 + 50 * k + 49], 0);
  }
  EXPECT_EQ(to_stl_binary(std::span<const OutputMesh>(&m, 1)), bytes);
  int calls = 0;
  EXPECT_FALSE(write_stl_binary(std::span<const OutputMesh>(&m, 1), [&](std::string_view) { return ++calls < 1; }));
  EXPECT_EQ(calls, 1);
  // The overlapped writer (sink on a second thread, two buffers in turn) hands over the
  // same pieces in the same order, each intact while the next one is being made.
  std::vector<std::string> serial_pieces;
  ASSERT_TRUE(write_stl_binary(std::span<const OutputMesh>(&m, 1), [&](std::string_view piece) {
    serial_pieces.emplace_back(piece);
    return true;
  }));
  std::vector<std::string> overlapped_pieces;
  const std::thread::id caller = std::this_thread::get_id();
  ASSERT_TRUE(write_stl_binary_overlapped(std::span<const OutputMesh>(&m, 1), [&](std::string_view piece) {
    EXPECT_NE(std::this_thread::get_id(), caller);
    std::this_thread::sleep_for(std::chrono::milliseconds(2));  // the next piece is being made meanwhile
    overlapped_pieces.emplace_back(piece);
    return true;
  }));
  EXPECT_EQ(overlapped_pieces, serial_pieces);
  // A failing sink stops it: the piece after the failure is not written.
  int overlapped_calls = 0;
  EXPECT_FALSE(write_stl_binary_overlapped(std::span<const OutputMesh>(&m, 1),
                                           [&](std::string_view) { return ++overlapped_calls < 2; }));
  EXPECT_EQ(overlapped_calls, 2);
}

// The streamed text writers (what `nomec --emit stl --stl-ascii` and `--emit obj` write)
// hand over pieces of at most about a megabyte whose concatenation is the file fmt's loops
// make (written out here, independently of number_text.h), for a model of several pieces
// and two named meshes; a sink that refuses stops them.
TEST(Write, StreamedTextWritersMatchFmtAcrossPieces) {
  std::vector<OutputMesh> meshes(2);
  meshes[0].name = "first";
  for (int i = 0; i < 12000; ++i) {
    kernel::PolygonSoup& s = meshes[0].soup;
    const double x = 0.1 * i, y = -1.0 / (i + 1), z = i * 1e-7;
    const int32_t a = s.add_vertex({x, y, z});
    s.add_vertex({x + 1.5, y * 3.25, -z});
    s.add_vertex({x + 0.3, y + 1e5, 1e17 + i});
    s.add_vertex({x - 7e-5, 2.0 / 3.0, z});
    s.add_face({a, a + 1, a + 2, a + 3});
  }
  meshes[1].soup.add_vertex({0, 0, 0});
  meshes[1].soup.add_vertex({1, 0, -0.0});
  meshes[1].soup.add_vertex({0, 1, 0});
  meshes[1].soup.add_face({0, 1, 2});
  const std::span<const OutputMesh> all(meshes);

  std::string obj = "# written by nomec\n";
  int64_t base = 1;
  std::string stl;
  for (const OutputMesh& m : meshes) {
    const kernel::PolygonSoup& s = m.soup;
    const std::string name = m.name.empty() ? "nomec" : m.name;
    obj += fmt::format("o {}\n", name);
    for (const glm::dvec3& p : s.positions) obj += fmt::format("v {} {} {}\n", p.x + 0.0, p.y + 0.0, p.z + 0.0);
    size_t at = 0;
    for (int32_t f = 0; f < s.face_count(); ++f) {
      obj += "f";
      for (int32_t i = 0; i < s.face_sizes[f]; ++i) obj += fmt::format(" {}", base + s.face_vertices[at + i]);
      obj += "\n";
      at += static_cast<size_t>(s.face_sizes[f]);
    }
    base += s.vertex_count();
    stl += fmt::format("solid {}\n", name);
    const std::vector<int32_t> t = triangulate(s);
    for (size_t k = 0; k < t.size(); k += 3) {
      const glm::dvec3 &a = s.positions[t[k]], &b = s.positions[t[k + 1]], &c = s.positions[t[k + 2]];
      const glm::dvec3 x = glm::cross(b - a, c - a);
      const glm::dvec3 n = glm::length(x) > 0 ? x / glm::length(x) : glm::dvec3(0.0);
      stl += fmt::format("  facet normal {:e} {:e} {:e}\n    outer loop\n", n.x + 0.0, n.y + 0.0, n.z + 0.0);
      for (const glm::dvec3* p : {&a, &b, &c}) {
        stl += fmt::format("      vertex {:e} {:e} {:e}\n", p->x + 0.0, p->y + 0.0, p->z + 0.0);
      }
      stl += "    endloop\n  endfacet\n";
    }
    stl += fmt::format("endsolid {}\n", name);
  }
  ASSERT_GT(obj.size(), 2'000'000u);
  auto pieces_of = [&](auto write) {
    std::string text;
    int pieces = 0;
    EXPECT_TRUE(write([&](std::string_view piece) {
      EXPECT_LE(piece.size(), size_t{1} << 20);
      text.append(piece);
      ++pieces;
      return true;
    }));
    EXPECT_GT(pieces, 1);
    return text;
  };
  EXPECT_EQ(pieces_of([&](const auto& sink) { return write_obj(all, "", sink); }), obj);
  EXPECT_EQ(pieces_of([&](const auto& sink) { return write_stl_ascii(all, sink); }), stl);
  EXPECT_EQ(to_obj(all, ""), obj);
  EXPECT_EQ(to_stl_ascii(all), stl);
  int calls = 0;
  EXPECT_FALSE(write_obj(all, "", [&](std::string_view) { return ++calls < 1; }));
  EXPECT_EQ(calls, 1);
  calls = 0;
  EXPECT_FALSE(write_stl_ascii(all, [&](std::string_view) { return ++calls < 2; }));
  EXPECT_EQ(calls, 2);
}

}  // namespace
}  // namespace nomec::backend
