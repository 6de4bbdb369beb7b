// Saving slider values (backend/save.h, issue 45): each dialect's value token rewritten in
// place and nothing else — SLIDE's `CreateScale` default argument and the number a `set`
// gives a `scale -variable` (the save once replaced `[CreateScale …` itself: 17 errors on
// BellShape.slf), a NOME 2016 file's one `savedparameter` block updated instead of a new
// block per save, a bank's `set` value; values written with the fewest digits that read back
// at the slider's step; a saved file saved again keeps one header; sliders of an included
// file are reported, its text not copied in.
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <map>
#include <string>

#include "backend/save.h"
#include "frontend/check/check.h"

namespace nomec::backend {
namespace {

struct Checked {
  SourceManager sources;
  DiagnosticEngine diags;
  CheckResult check;
};

// `text` checked as `path` with `-D` overrides; `files` are the other files it may read.
std::unique_ptr<Checked> check(const std::string& path, const std::string& text,
                               std::vector<std::pair<std::string, double>> overrides = {},
                               std::map<std::string, std::string> files = {}) {
  auto c = std::make_unique<Checked>();
  CheckOptions o;
  o.overrides = std::move(overrides);
  o.read_file = [files](const std::string& p) -> std::optional<std::string> {
    for (const auto& [name, body] : files) {
      if (p.size() >= name.size() && p.compare(p.size() - name.size(), name.size(), name) == 0) return body;
    }
    return std::nullopt;
  };
  c->check = check_source(c->sources, path, text, o, c->diags);
  for (const Diagnostic& d : c->diags.diagnostics()) {
    EXPECT_NE(d.severity, Severity::Error) << path << ": " << d.message;
  }
  return c;
}

// The scene of `c` saved; `as_written` is the same file checked without `-D` (default:
// the file as checked, nothing moved).
SavedScene save(const Checked& c, const std::string& path, const Checked* as_written = nullptr) {
  return save_scene(c.check.module, (as_written ? as_written : &c)->check.module, c.sources, path, c.check.base_file);
}

double value_of(const Checked& c, std::string_view bank, std::string_view name) {
  const ir::NodeId id = c.check.module.find_param(bank, name);
  EXPECT_TRUE(id.is_valid()) << bank << "." << name;
  return id.is_valid() ? c.check.module.param(id).value : -12345;
}

// The saved text without its first (header) line.
std::string body(const std::string& saved) { return saved.substr(saved.find('\n') + 1); }

size_t count(const std::string& s, const std::string& what) {
  size_t n = 0;
  for (size_t at = s.find(what); at != std::string::npos; at = s.find(what, at + 1)) ++n;
  return n;
}

constexpr const char* kSlide = R"(tclinit {
  source SLIDEUI.tcl
  proc CreateParamUI { parent name } {
    set root $parent.$name
    frame $root
    set q0x [CreateScale $name $root q0x "q0x"   0.9   0   2  0.1  1 horizontal]
    set n [CreateScaleCmd $name $root n "count" 4 3 20 1 1 horizontal Redraw]
    pack $q0x $n
  }
  CreateParamUI {} par
}
tclinit {
  global x0
  set x0 1.0
  scale .x0 -from 0.0 -to 1.5 -resolution 0.01 -variable x0
}
tclinit {
  proc CreateParamObject { name } {
    global $name
    set [subst $name](v0) 1.60
    set [subst $name](v0_min) 0.8
  }
  CreateParamObject prm
  scale .v0 -from 0.8 -to 2.0 -resolution 0.02 -variable prm(v0)
}
point p ({expr $par_q0x} {expr $x0} {expr $prm(v0) * $par_n}) endpoint
)";

TEST(SaveSlide, EachSlidersValueIsRewrittenWhereTheFileWritesIt) {
  auto c = check("scene.slf", kSlide, {{"par.q0x", 1.1}, {"par.n", 7}, {"x0.x0", 0.25}, {"prm.v0", 1.62}});
  auto plain = check("scene.slf", kSlide);
  const SavedScene s = save(*c, "scene.slf", plain.get());
  EXPECT_TRUE(s.unsaved.empty());
  std::string expected = kSlide;
  auto replace = [&](const std::string& from, const std::string& to) {
    const size_t at = expected.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    expected.replace(at, from.size(), to);
  };
  replace("\"q0x\"   0.9   0", "\"q0x\"   1.1   0");
  replace("\"count\" 4 3", "\"count\" 7 3");
  replace("set x0 1.0", "set x0 0.25");
  replace("(v0) 1.60", "(v0) 1.62");
  EXPECT_EQ(body(s.text), expected);
  // Read back: the values are the ones saved.
  auto back = check("scene.saved.slf", s.text);
  EXPECT_DOUBLE_EQ(value_of(*back, "par", "q0x"), 1.1);
  EXPECT_DOUBLE_EQ(value_of(*back, "par", "n"), 7);
  EXPECT_DOUBLE_EQ(value_of(*back, "x0", "x0"), 0.25);
  EXPECT_DOUBLE_EQ(value_of(*back, "prm", "v0"), 1.62);
}

TEST(SaveSlide, UnmovedSlidersKeepTheirSpelling) {
  auto c = check("scene.slf", kSlide);
  const SavedScene s = save(*c, "scene.slf");
  EXPECT_EQ(body(s.text), kSlide);  // `0.9`, `1.0` and `1.60` as written
}

constexpr const char* kNome2016 = R"(bank fp
    set n 8 3 10 1
    set ro 0.4 0.1 1.0 0.1   # the radius
endbank
funnel fun ({expr $fp_n} {expr $fp_ro} 0 0.2) endfunnel
instance f1 fun endinstance
savedparameter
    fp_n 6.000000
endsavedparameter
)";

TEST(SaveNome2016, TheOneSavedParameterBlockIsUpdatedAtEverySave) {
  std::string text = kNome2016;
  for (int save_count = 0; save_count < 3; ++save_count) {
    const double n = 4 + save_count, ro = 0.5 + 0.1 * save_count;  // 0.6 + 0.1 is 0.7000000000000001
    auto c = check("scene.nom", text, {{"fp.n", n}, {"fp.ro", ro}});
    auto plain = check("scene.nom", text);
    const SavedScene s = save(*c, "scene.nom", plain.get());
    EXPECT_TRUE(s.unsaved.empty());
    EXPECT_EQ(count(s.text, "\nsavedparameter\n"), 1u) << s.text;
    EXPECT_EQ(count(s.text, "endsavedparameter"), 1u) << s.text;
    EXPECT_EQ(count(s.text, "# Saved by nomec"), 1u) << s.text;
    // `fp.n` is set by the block: its entry changes, the bank keeps 8; `fp.ro` is set by
    // the bank only: its `set` line changes, and no entry is added.
    EXPECT_NE(s.text.find(fmt::format("    fp_n {}\n", n)), std::string::npos) << s.text;
    EXPECT_NE(s.text.find("    set n 8 3 10 1\n"), std::string::npos) << s.text;
    EXPECT_NE(s.text.find(fmt::format("    set ro {} 0.1 1.0 0.1   # the radius\n", slider_value_text(ro, 0.1))),
              std::string::npos)
        << s.text;
    EXPECT_EQ(s.text.find("    fp_ro "), std::string::npos) << s.text;
    auto back = check("scene.nom", s.text);
    EXPECT_DOUBLE_EQ(value_of(*back, "fp", "n"), n);
    EXPECT_NEAR(value_of(*back, "fp", "ro"), ro, 1e-12);
    text = s.text;
  }
}

TEST(SaveValues, TheFewestDigitsThatReadBackAtTheSlidersStep) {
  EXPECT_EQ(slider_value_text(0.1 + 0.2, 0.1), "0.3");  // 0.30000000000000004
  EXPECT_EQ(slider_value_text(1.15 + 0.01, 0.01), "1.16");
  EXPECT_EQ(slider_value_text(0.6 + 0.1, 0.1), "0.7");
  EXPECT_EQ(slider_value_text(5, 1), "5");
  EXPECT_EQ(slider_value_text(-2.4000000000000004, 0.1), "-2.4");
  EXPECT_EQ(slider_value_text(-0.0, 0.1), "0");
  EXPECT_EQ(slider_value_text(-1e-17, 0.1), "0");
  EXPECT_EQ(slider_value_text(0.123, 0.1), "0.123");  // off the step grid (a -D value): kept
  EXPECT_EQ(slider_value_text(180, 180), "180");
  EXPECT_EQ(slider_value_text(0.30000000000000004, 0), "0.30000000000000004");  // no step: exact
  EXPECT_EQ(slider_value_text(1e-20, 0), "1e-20");
  // Through a save: `-D fp.ro=0.30000000000000004` is written `0.3`.
  auto c = check("scene.nom", kNome2016, {{"fp.ro", 0.1 + 0.2}});
  auto plain = check("scene.nom", kNome2016);
  const SavedScene s = save(*c, "scene.nom", plain.get());
  EXPECT_NE(s.text.find("    set ro 0.3 0.1 1.0 0.1"), std::string::npos) << s.text;
}

TEST(SaveNome3, ABanksValueIsRewrittenCommentsAndLayoutKept) {
  const std::string text = R"(# a torus knot
bank knot
    set p 2 1 9 1     (* winding *)
    set q 3 1 9 1
    list (p q)
endbank
torusknot k ($knot.p $knot.q 1 0.3 0.1 64 8) endtorusknot
instance i k endinstance
)";
  auto c = check("knot.nom", text, {{"knot.q", 5}});
  auto plain = check("knot.nom", text);
  const SavedScene s = save(*c, "knot.nom", plain.get());
  std::string expected = text;
  expected.replace(expected.find("set q 3"), 7, "set q 5");
  EXPECT_EQ(body(s.text), expected);
  EXPECT_EQ(s.text.find("savedparameter"), std::string::npos);
  // Saved again: one header line, replaced.
  auto again = check("knot.saved.nom", s.text, {{"knot.q", 6}});
  auto again_plain = check("knot.saved.nom", s.text);
  const SavedScene s2 = save(*again, "knot.saved.nom", again_plain.get());
  EXPECT_EQ(count(s2.text, "# Saved by nomec"), 1u) << s2.text;
  EXPECT_NE(s2.text.find("set q 6 1 9 1"), std::string::npos);
}

TEST(SaveIncludes, AnIncludedFilesSlidersAreReportedAndItsTextNotCopied) {
  const std::string main_text = "include \"sliders.nom\"\nfunnel fun ({expr $fp_n} 0.4 0 0.2) endfunnel\ninstance f fun endinstance\n";
  const std::map<std::string, std::string> files = {{"sliders.nom", "bank fp\n    set n 8 3 10 1\nendbank\n"}};
  auto c = check("scene.nom", main_text, {}, files);
  const ir::NodeId n = c->check.module.find_param("fp", "n");
  ASSERT_TRUE(n.is_valid());
  c->check.module.param(n).value = 5;  // moved (`-D` does not reach an included bank)
  auto plain = check("scene.nom", main_text, {}, files);
  const SavedScene s = save(*c, "scene.nom", plain.get());
  EXPECT_EQ(body(s.text), main_text);
  ASSERT_EQ(s.unsaved.size(), 1u);
  EXPECT_EQ(c->check.module.node(s.unsaved[0].param).name, "fp.n");
  EXPECT_NE(s.unsaved[0].reason.find("included file"), std::string::npos) << s.unsaved[0].reason;
}

TEST(SaveSlide, ASliderMadeByAnotherFilesProcedureGetsOneSetLine) {
  // `CreateSLIDESubdivisionUI` (slideui, one of SLIDE's lost packages: nomec's stand-in
  // makes the slider, with the default of `CreateSLIDESubdivisionObject`) writes no value
  // into the scene file: the save sets it just before the command that makes the slider.
  const std::string text = R"(tclinit {
  package require slideui
  CreateSLIDESubdivisionObject oSub
    set widget [CreateSLIDESubdivisionUI .ui oSub]
}
point p ({expr $oSub(subdivisions)} 0 0) endpoint
)";
  auto plain = check("sub.slf", text);
  auto c = check("sub.slf", text, {{"oSub.subdivisions", 3}});
  const SavedScene s = save(*c, "sub.slf", plain.get());
  EXPECT_TRUE(s.unsaved.empty());
  std::string expected = text;
  expected.insert(expected.find("set widget"), "set oSub(subdivisions) 3\n    ");
  EXPECT_EQ(body(s.text), expected);
  auto back = check("sub.saved.slf", s.text, {{"oSub.subdivisions", 4}});
  EXPECT_DOUBLE_EQ(value_of(*check("sub.saved.slf", s.text), "oSub", "subdivisions"), 3);
  // The next save rewrites that line: no second one.
  auto back_plain = check("sub.saved.slf", s.text);
  const SavedScene s2 = save(*back, "sub.saved.slf", back_plain.get());
  EXPECT_EQ(count(s2.text, "set oSub(subdivisions)"), 1u) << s2.text;
  EXPECT_NE(s2.text.find("set oSub(subdivisions) 4\n"), std::string::npos) << s2.text;
}

TEST(SaveSlide, ASliderTheFileNeitherWritesNorReadsIsReported) {
  const std::string text = "tclinit {\n  package require slideui\n  CreateSLIDEOffsetObject oOff\n"
                           "  CreateSLIDEOffsetUI .ui oOff\n}\npoint p (0 0 0) endpoint\n";
  auto plain = check("off.slf", text);
  auto c = check("off.slf", text, {{"oOff.height", 0.5}});
  const SavedScene s = save(*c, "off.slf", plain.get());
  EXPECT_EQ(body(s.text), text);
  ASSERT_EQ(s.unsaved.size(), 1u);
  EXPECT_EQ(c->check.module.node(s.unsaved[0].param).name, "oOff.height");
  EXPECT_NE(s.unsaved[0].reason.find("not written in `off.slf`"), std::string::npos) << s.unsaved[0].reason;
}

TEST(SaveSlide, SlidersNotMovedAreLeftAsWrittenWhateverTheirText) {
  // `0` is below the slider's range: nomec reads it as 0.1 (the minimum). Saving after
  // another slider moved leaves that `0` as the user wrote it.
  const std::string text = R"(tclinit {
  source SLIDEUI.tcl
  proc UI { parent name } {
    set root $parent.$name
    set a [CreateScale $name $root rkink "kink" 0 0.1 1.0 0.1 1 horizontal]
    set b [CreateScale $name $root thick "thick" 0.2 0.1 1.0 0.1 1 horizontal]
  }
  UI {} par
}
point p ({expr $par_rkink} {expr $par_thick} 0) endpoint
)";
  auto plain = check("k.slf", text);
  EXPECT_DOUBLE_EQ(value_of(*plain, "par", "rkink"), 0.1);
  auto c = check("k.slf", text, {{"par.thick", 0.3}});
  const SavedScene s = save(*c, "k.slf", plain.get());
  std::string expected = text;
  expected.replace(expected.find("\"thick\" 0.2"), 11, "\"thick\" 0.3");
  EXPECT_EQ(body(s.text), expected);
}

TEST(SaveValues, LostValuesNameEverySliderTheSavedTextDoesNotCarry) {
  auto plain = check("scene.nom", kNome2016);
  auto moved = check("scene.nom", kNome2016, {{"fp.ro", 0.7}});
  const SavedScene faithful = save(*moved, "scene.nom", plain.get());
  EXPECT_TRUE(lost_values(moved->check.module, faithful, check("s.nom", faithful.text)->check.module).empty());
  // The original text does not carry the move.
  const std::vector<std::string> lost = lost_values(moved->check.module, faithful, plain->check.module);
  ASSERT_EQ(lost.size(), 1u);
  EXPECT_EQ(lost[0], "slider `fp.ro` = 0.7 cannot be saved: the saved file gives it 0.4");
}

}  // namespace
}  // namespace nomec::backend
