// Sweeps as NOME3 made them, from first principles (generators-original.md §12): every
// expected position below is written from the section's formulas — the default frame N =
// T × x̂ (T × ŷ along ±x), B = T × N; at a joint T = u_out + u_in, N = u_out − u_in with the
// N coordinate scaled by 1/cos(θ/2); `mintorsion` carries the last ring's N back along the
// path; `azimuth` and `twist` turn the rings; names `v{ring}_{point}` from ring 1; caps —
// and never from nomec's own output.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <map>
#include <sstream>

#include "backend/evaluate.h"
#include "frontend/check/check.h"
#include "tests/backend/evaluated.h"
#include "kernel/topology.h"

namespace nomec::backend {
namespace {

std::unique_ptr<Evaluated> eval(const std::string& text) {
  CheckOptions o;
  o.dialect = Dialect::Nome3;
  return evaluate_text("sweep.nom", text, o);
}

// The sweep's vertices by their NOME3 name (the part after the last dot).
std::map<std::string, glm::dvec3> by_name(const kernel::PolygonSoup& s) {
  std::map<std::string, glm::dvec3> out;
  for (size_t i = 0; i < s.names.size(); ++i) {
    const std::string& n = s.names[i];
    out[n.substr(n.rfind('.') + 1)] = s.positions[i];
  }
  return out;
}

void expect_at(const std::map<std::string, glm::dvec3>& v, const std::string& name, glm::dvec3 want) {
  auto it = v.find(name);
  ASSERT_NE(it, v.end()) << "no vertex " << name;
  EXPECT_NEAR(it->second.x, want.x, 1e-9) << name;
  EXPECT_NEAR(it->second.y, want.y, 1e-9) << name;
  EXPECT_NEAR(it->second.z, want.z, 1e-9) << name;
}

// A square cross-section (x, y) = (1,0) (0,1) (-1,0) (0,-1), points 0..3.
const std::string kDiamond =
    "point q0 (1 0 0) endpoint\npoint q1 (0 1 0) endpoint\npoint q2 (-1 0 0) endpoint\n"
    "point q3 (0 -1 0) endpoint\npolyline cs (q0 q1 q2 q3) closed endpolyline\n";
const glm::dvec2 kCs[4] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};

std::string sweep_of(const std::string& points, const std::string& path_flags, const std::string& cs_flags = "",
                     bool closed = false) {
  std::string names, text = kDiamond;
  std::istringstream in(points);
  std::string line;
  int k = 0;
  while (std::getline(in, line)) {
    text += "point p" + std::to_string(k) + " (" + line + ") endpoint\n";
    names += (k ? " p" : "p") + std::to_string(k);
    ++k;
  }
  text += "polyline path (" + names + ")" + (closed ? " closed" : "") + " endpolyline\n";
  text += "sweep sw\n  crosssection cs " + cs_flags + " endcrosssection\n  path path " + path_flags +
          " endpath\nendsweep\ninstance s sw endinstance\n";
  return text;
}

TEST(Nome3Sweep, StraightPathAlongZUsesTheDefaultFrame) {
  // T = +z: N = z × x = (0,1,0), B = T × N = (-1,0,0); (x, y) -> P + x N + y B.
  auto e = eval(sweep_of("0 0 0\n0 0 2", ""));
  ASSERT_EQ(e->meshes.size(), 1u);
  auto v = by_name(e->meshes[0].soup);
  EXPECT_EQ(v.size(), 8u);  // the closed cross-section's repeated point is welded
  for (int k = 0; k < 2; ++k) {
    for (int j = 0; j < 4; ++j) {
      expect_at(v, "v" + std::to_string(k + 1) + "_" + std::to_string(j),
                glm::dvec3(-kCs[j].y, kCs[j].x, 2.0 * k));
    }
  }
  EXPECT_EQ(e->meshes[0].soup.face_count(), 4);
}

TEST(Nome3Sweep, StraightPathAlongYAndAlongX) {
  // T = +y: N = y × x = (0,0,-1), B = y × N = (-1,0,0).
  auto y = by_name(eval(sweep_of("0 0 0\n0 3 0", ""))->meshes.at(0).soup);
  expect_at(y, "v2_0", {0, 3, -1});
  expect_at(y, "v2_1", {-1, 3, 0});
  // T = +x: N = x × y = (0,0,1), B = x × N = (0,-1,0).
  auto x = by_name(eval(sweep_of("0 0 0\n3 0 0", ""))->meshes.at(0).soup);
  expect_at(x, "v2_0", {3, 0, 1});
  expect_at(x, "v2_1", {3, -1, 0});
}

TEST(Nome3Sweep, LPathMitresTheJoint) {
  // Along +x to (1,0,0), then along +y. Ring 1: T = x, N = (0,0,1), B = (0,-1,0). Ring 2 (the
  // joint): T = (1,1,0)/√2, N = (-1,1,0)/√2, B = T × N = (0,0,1), the N coordinate scaled by
  // 1/cos 45° = √2, so (x, y) -> (1,0,0) + (-x, x, y). Ring 3: T = y, N = (0,0,-1), B = (-1,0,0), at (1,1,0).
  auto e = eval(sweep_of("0 0 0\n1 0 0\n1 1 0", ""));
  auto v = by_name(e->meshes.at(0).soup);
  for (int j = 0; j < 4; ++j) {
    const double x = kCs[j].x, y = kCs[j].y;
    const std::string s = "_" + std::to_string(j);
    expect_at(v, "v1" + s, {0, -y, x});
    expect_at(v, "v2" + s, {1 - x, x, y});
    expect_at(v, "v3" + s, {1 - y, 1, -x});
  }
}

TEST(Nome3Sweep, MintorsionCarriesTheLastRingsFrameBack) {
  // With mintorsion every ring's x axis is the last ring's N = (0,0,-1) (the L is planar, so
  // parallel transport keeps it), its y axis T × (0,0,-1). Ring 2's y axis is the joint's N,
  // so the miter stretches y: (x, y) -> (1,0,0) + (-y, y, -x).
  auto e = eval(sweep_of("0 0 0\n1 0 0\n1 1 0", "mintorsion"));
  auto v = by_name(e->meshes.at(0).soup);
  for (int j = 0; j < 4; ++j) {
    const double x = kCs[j].x, y = kCs[j].y;
    const std::string s = "_" + std::to_string(j);
    expect_at(v, "v1" + s, {0, y, -x});
    expect_at(v, "v2" + s, {1 - y, y, -x});
    expect_at(v, "v3" + s, {1 - y, 1, -x});
  }
}

TEST(Nome3Sweep, ClosedSquarePathIsMitredAtEveryCornerAndWelded) {
  // Every point of a closed path is a joint. At (0,0,0): u_in = -y, u_out = +x, T = (1,-1,0)/√2,
  // N = (1,1,0)/√2, B = z, N scaled by √2: (x, y) -> (x, x, y). At (1,1,0): N = (-1,-1,0)/√2,
  // B = z: (x, y) -> (1 - x, 1 - x, y). The fifth ring repeats the first and is welded.
  auto e = eval(sweep_of("0 0 0\n1 0 0\n1 1 0\n0 1 0", "", "", true));
  const OutputMesh& m = e->meshes.at(0);
  auto v = by_name(m.soup);
  EXPECT_EQ(v.size(), 16u);
  EXPECT_EQ(m.soup.face_count(), 16);
  EXPECT_EQ(kernel::topology(m.mesh).euler_characteristic, 0);
  for (int j = 0; j < 4; ++j) {
    const double x = kCs[j].x, y = kCs[j].y;
    expect_at(v, "v1_" + std::to_string(j), {x, x, y});
    expect_at(v, "v3_" + std::to_string(j), {1 - x, 1 - x, y});
  }
  EXPECT_EQ(v.count("v5_0"), 0u);
}

TEST(Nome3Sweep, AzimuthAndTwistTurnTheRings) {
  // Along +x (N = z, B = -y), three rings turned by azimuth + twist·k/2 = 90°, 135°, 180°:
  // (x, y) -> (x cos a - y sin a) N + (x sin a + y cos a) B.
  auto e = eval(sweep_of("0 0 0\n1 0 0\n2 0 0", "azimuth 90 twist 90"));
  auto v = by_name(e->meshes.at(0).soup);
  for (int k = 0; k < 3; ++k) {
    const double a = (90.0 + 45.0 * k) * M_PI / 180.0;
    for (int j = 0; j < 4; ++j) {
      const double x = kCs[j].x, y = kCs[j].y;
      const double xr = x * std::cos(a) - y * std::sin(a), yr = x * std::sin(a) + y * std::cos(a);
      expect_at(v, "v" + std::to_string(k + 1) + "_" + std::to_string(j), {double(k), -yr, xr});
    }
  }
}

// The smallest rotation taking unit a to unit b, applied to v (Rodrigues).
glm::dvec3 turn(glm::dvec3 v, glm::dvec3 a, glm::dvec3 b) {
  const glm::dvec3 k = glm::cross(a, b);
  const double s = glm::length(k), c = glm::dot(a, b);
  if (s < 1e-12) return v;
  const glm::dvec3 u = k / s;
  return v * c + glm::cross(u, v) * s + u * glm::dot(u, v) * (1 - c);
}

TEST(Nome3Sweep, MintorsionOnAHelixIsParallelTransport) {
  // A helix-like polyline (quarter turns rising 0.5). From each ring's vertices v_k_0 (the
  // cross-section's (1,0)) undo the miter to get the ring's x axis X_k; then X_k ⊥ T_k, the
  // last X is the default N = T × x̂, and straightening X_k and X_{k+1} onto their segment
  // gives the same vector (no turn about the path between rings).
  std::string pts;
  std::vector<glm::dvec3> P;
  for (int k = 0; k < 6; ++k) {
    P.push_back({std::cos(k * M_PI / 2), std::sin(k * M_PI / 2), 0.5 * k});
    pts += std::to_string(P.back().x) + " " + std::to_string(P.back().y) + " " + std::to_string(P.back().z) + "\n";
  }
  // std::to_string keeps 6 decimals: use the values the file says.
  for (auto& p : P) p = glm::dvec3(std::round(p.x * 1e6) / 1e6, std::round(p.y * 1e6) / 1e6, p.z);
  auto e = eval(sweep_of(pts, "mintorsion"));
  auto v = by_name(e->meshes.at(0).soup);
  const size_t n = P.size();
  std::vector<glm::dvec3> u, T(n), X(n);
  for (size_t k = 0; k + 1 < n; ++k) u.push_back(glm::normalize(P[k + 1] - P[k]));
  for (size_t k = 0; k < n; ++k) {
    const glm::dvec3 d = v.at("v" + std::to_string(k + 1) + "_0") - P[k];
    if (k == 0 || k + 1 == n) {
      T[k] = k == 0 ? u[0] : u[n - 2];
      X[k] = d;
    } else {
      const glm::dvec3 s = u[k - 1] + u[k];
      T[k] = glm::normalize(s);
      const glm::dvec3 N = glm::normalize(u[k] - u[k - 1]);
      X[k] = d + (glm::length(s) / 2 - 1) * glm::dot(d, N) * N;  // undo the 1/cos(θ/2)
    }
    EXPECT_NEAR(glm::length(X[k]), 1.0, 1e-9) << k;
    EXPECT_NEAR(glm::dot(X[k], T[k]), 0.0, 1e-9) << k;
  }
  const glm::dvec3 last = glm::normalize(glm::cross(T[n - 1], glm::dvec3(1, 0, 0)));
  EXPECT_NEAR(glm::length(X[n - 1] - last), 0.0, 1e-9);
  for (size_t k = 0; k + 1 < n; ++k) {
    const glm::dvec3 a = turn(X[k], T[k], u[k]), b = turn(X[k + 1], T[k + 1], u[k]);
    EXPECT_NEAR(glm::length(a - b), 0.0, 1e-9) << "segment " << k;
  }
  // Without mintorsion the joints keep their bend-plane N: ring 2's x axis, stretched, is
  // along N = u_out − u_in.
  auto plain = by_name(eval(sweep_of(pts, ""))->meshes.at(0).soup);
  const glm::dvec3 N1 = glm::normalize(u[1] - u[0]);
  EXPECT_NEAR(glm::length(glm::cross(plain.at("v2_0") - P[1], N1)), 0.0, 1e-9);
}

TEST(Nome3Sweep, CapsAreTheFirstRingReversedAndTheLastRing) {
  auto e = eval(sweep_of("0 0 0\n0 0 2", "", "begincap endcap"));
  const kernel::PolygonSoup& s = e->meshes.at(0).soup;
  ASSERT_EQ(s.face_count(), 6);
  auto face_names = [&](int32_t f) {
    int32_t at = 0;
    for (int32_t i = 0; i < f; ++i) at += s.face_sizes[i];
    std::vector<std::string> out;
    for (int32_t i = 0; i < s.face_sizes[f]; ++i) {
      const std::string& n = s.names[s.face_vertices[at + i]];
      out.push_back(n.substr(n.rfind('.') + 1));
    }
    return out;
  };
  EXPECT_EQ(face_names(4), (std::vector<std::string>{"v1_3", "v1_2", "v1_1", "v1_0"}));
  EXPECT_EQ(face_names(5), (std::vector<std::string>{"v2_0", "v2_1", "v2_2", "v2_3"}));
  EXPECT_TRUE(kernel::topology(e->meshes.at(0).mesh).is_closed);
}

TEST(Nome3Sweep, VertexNamesResolveAsInstanceDotName) {
  // A face over `s.v1_0 s.v2_0 s.v2_1` of the +z sweep: (0,1,0), (0,1,2), (-1,0,2).
  auto e = eval(sweep_of("0 0 0\n0 0 2", "") +
                "mesh tri face t (s.v1_0 s.v2_0 s.v2_1) endface endmesh\ninstance it tri endinstance\n");
  ASSERT_EQ(e->meshes.size(), 2u);
  const kernel::PolygonSoup& t = e->meshes[1].soup;
  ASSERT_EQ(t.face_count(), 1);
  const glm::dvec3 want[3] = {{0, 1, 0}, {0, 1, 2}, {-1, 0, 2}};
  for (int i = 0; i < 3; ++i) {
    const glm::dvec3 p = t.positions[t.face_vertices[i]];
    EXPECT_NEAR(glm::length(p - want[i]), 0.0, 1e-9) << i;
  }
}

TEST(Nome3Sweep, NamesOfNome3sRepeatedVerticesResolveToTheWeldedOnes) {
  // NOME3 repeats a closed cross-section's first point (`v{k}_4` for 4 points) and a closed
  // path's first ring (ring 5 of a 4-point path); nomec welds both, and the names still
  // resolve: s.v1_4 = s.v1_0 = (1,1,0), s.v5_1 = s.v1_1 = (0,0,1), s.v5_4 = s.v1_0.
  auto e = eval(sweep_of("0 0 0\n1 0 0\n1 1 0\n0 1 0", "", "", true) +
                "mesh tri face t (s.v1_4 s.v5_1 s.v3_0) endface endmesh\ninstance it tri endinstance\n"
                "mesh tri2 face t (s.v5_4 s.v2_0 s.v3_0) endface endmesh\ninstance it2 tri2 endinstance\n");
  ASSERT_EQ(e->meshes.size(), 3u);
  const kernel::PolygonSoup& t = e->meshes[1].soup;
  ASSERT_EQ(t.face_count(), 1);
  EXPECT_NEAR(glm::length(t.positions[t.face_vertices[0]] - glm::dvec3(1, 1, 0)), 0.0, 1e-9);
  EXPECT_NEAR(glm::length(t.positions[t.face_vertices[1]] - glm::dvec3(0, 0, 1)), 0.0, 1e-9);
  const kernel::PolygonSoup& t2 = e->meshes[2].soup;
  EXPECT_NEAR(glm::length(t2.positions[t2.face_vertices[0]] - glm::dvec3(1, 1, 0)), 0.0, 1e-9);
  // An open cross-section has no repeated point: `v1_2` of a 2-point one names nothing.
  std::string text = "point a (1 0 0) endpoint\npoint b (-1 0 0) endpoint\npolyline seg (a b) endpolyline\n"
                     "point p0 (0 0 0) endpoint\npoint p1 (0 0 1) endpoint\npolyline path (p0 p1) endpolyline\n"
                     "sweep sw crosssection seg endcrosssection path path endpath endsweep\n"
                     "instance s sw endinstance\nmesh m face f (s.v1_2 s.v2_0 s.v2_1) endface endmesh\n"
                     "instance im m endinstance\n";
  auto bad = std::make_unique<Evaluated>();
  CheckOptions o;
  o.dialect = Dialect::Nome3;
  bad->check = check_source(bad->sources, "bad.nom", text, o, bad->diags);
  bad->meshes = evaluate_scene(bad->check.module, bad->diags);
  EXPECT_GT(bad->diags.error_count(), 0);
}

TEST(Nome3Sweep, ClosedPathWhoseEndsDoNotMeetKeepsTheSeamOpenWithAWarning) {
  // A twist of 90° around a closed square: the fifth ring (NOME3's repeat of the first) is
  // turned by 90° against the first, so it stays, named v5_*, and the tube is open there.
  auto e = eval(sweep_of("0 0 0\n1 0 0\n1 1 0\n0 1 0", "twist 90", "", true));
  auto v = by_name(e->meshes.at(0).soup);
  EXPECT_EQ(v.size(), 20u);
  EXPECT_EQ(e->meshes.at(0).soup.face_count(), 16);
  // Ring 5 at (0,0,0), turned 90°: (x, y) -> (-y, x) then mapped as ring 1: (-y, -y, x).
  for (int j = 0; j < 4; ++j) expect_at(v, "v5_" + std::to_string(j), {-kCs[j].y, -kCs[j].y, kCs[j].x});
  bool warned = false;
  for (const auto& d : e->diags.diagnostics()) warned = warned || d.kind == DiagKind::SweepSeamOpen;
  EXPECT_TRUE(warned);
}

TEST(Nome3Sweep, TorusKnotWithoutTubeIsASweepPath) {
  // generators-original.md §3.4: `torusknot` with tube_radius 0 is the open line strip
  // knotpoint0 … knotpoint{sweep_segs − 1}, used as a sweep path. Ring k (from 1) sits at
  // knotpoint{k−1}: its four diamond points average to it (x and y coordinates cancel
  // pairwise, whatever the frame and the miter scale on N), and 9 gaps of 4 quads join the
  // 10 rings.
  auto e = eval(kDiamond +
                "torusknot k (2 3 2 0.5 0 6 10) endtorusknot\n"
                "sweep sw crosssection cs endcrosssection path k endpath endsweep\ninstance s sw endinstance\n");
  ASSERT_EQ(e->meshes.size(), 1u);
  auto v = by_name(e->meshes[0].soup);
  EXPECT_EQ(v.size(), 40u);
  EXPECT_EQ(e->meshes[0].soup.face_count(), 36);
  for (int k = 0; k < 10; ++k) {
    const double t = 2 * M_PI * k / 10;
    const glm::dvec3 centre((2 + 0.5 * std::cos(2 * t)) * std::cos(3 * t), (2 + 0.5 * std::cos(2 * t)) * std::sin(3 * t),
                            0.5 * std::sin(2 * t));
    glm::dvec3 mid(0, 0, 0);
    for (int j = 0; j < 4; ++j) mid += v.at("v" + std::to_string(k + 1) + "_" + std::to_string(j)) / 4.0;
    EXPECT_NEAR(glm::length(mid - centre), 0.0, 1e-9) << "ring " << k + 1;
  }
}

}  // namespace
}  // namespace nomec::backend
