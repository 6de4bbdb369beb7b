// Every slider of every corpus scene written back (issue 45, "never lose the user's text"):
// for each scene of ../shared/corpus (read in place) that checks clean, each slider is moved
// one step with `-D` (up, or down at its maximum), the scene is saved with that value
// (backend::save_scene), the saved copy is written to a temporary folder and read back, and
// checked as if it stood beside the original (so its `source`d Tcl and included files are
// found). It must check without errors, give the slider the moved value, build the same
// meshes as `-D` on the original (every position within a millionth of the scene's size),
// and differ from the original in that one value token only (past the saved header line).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <string>
#include <unistd.h>
#include <vector>

#include "backend/evaluate.h"
#include "backend/save.h"
#include "base/file_io.h"
#include "frontend/check/check.h"
#include "frontend/flat/flat.h"
#include "frontend/source/file_kinds.h"
#include "tests/common/corpus_inputs.h"

namespace nomec {
namespace {

namespace fs = std::filesystem;

struct Checked {
  SourceManager sources;
  DiagnosticEngine diags;
  CheckResult check;
  std::vector<backend::OutputMesh> meshes;
  DiagnosticEngine geometry;
};

std::unique_ptr<Checked> check_and_build(const std::string& path, std::string text,
                                         std::vector<std::pair<std::string, double>> overrides) {
  auto c = std::make_unique<Checked>();
  CheckOptions o;
  o.overrides = std::move(overrides);
  o.allow_out_of_range = true;  // a slider written out of its range moves one step all the same
  o.read_file = read_file_bytes;
  o.list_folder = list_folder;
  c->check = check_source(c->sources, path, std::move(text), o, c->diags);
  if (c->diags.error_count() == 0) c->meshes = backend::evaluate_scene(c->check.module, c->geometry);
  return c;
}

std::string first_error(const DiagnosticEngine& d) {
  for (const Diagnostic& x : d.diagnostics()) {
    if (x.severity == Severity::Error) return x.message;
  }
  return "";
}

// The two mesh lists are the same geometry: names, faces and positions (within `tol`).
void expect_same_meshes(const std::vector<backend::OutputMesh>& a, const std::vector<backend::OutputMesh>& b,
                        const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  double size = 1;
  for (const backend::OutputMesh& m : a) {
    for (const auto& p : m.soup.positions) size = std::max({size, std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
  }
  const double tol = 1e-6 * size;
  for (size_t i = 0; i < a.size(); ++i) {
    const kernel::PolygonSoup& x = a[i].soup;
    const kernel::PolygonSoup& y = b[i].soup;
    EXPECT_EQ(a[i].name, b[i].name) << what;
    ASSERT_EQ(x.positions.size(), y.positions.size()) << what << " mesh " << a[i].name;
    EXPECT_EQ(x.face_sizes, y.face_sizes) << what << " mesh " << a[i].name;
    EXPECT_EQ(x.face_vertices, y.face_vertices) << what << " mesh " << a[i].name;
    double worst = 0;
    for (size_t k = 0; k < x.positions.size(); ++k) {
      worst = std::max({worst, std::fabs(x.positions[k].x - y.positions[k].x), std::fabs(x.positions[k].y - y.positions[k].y),
                        std::fabs(x.positions[k].z - y.positions[k].z)});
    }
    EXPECT_LE(worst, tol) << what << " mesh " << a[i].name;
  }
}

// `saved` is `original` with one value changed, past its header line: one number token
// replaced, or (a slider made by a procedure of another file) one line `set VAR NUMBER`
// inserted.
void expect_one_value_changed(std::string_view original, std::string_view saved) {
  saved.remove_prefix(saved.find('\n') + 1);
  auto lines = [](std::string_view t) {
    std::vector<std::string_view> out;
    for (size_t at = 0; at <= t.size();) {
      const size_t eol = std::min(t.find('\n', at), t.size());
      out.push_back(t.substr(at, eol - at));
      at = eol + 1;
    }
    return out;
  };
  const std::vector<std::string_view> a = lines(original), b = lines(saved);
  auto is_number = [](std::string_view t) {
    std::string s(t);
    char* end = nullptr;
    std::strtod(s.c_str(), &end);
    return !s.empty() && *end == '\0';
  };
  if (b.size() == a.size() + 1) {
    size_t i = 0;
    while (i < a.size() && a[i] == b[i]) ++i;
    std::string_view added = b[i];
    while (!added.empty() && (added[0] == ' ' || added[0] == '\t')) added.remove_prefix(1);
    const size_t last_space = added.rfind(' ');
    EXPECT_TRUE(added.starts_with("set ") && last_space > 4 && is_number(added.substr(last_space + 1)) &&
                added.substr(4, last_space - 4).find(' ') == std::string_view::npos)
        << "inserted line `" << b[i] << "`";
    EXPECT_TRUE(std::equal(a.begin() + static_cast<std::ptrdiff_t>(i), a.end(), b.begin() + static_cast<std::ptrdiff_t>(i) + 1))
        << "more than one line inserted";
    return;
  }
  ASSERT_EQ(a.size(), b.size()) << "lines added or removed";
  int changed = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i] == b[i]) continue;
    ++changed;
    size_t head = 0;
    while (head < a[i].size() && head < b[i].size() && a[i][head] == b[i][head]) ++head;
    size_t tail = 0;
    while (tail < a[i].size() - head && tail < b[i].size() - head && a[i][a[i].size() - 1 - tail] == b[i][b[i].size() - 1 - tail]) ++tail;
    // Widened to whole tokens (`0.9` -> `1`: the `0.` or `.` may be shared).
    auto token_char = [](char c) { return std::isdigit(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == 'e' || c == '+'; };
    while (head > 0 && token_char(a[i][head - 1])) --head;
    while (tail > 0 && token_char(a[i][a[i].size() - tail])) --tail;
    EXPECT_TRUE(is_number(a[i].substr(head, a[i].size() - head - tail))) << "line was `" << a[i] << "`";
    EXPECT_TRUE(is_number(b[i].substr(head, b[i].size() - head - tail))) << "line is `" << b[i] << "`";
  }
  EXPECT_EQ(changed, 1);
}

class CorpusSave : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / fmt::format("nomec_corpus_save_{}", ::getpid());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_P(CorpusSave, EverySliderMovedOneStepIsSavedInPlace) {
  const std::string path = GetParam();
  std::optional<std::string> original = read_file_bytes(path);
  ASSERT_TRUE(original.has_value()) << path;
  auto plain = check_and_build(path, *original, {});
  if (plain->diags.error_count() > 0) {
    // Files known not to check (a user's mistake, an older syntax, a file made to be
    // included) have nothing to save; any other file must check.
    static const char* const kBroken[] = {"/nome1/funnelCube/savetemp.anom", "/nome3/olympictorus.nom", "/slide/viewing.slf"};
    EXPECT_TRUE(std::any_of(std::begin(kBroken), std::end(kBroken), [&](const char* b) { return path.ends_with(b); }))
        << path << " does not check: " << first_error(plain->diags);
    return;
  }
  const fs::path p(path);
  const bool as_nome = is_saved_work_path(path) || flat::format_of_path(path).has_value();
  const std::string ext = as_nome ? ".nome" : p.extension().string();
  // The saved copy is checked as if beside the original: its sources and includes are there.
  const std::string beside = (p.parent_path() / (p.stem().string() + ".saved" + ext)).string();
  const std::string copy = (dir_ / (p.stem().string() + ".saved" + ext)).string();
  const ir::Module& m = plain->check.module;
  int moved = 0;
  for (ir::NodeId id : m.params()) {
    const std::string name = m.node(id).name;
    const ir::ParamData& d = m.param(id);
    if (!(d.step > 0) || d.max <= d.min) continue;  // a slider that cannot move
    const double value = d.value + d.step <= d.max + d.step * 1e-9 ? d.value + d.step : d.value - d.step;
    const std::string what = fmt::format("{}: {} {} -> {}", path, name, d.value, value);
    SCOPED_TRACE(what);
    auto with_d = check_and_build(path, *original, {{name, value}});
    ASSERT_EQ(with_d->diags.error_count(), 0) << first_error(with_d->diags);
    const backend::SavedScene saved =
        backend::save_scene(with_d->check.module, plain->check.module, with_d->sources, path, with_d->check.base_file);
    for (const backend::UnsavedSlider& u : saved.unsaved) {
      EXPECT_NE(u.param, id) << "the moved slider cannot be saved: " << u.reason;
    }
    ASSERT_EQ(write_file_atomically(copy, saved.text), "");
    std::optional<std::string> back = read_file_bytes(copy);
    ASSERT_TRUE(back.has_value());
    auto reread = check_and_build(beside, *back, {});
    ASSERT_EQ(reread->diags.error_count(), 0) << first_error(reread->diags);
    const ir::NodeId again = reread->check.module.find_param(d.bank, name.substr(d.bank.size() + 1));
    ASSERT_TRUE(again.is_valid());
    EXPECT_NEAR(reread->check.module.param(again).value, value, d.step * 1e-6);
    EXPECT_EQ(reread->geometry.error_count(), with_d->geometry.error_count()) << first_error(reread->geometry);
    expect_same_meshes(with_d->meshes, reread->meshes, what);
    EXPECT_TRUE(backend::lost_values(with_d->check.module, saved, reread->check.module).empty());
    ++moved;
    if (!as_nome) expect_one_value_changed(*original, saved.text);  // (saved work + base scene: a new text)
  }
  RecordProperty("sliders_moved", moved);
}

std::string test_name(const ::testing::TestParamInfo<std::string>& info) {
  std::string rel = info.param.substr(std::string(NOMEC_CORPUS_DIR).size() + 1);
  for (char& c : rel) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return rel;
}

INSTANTIATE_TEST_SUITE_P(Corpus, CorpusSave, ::testing::ValuesIn(testing_inputs::corpus_scenes()), test_name);

// The sweep above must have met sliders of every dialect: a corpus that lost its sliders
// (or a save that skipped them) would pass over nothing.
TEST(CorpusSaveCoverage, EveryDialectHasSliders) {
  int per_folder[3] = {0, 0, 0};
  const char* folders[3] = {"/nome1/", "/nome3/", "/slide/"};
  for (const std::string& path : testing_inputs::corpus_scenes()) {
    std::optional<std::string> text = read_file_bytes(path);
    ASSERT_TRUE(text.has_value());
    auto c = check_and_build(path, *text, {});
    if (c->diags.error_count() > 0) continue;
    for (int f = 0; f < 3; ++f) {
      if (path.find(folders[f]) != std::string::npos) per_folder[f] += static_cast<int>(c->check.module.params().size());
    }
  }
  // Today: 198, 71 and 140.
  EXPECT_GE(per_folder[0], 150);
  EXPECT_GE(per_folder[1], 60);
  EXPECT_GE(per_folder[2], 130);
}

}  // namespace
}  // namespace nomec
