// Inputs are bounded (issue 45, "Unbounded inputs"): one scene per defect found, written by
// the test into a folder of its own. An included FIFO once blocked forever and `/dev/zero`
// grew a string to 2 GB: they are refused without being read. A 4-line file that includes
// itself four times grew exponentially: includes stop at a depth, a count and a byte budget
// in which a repeat counts again, with one `IncludeLimit` error naming the chain. Nested
// instancing of 10^7 instances reached 2.5 GB, and past the vertex budget the walk still
// visited every instance: the budget is applied to instances × vertices before anything is
// built (`SceneTooLarge` naming the chain), and the walk stops where it runs out. Checking
// saved work parsed every mesh beside it: only the candidates that can win are read. A face
// of millions of repeated names was checked pair by pair with an error per pair: one pass
// and at most 10 errors now.
//
// The scenes that once hung or exhausted memory run in a child process with an alarm and
// (unless sanitized) a 1 GiB address space, so a regression fails the test instead of
// hanging or swapping the machine.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <set>
#include <string>
#include <vector>

#include "backend/evaluate.h"
#include "backend/session.h"
#include "base/file_io.h"
#include "frontend/check/check.h"

namespace nomec {
namespace {

namespace fs = std::filesystem;

constexpr unsigned kAlarmSeconds = 120;  // far above what any of these takes; only "hung" trips it

class BoundedInputs : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("nomec_bounded_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  fs::path dir_;
};

// A check of the file at `path` as the command line does it: the file and what it reads
// under `max_bytes`, through the one reader.
struct Checked {
  SourceManager sources;
  DiagnosticEngine diags;
  CheckResult result;
  std::vector<std::string> reads;  // every path the checker asked for

  std::vector<const Diagnostic*> of(DiagKind kind) const {
    std::vector<const Diagnostic*> out;
    for (const Diagnostic& d : diags.diagnostics()) {
      if (d.kind == kind) out.push_back(&d);
    }
    return out;
  }
  std::string all() const {
    std::string out;
    for (const Diagnostic& d : diags.diagnostics()) out += std::string(diag_kind_name(d.kind)) + ": " + d.message + "\n";
    return out;
  }
};

std::unique_ptr<Checked> check_file(const std::string& path, int64_t max_bytes = kDefaultMaxFileBytes) {
  auto c = std::make_unique<Checked>();
  FileRead main = read_input_file(path, max_bytes);
  EXPECT_TRUE(main.ok()) << main.error;
  CheckOptions options;
  InputReader reader = input_reader(max_bytes);
  options.read_file = [&reads = c->reads, read = reader.read](const std::string& p) {
    reads.push_back(p);
    return read(p);
  };
  options.read_problem = reader.problem;
  options.list_folder = list_folder;
  options.max_input_bytes = max_bytes;
  c->result = check_source(c->sources, path, std::move(main.bytes), options, c->diags);
  c->diags.sort_and_dedupe();
  return c;
}

void limit(int resource, rlim_t value) {
  struct rlimit rl {};
  getrlimit(resource, &rl);
  rl.rlim_cur = rl.rlim_max != RLIM_INFINITY && rl.rlim_max < value ? rl.rlim_max : value;
  setrlimit(resource, &rl);
}

// Runs `body` in a child process that an alarm ends after kAlarmSeconds and that may use 1
// GiB of address space; the child exits 0 when `body` returns "" and otherwise prints what
// it returned. Its peak resident memory must stay under 1 GiB too.
void expect_bounded(const std::function<std::string()>& body) {
  EXPECT_EXIT(
      {
        alarm(kAlarmSeconds);
#ifndef NOMEC_SANITIZED
        // Under AddressSanitizer the address space holds the shadow memory (terabytes
        // reserved up front): no cap on it can express this budget there.
        limit(RLIMIT_AS, rlim_t{1} << 30);
#endif
        std::string problem = body();
        struct rusage usage {};
        getrusage(RUSAGE_SELF, &usage);
        if (problem.empty() && usage.ru_maxrss > (1L << 20)) {
          problem = "peak resident memory " + std::to_string(usage.ru_maxrss) + " KiB, more than 1 GiB";
        }
        std::cerr << problem;
        std::_Exit(problem.empty() ? 0 : 1);
      },
      ::testing::ExitedWithCode(0), "");
}

std::string repeat(std::string_view s, int n) {
  std::string out;
  for (int i = 0; i < n; ++i) out += s;
  return out;
}

// ---- files that are not regular files ----

// `include` of a FIFO waited forever for a writer; now it is refused at once, and the check
// goes on (the mesh after it is still defined).
TEST_F(BoundedInputs, AnIncludedFifoIsRefusedWithoutBlocking) {
  ASSERT_EQ(::mkfifo(path("pipe.slf").c_str(), 0600), 0);
  ASSERT_EQ(::mkfifo(path("pipe.stl").c_str(), 0600), 0);
  const std::string scene = write("scene.nome",
                                  "include \"pipe.slf\"\n"
                                  "include \"pipe.stl\"\n"
                                  "point a (0 0 0) endpoint\n");
  expect_bounded([&]() -> std::string {
    auto c = check_file(scene);
    const auto failed = c->of(DiagKind::IncludeFailed);
    if (failed.size() != 2) return "expected 2 IncludeFailed:\n" + c->all();
    if (failed[0]->message != "cannot read included file `pipe.slf` (looked for `" + path("pipe.slf") +
                                  "`): it is a named pipe (FIFO), not a regular file" ||
        failed[1]->message != "cannot read included mesh file `pipe.stl` (looked for `" + path("pipe.stl") +
                                  "`): it is a named pipe (FIFO), not a regular file") {
      return "wrong messages:\n" + c->all();
    }
    return c->diags.error_count() == 2 ? "" : "other errors:\n" + c->all();
  });
}

// `include "/dev/zero"` read until the string reached 2 GB and aborted; a symbolic link to
// it beside the scene was read the same way.
TEST_F(BoundedInputs, AnIncludedDeviceIsRefusedWithoutReadingIt) {
  fs::create_symlink("/dev/zero", dir_ / "zero.slf");
  const std::string scene = write("scene.nome", "include \"/dev/zero\"\ninclude \"zero.slf\"\n");
  expect_bounded([&]() -> std::string {
    auto c = check_file(scene);
    const auto failed = c->of(DiagKind::IncludeFailed);
    if (failed.size() != 2) return "expected 2 IncludeFailed:\n" + c->all();
    for (const Diagnostic* d : failed) {
      if (d->message.find("): it is a character device, not a regular file") == std::string::npos) return c->all();
    }
    return "";
  });
}

// A file larger than the cap is refused before it is read: a sparse file of 3 GiB (no disk
// used) as a scene include and as a mesh include.
TEST_F(BoundedInputs, AnIncludedFileLargerThanTheCapIsRefusedUnread) {
  for (const char* name : {"huge.slf", "huge.stl"}) {
    write(name, "x");
    fs::resize_file(dir_ / name, std::uintmax_t{3} << 30);
  }
  const std::string scene = write("scene.nome", "include \"huge.slf\"\ninclude \"huge.stl\"\n");
  expect_bounded([&]() -> std::string {
    auto c = check_file(scene);
    const auto failed = c->of(DiagKind::IncludeFailed);
    if (failed.size() != 2) return "expected 2 IncludeFailed:\n" + c->all();
    // A scene's text and its mesh files each have a cap of their own.
    if (failed[0]->message.find("): it is 3.0 GiB, more than the " + byte_size_text(kDefaultMaxFileBytes) +
                                " nomec reads (`--max-file-size`)") == std::string::npos ||
        failed[1]->message.find("): it is 3.0 GiB, more than the " + byte_size_text(kDefaultMaxMeshFileBytes) +
                                " nomec reads (`--max-mesh-size`)") == std::string::npos) {
      return c->all();
    }
    return "";
  });
}

// Mesh files for 3D printing are megabytes to tens of megabytes: a binary STL past the
// scene text's cap is read under the mesh cap, and one past that is refused naming it.
TEST_F(BoundedInputs, MeshFilesHaveACapOfTheirOwn) {
  const int triangles = 120'000;  // 6 MB, three times the text cap
  std::string stl(80, '\0');
  auto u32 = [&](uint32_t v) { stl.append(reinterpret_cast<const char*>(&v), 4); };
  auto f32 = [&](float v) { stl.append(reinterpret_cast<const char*>(&v), 4); };
  u32(triangles);
  for (int t = 0; t < triangles; ++t) {
    const float x = static_cast<float>(t % 400), y = static_cast<float>(t / 400);
    for (float v : {0.f, 0.f, 1.f, x, y, 0.f, x + 1, y, 0.f, x, y + 1, 0.f}) f32(v);
    stl.append(2, '\0');
  }
  write("big.stl", stl);
  ASSERT_GT(static_cast<int64_t>(stl.size()), kDefaultMaxFileBytes);
  const std::string scene = write("scene.nome", "include \"big.stl\"\ninstance b big endinstance\n");
  auto c = check_file(scene);
  EXPECT_TRUE(c->of(DiagKind::IncludeFailed).empty()) << c->all();
  EXPECT_EQ(c->diags.error_count(), 0u) << c->all();
  // Under a smaller mesh cap it is refused, and the message names the mesh cap's flag.
  CheckOptions options;
  InputReader reader = input_reader(kDefaultMaxFileBytes, int64_t{1} << 20);
  options.read_file = reader.read;
  options.read_problem = reader.problem;
  options.max_mesh_bytes = int64_t{1} << 20;
  SourceManager sources;
  DiagnosticEngine diags;
  check_source(sources, scene, read_input_file(scene).bytes, options, diags);
  bool named = false;
  for (const Diagnostic& d : diags.diagnostics()) {
    named = named || (d.kind == DiagKind::IncludeFailed && d.message.find("`--max-mesh-size`") != std::string::npos);
  }
  EXPECT_TRUE(named);
}

// ---- include bombs ----

// A 4-line file that includes itself four times: 4^16 includes before the depth limit once
// stopped it (2.9 GB). Now the first include past 16 levels is one error naming the chain,
// and no include is read after it.
TEST_F(BoundedInputs, AFileThatIncludesItselfStopsAtOneError) {
  const std::string bomb = write("bomb.nome", repeat("include \"bomb.nome\"\n", 4));
  expect_bounded([&]() -> std::string {
    auto c = check_file(bomb);
    const auto limits = c->of(DiagKind::IncludeLimit);
    if (limits.size() != 1 || c->diags.error_count() != 1) return "expected one IncludeLimit:\n" + c->all();
    if (limits[0]->message != "`include \"bomb.nome\"` nests more than 16 files deep: bomb.nome" +
                                  repeat(" → bomb.nome", 17)) {
      return "wrong message: " + limits[0]->message;
    }
    if (c->reads.size() != 16) return "read " + std::to_string(c->reads.size()) + " includes, expected 16";
    return "";
  });
}

// One file included 5000 times: each repeat counts, and the 4097th is refused.
TEST_F(BoundedInputs, IncludesStopAfterTheirCount) {
  write("one.slf", "# nothing but a comment\n");
  const std::string scene = write("many.slf", repeat("include \"one.slf\"\n", 5000));
  expect_bounded([&]() -> std::string {
    auto c = check_file(scene);
    const auto limits = c->of(DiagKind::IncludeLimit);
    if (limits.size() != 1 || c->diags.error_count() != 1) return "expected one IncludeLimit:\n" + c->all();
    if (limits[0]->message != "`include \"one.slf\"` is one more than the 4096 includes nomec reads for one scene, "
                              "repeats counted: many.slf → one.slf") {
      return "wrong message: " + limits[0]->message;
    }
    if (c->sources.line_col(limits[0]->range.file, limits[0]->range.begin).line != 4097) return "not at line 4097";
    return c->reads.size() == 4096 ? "" : "read " + std::to_string(c->reads.size()) + " includes";
  });
}

// The bytes a scene reads with its includes are capped, a repeat counting again: with a cap
// of 1 MiB, a 300 KB file included 20 times is read 3 times, and the 4th include, which
// would bring the scene past the cap, is the one error.
TEST_F(BoundedInputs, IncludedBytesStopAtTheCapCountingRepeats) {
  write("part.slf", repeat("# a comment line of a part that is fifty bytes...\n", 6000));  // 300,000 bytes
  const std::string scene = write("main.slf", "# main\n" + repeat("include \"part.slf\"\n", 20));
  auto c = check_file(scene, int64_t{1} << 20);
  const auto limits = c->of(DiagKind::IncludeLimit);
  ASSERT_EQ(limits.size(), 1u) << c->all();
  EXPECT_EQ(c->diags.error_count(), 1) << c->all();
  EXPECT_EQ(limits[0]->message,
            "`include \"part.slf\"` brings the scene's text to 1.1 MiB, more than the 1.0 MiB nomec reads "
            "(`--max-file-size`): main.slf → part.slf");
  EXPECT_EQ(c->sources.line_col(limits[0]->range.file, limits[0]->range.begin).line, 5u);
  EXPECT_EQ(c->reads.size(), 4u);  // three read and kept, the fourth read and refused
}

// ---- the vertex budget against nested instancing ----

// Seven levels of ten instances of a triangle: 10^7 instances of 3 vertices. They were
// placed one by one until memory ran out (2.5 GB); now the scene is refused before anything
// is built, naming the chain of instances that multiplies. Twelve levels count past 10^12
// without overflowing.
std::string nested_groups(int levels, int per_level) {
  std::string text =
      "mesh tri\n  point a (0 0 0) endpoint\n  point b (1 0 0) endpoint\n  point c (0 1 0) endpoint\n"
      "  face f (a b c) endface\nendmesh\n";
  std::string below = "tri";
  for (int level = 1; level <= levels; ++level) {
    const std::string name = "g" + std::to_string(level);
    text += "group " + name + "\n";
    for (int k = 0; k < per_level; ++k) {
      text += "  instance i" + std::to_string(k) + " " + below + " translate (" + std::to_string(k) + " 0 0) endinstance\n";
    }
    text += "endgroup\n";
    below = name;
  }
  return text + "instance top " + below + " endinstance\n";
}

std::string evaluate_problem(const std::string& text, const std::string& expected, int64_t max_vertices) {
  SourceManager sources;
  DiagnosticEngine diags;
  CheckResult r = check_source(sources, "nested.nome", text, CheckOptions{}, diags);
  if (diags.error_count() != 0) return "check errors";
  std::vector<backend::OutputMesh> meshes = backend::evaluate_scene(r.module, diags, nullptr, max_vertices);
  if (!meshes.empty()) return "built " + std::to_string(meshes.size()) + " meshes";
  if (diags.error_count() != 1 || diags.diagnostics()[0].kind != DiagKind::SceneTooLarge) return "expected one SceneTooLarge";
  return diags.diagnostics()[0].message == expected ? "" : "message: " + diags.diagnostics()[0].message;
}

TEST_F(BoundedInputs, NestedInstancesPastTheBudgetAreRefusedBeforeBuilding) {
  expect_bounded([&]() -> std::string {
    std::string problem = evaluate_problem(nested_groups(7, 10),
                                           "instance `top` → `i0` → `i0` → `i0` → `i0` → `i0` → `i0` → `i0` would build "
                                           "30,000,000 vertices; nomec builds at most 1,000,000 (`--max-vertices`)",
                                           backend::kDefaultMaxVertices);
    if (!problem.empty()) return problem;
    return evaluate_problem(nested_groups(12, 10),
                            "instance `top` → `i0` → `i0` → `i0` → `i0` → `i0` → `i0` → `i0` → `i0` → `i0` → `i0` → `i0` "
                            "→ `i0` would build 3,000,000,000,000 vertices; nomec builds at most 1,000,000 "
                            "(`--max-vertices`)",
                            backend::kDefaultMaxVertices);
  });
}

// A scene whose plan fits but whose block results outgrow the budget as they are placed
// (each placement of a subdivided cube costs its 98 vertices, the plan its 8 input ones):
// the walk stops where the budget runs out instead of visiting every later instance, and a
// second entry's 10,000 triangles are not visited at all.
TEST_F(BoundedInputs, TheWalkStopsWhereTheBudgetRunsOut) {
  std::string text =
      "point p0 (0 0 0) endpoint\npoint p1 (1 0 0) endpoint\npoint p2 (1 1 0) endpoint\npoint p3 (0 1 0) endpoint\n"
      "point p4 (0 0 1) endpoint\npoint p5 (1 0 1) endpoint\npoint p6 (1 1 1) endpoint\npoint p7 (0 1 1) endpoint\n"
      "mesh cube\n  face b (p0 p3 p2 p1) endface\n  face t (p4 p5 p6 p7) endface\n  face f (p0 p1 p5 p4) endface\n"
      "  face r (p1 p2 p6 p5) endface\n  face k (p2 p3 p7 p6) endface\n  face l (p3 p0 p4 p7) endface\nendmesh\n"
      "subdivision s type NOME_SD_CC subdivisions 2\n  instance c cube endinstance\nendsubdivision\n";
  text += "group row\n";
  for (int k = 0; k < 100; ++k) text += "  instance s" + std::to_string(k) + " s translate (" + std::to_string(2 * k) + " 0 0) endinstance\n";
  text += "endgroup\ngroup field\n";
  for (int k = 0; k < 100; ++k) text += "  instance r" + std::to_string(k) + " row translate (0 " + std::to_string(2 * k) + " 0) endinstance\n";
  text += "endgroup\ninstance cubes field endinstance\n";
  // A second entry of 100 × 100 triangles (30,000 vertices).
  text += nested_groups(2, 100);
  SourceManager sources;
  DiagnosticEngine diags;
  CheckResult r = check_source(sources, "walk.nome", text, CheckOptions{}, diags);
  ASSERT_EQ(diags.error_count(), 0) << diags.diagnostics()[0].message;
  backend::PipelineOptions limits;
  limits.max_vertices = 200000;  // the plan: 10,000 × 8 + 30,000 fits; placed: 10,000 × 98 does not
  backend::SceneEvaluator ev(r.module, false, limits);
  ev.evaluate(diags);
  ASSERT_EQ(diags.error_count(), 1);
  EXPECT_EQ(diags.diagnostics()[0].kind, DiagKind::SceneTooLarge);
  EXPECT_EQ(diags.diagnostics()[0].message.substr(0, 19), "placing `cubes.r20.");
  // Only the cube inside the block was placed as a leaf: the triangles were never visited.
  EXPECT_LE(ev.take_counters().instances_placed, 1);
}

// ---- diagnostics that grew with the input ----

// A face of 600,000 vertex names repeating three points was checked pair by pair, one error
// per pair (22 GB for a 32 MiB face); in SLIDE the same face was scanned pair by pair. Now
// one pass, at most 10 errors; and a list of the wrong length quotes its first 16 items.
TEST_F(BoundedInputs, AHugeFaceOrListGivesAFewShortErrors) {
  const std::string points = "point a (0 0 0) endpoint\npoint b (1 0 0) endpoint\npoint c (0 1 0) endpoint\n";
  const std::string face = "mesh m\n  face f (" + repeat("a b c ", 200000) + ") endface\nendmesh\n";
  const std::string list = "point p (" + repeat("1 ", 200000) + ") endpoint\n";
  expect_bounded([&]() -> std::string {
    SourceManager sources;
    DiagnosticEngine diags;
    check_source(sources, "face.nome", points + face, CheckOptions{}, diags);
    if (diags.error_count() != 10) return "face.nome: " + std::to_string(diags.error_count()) + " errors, expected 10";
    const Diagnostic& last = diags.diagnostics().back();
    if (last.notes.size() != 2 || last.notes[1].message != "further repeats in this face are not reported one by one") {
      return "the 10th error does not say that more repeats follow";
    }
    DiagnosticEngine slide;
    check_source(sources, "face.slf", points + face, CheckOptions{}, slide);
    int repeated = 0;
    for (const Diagnostic& d : slide.diagnostics()) repeated += d.kind == DiagKind::SlideFaceRepeatedVertex;
    if (repeated != 1) return "face.slf: " + std::to_string(repeated) + " SlideFaceRepeatedVertex, expected 1";
    DiagnosticEngine arity;
    check_source(sources, "list.nome", list, CheckOptions{}, arity);
    if (arity.error_count() != 1) return "list.nome: expected one error";
    const std::string& message = arity.diagnostics()[0].message;
    if (message.size() > 300 || message.find("… (200000 in all)") == std::string::npos) return "list.nome: " + message;
    return "";
  });
}

// In an editing session the plan follows the sliders: a move that makes the scene too large
// is refused before building, and moving back builds it again (the plan of each node is
// kept with the parameters it read, so the move recounts only what read the slider).
TEST_F(BoundedInputs, ThePlanFollowsSliderMoves) {
  std::string text = "bank b\n  set n 10 3 100 1\nendbank\nfunnel f ($b_n 1 0.5 1) endfunnel\n";
  std::string below = "f";
  for (int level = 1; level <= 3; ++level) {
    text += "group g" + std::to_string(level) + "\n";
    for (int k = 0; k < 10; ++k) text += "  instance i" + std::to_string(k) + " " + below + " endinstance\n";
    text += "endgroup\n";
    below = "g" + std::to_string(level);
  }
  text += "instance top g3 endinstance\n";
  SourceManager sources;
  DiagnosticEngine diags;
  CheckResult r = check_source(sources, "slider.nome", text, CheckOptions{}, diags);
  ASSERT_EQ(diags.error_count(), 0);
  backend::SessionOptions options;
  options.pipeline.max_vertices = 50000;  // 1000 funnels of 2n vertices: n = 10 fits, n = 40 does not
  backend::Session session(std::move(r.module), options);
  DiagnosticEngine built;
  session.build(built);
  EXPECT_EQ(built.error_count(), 0);
  ASSERT_EQ(session.outputs().size(), 1u);
  EXPECT_EQ(session.outputs()[0]->soup.vertex_count(), 20000);
  DiagnosticEngine grown;
  session.set_parameter("b.n", 40, grown);
  ASSERT_EQ(grown.error_count(), 1);
  EXPECT_EQ(grown.diagnostics()[0].message,
            "instance `top` → `i0` → `i0` → `i0` would build 80,000 vertices; nomec builds at most 50,000 "
            "(`--max-vertices`)");
  EXPECT_TRUE(session.outputs().empty());
  DiagnosticEngine back;
  session.set_parameter("b.n", 12, back);
  EXPECT_EQ(back.error_count(), 0);
  ASSERT_EQ(session.outputs().size(), 1u);
  EXPECT_EQ(session.outputs()[0]->soup.vertex_count(), 24000);
}

// ---- saved work ----

// Saved work that sets a slider is checked over the scene whose bank has it; the meshes
// beside it cannot qualify (they have no sliders) and are not read, however large.
TEST_F(BoundedInputs, SavedWorkReadsOnlyTheCandidatesItNeeds) {
  write("scene.nom", "bank b\n  set x 1 0 2 0.1\nendbank\npoint p (0 0 0) endpoint\n");
  write("other.nom", "point q (0 0 0) endpoint\n");
  write("mesh.sif", "(shell (vertices 3 (v 0 0 0) (v 1 0 0) (v 0 1 0)) (triangles 1 (t 0 1 2)))\n");
  write("mesh.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const std::string saved = write("work.anom", "savedparameter\n  b_x 1.5\nendsavedparameter\n");
  auto c = check_file(saved);
  EXPECT_EQ(c->result.base_file, path("scene.nom")) << c->all();
  for (const std::string& read : c->reads) {
    EXPECT_EQ(read.find("mesh."), std::string::npos) << read << " was read";
  }

  // Saved work that names no slider and no vertex: every candidate scores 0 unread.
  write("zz.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  fs::remove(dir_ / "scene.nom");
  fs::remove(dir_ / "other.nom");
  fs::remove(dir_ / "mesh.sif");
  fs::remove(dir_ / "mesh.obj");
  const std::string plain = write("plain.anom", "# nothing saved\n");
  auto p = check_file(plain);
  EXPECT_EQ(p->result.base_file, path("zz.obj")) << p->all();
  EXPECT_EQ(p->reads, std::vector<std::string>{path("zz.obj")});  // only to load the base chosen
}

}  // namespace
}  // namespace nomec
