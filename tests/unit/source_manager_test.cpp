// Source manager and diagnostics engine: line/column mapping (including UTF-8 text and
// files without a final newline), sorting and de-duplication, "did you mean".
#include <gtest/gtest.h>

#include "frontend/diagnostics/diagnostic.h"
#include "frontend/source/file_kinds.h"
#include "frontend/source/source_manager.h"

namespace nomec {
namespace {

TEST(SourceManager, LineAndColumn) {
  SourceManager sm;
  FileId f = sm.add_file("a.nome", "point p\n  (1 2 3)\nendpoint");
  EXPECT_EQ(sm.line_col(f, 0).line, 1u);
  EXPECT_EQ(sm.line_col(f, 8).line, 2u);
  EXPECT_EQ(sm.line_col(f, 10).column, 3u);
  EXPECT_EQ(sm.line_text(f, 3), "endpoint");
  EXPECT_EQ(sm.line_col(f, 100).line, 3u);  // clamped to the end
  EXPECT_EQ(sm.offset_of(f, 2, 2), 10u);
}

TEST(Diagnostics, SortsAndDedupes) {
  SourceManager sm;
  FileId f = sm.add_file("a.nome", "abc def\n");
  DiagnosticEngine d;
  d.emit(DiagKind::UnknownName, {f, 4, 7}, "unknown `def`");
  d.emit(DiagKind::UnknownName, {f, 0, 3}, "unknown `abc`");
  d.emit(DiagKind::UnknownName, {f, 4, 7}, "unknown `def`");
  d.sort_and_dedupe();
  ASSERT_EQ(d.diagnostics().size(), 2u);
  EXPECT_EQ(d.diagnostics()[0].range.begin, 0u);
  EXPECT_EQ(d.error_count(), 2);
  std::string text = render_text(sm, d.diagnostics()[1], false, false);
  EXPECT_EQ(text, "a.nome:1:5: error: unknown `def` [UnknownName]\n    1 | abc def\n      |     ^~~\n");
}

TEST(Diagnostics, WerrorPromotesWarnings) {
  SourceManager sm;
  FileId f = sm.add_file("a.nome", "x\n");
  DiagnosticEngine d;
  d.emit(DiagKind::CommaInList, {f, 0, 1}, "commas");
  EXPECT_NE(render_text(sm, d.diagnostics()[0], true, false).find(": error: "), std::string::npos);
  EXPECT_NE(render_text(sm, d.diagnostics()[0], false, false).find(": warning: "), std::string::npos);
}

// A source line quoted under a diagnostic cannot drive the terminal: escape sequences,
// other control characters, bytes that are not UTF-8, C1 controls and bidirectional
// overrides are shown as visible escapes, and the caret still stands under the range.
TEST(Diagnostics, ControlCharactersInTheLineAreEscaped) {
  SourceManager sm;
  FileId f = sm.add_file("a.nome", "point \x1b[2J\x1b[31mp\x07 (1 2 \xc2\x9b\xe2\x80\xae\xff zz) endpoint\n");
  const uint32_t zz = static_cast<uint32_t>(sm.text(f).find("zz"));
  DiagnosticEngine d;
  d.emit(DiagKind::ExpectedNumber, {f, zz, zz + 2}, "`zz` is not a number");
  const std::string text = render_text(sm, d.diagnostics()[0], false, false);
  EXPECT_EQ(text,
            "a.nome:1:31: error: `zz` is not a number [ExpectedNumber]\n"
            "    1 | point \\x1b[2J\\x1b[31mp\\x07 (1 2 \\u009b\\u202e\\xff zz) endpoint\n"
            "      |                                                  ^~\n");
  EXPECT_EQ(text.find('\x1b'), std::string::npos);
}

// Messages, notes, fix-it descriptions and file names that quote the scene's text are
// escaped too (a Tcl error message, an include path); the colours nomec adds are kept.
TEST(Diagnostics, ControlCharactersInMessagesAreEscaped) {
  SourceManager sm;
  FileId f = sm.add_file("dir/\x1b]0;title\x07.nome", "x\n");
  DiagnosticEngine d;
  d.emit(DiagKind::TclError, {f, 0, 1}, "Tcl error: \x1b[2Jgone\nfake.nome:1:1: error: forged")
      .note({f, 0, 1}, "note \x1b[31m")
      .fixit({f, 0, 1}, "y", "replace with `\x1b[0m`");
  const std::string text = render_text(sm, d.diagnostics()[0], false, true);
  EXPECT_EQ(text,
            "dir/\\x1b]0;title\\x07.nome:1:1: \x1b[1;31merror\x1b[0m: Tcl error: \\x1b[2Jgone\\nfake.nome:1:1: error: "
            "forged [TclError]\n"
            "    1 | x\n"
            "      | ^\n"
            "dir/\\x1b]0;title\\x07.nome:1:1: note: note \\x1b[31m\n"
            "    1 | x\n"
            "      | ^\n"
            "dir/\\x1b]0;title\\x07.nome:1:1: fix-it: replace with `\\x1b[0m`\n");
}

// Tabs become spaces to the next multiple of 8 columns and the caret line uses spaces, so
// it lines up whatever the terminal's tab width; a UTF-8 character is one column.
TEST(Diagnostics, TabsAndUtf8KeepTheCaretAligned) {
  SourceManager sm;
  FileId f = sm.add_file("a.nome", "\tpoint\tp (\xc3\xa9\xc3\xa9 zz) endpoint\n");
  const uint32_t zz = static_cast<uint32_t>(sm.text(f).find("zz"));
  DiagnosticEngine d;
  d.emit(DiagKind::ExpectedNumber, {f, zz, zz + 2}, "`zz` is not a number");
  EXPECT_EQ(render_text(sm, d.diagnostics()[0], false, false),
            "a.nome:1:16: error: `zz` is not a number [ExpectedNumber]\n"
            "    1 |         point   p (\xc3\xa9\xc3\xa9 zz) endpoint\n"
            "      |                       ^~\n");
}

// A range that starts at the end of a line (a missing token's, at the end of a file cut
// short) puts the caret just after the line's last character, without reading past it
// (found by the front-end fuzzer under AddressSanitizer).
TEST(Diagnostics, ARangeAtTheEndOfTheLineIsShownAfterIt) {
  SourceManager sm;
  FileId f = sm.add_file("a.nome", "list (radius nu");
  DiagnosticEngine d;
  d.emit(DiagKind::MissingEndKeyword, {f, 15, 15}, "`list` is never closed");
  EXPECT_EQ(render_text(sm, d.diagnostics()[0], false, false),
            "a.nome:1:16: error: `list` is never closed [MissingEndKeyword]\n"
            "    1 | list (radius nu\n"
            "      |                ^\n");
}

// A leading UTF-8 byte order mark is not part of the first line: columns count from after
// it (as editors show them) and the quoted line leaves it out. Other lines are unchanged.
TEST(SourceManager, ByteOrderMarkIsNotAColumn) {
  SourceManager sm;
  FileId f = sm.add_file("a.nome", "\xEF\xBB\xBFpoint p\n  (1 2 3)\n");
  EXPECT_EQ(utf8_bom_length(sm.text(f)), 3u);
  EXPECT_EQ(sm.line_col(f, 3).column, 1u);  // `point`
  EXPECT_EQ(sm.line_col(f, 9).column, 7u);  // `p`
  EXPECT_EQ(sm.line_col(f, 0).column, 1u);  // inside the mark: its start
  EXPECT_EQ(sm.line_col(f, 13).column, 3u);  // line 2 counts as always
  EXPECT_EQ(sm.line_text(f, 1), "point p");
  EXPECT_EQ(sm.offset_of(f, 1, 6), 9u);
  DiagnosticEngine d;
  d.emit(DiagKind::UnknownName, {f, 9, 10}, "unknown `p`");
  EXPECT_EQ(render_text(sm, d.diagnostics()[0], false, false),
            "a.nome:1:7: error: unknown `p` [UnknownName]\n    1 | point p\n      |       ^\n");
  EXPECT_EQ(utf8_bom_length("\xEF\xBB"), 0u);
  EXPECT_EQ(utf8_bom_length("x\xEF\xBB\xBF"), 0u);
}

TEST(Diagnostics, ClosestMatch) {
  EXPECT_EQ(closest_match("radus", {"radius", "ratio", "n"}), "radius");
  EXPECT_EQ(closest_match("pint", {"point", "face"}), "point");
  EXPECT_EQ(closest_match("zzzzzz", {"point", "face"}), "");
}

// Corpus folders hold SLIDE's Tcl helpers and `.sif` meshes beside the scenes: sweeps over
// real files choose scenes by these rules.
TEST(FileKinds, ScenesAreChosenByExtension) {
  for (const char* scene : {"a.nome", "dir/b.nom", "c.slf", "zero/zerosave.anom", "x.amom", "../shared/a.b/c.nom"}) {
    EXPECT_TRUE(is_scene_path(scene)) << scene;
  }
  for (const char* other : {"slide/SLIDEUI.tcl", "zero/Zero_6.sif", "README.md", "nome", "dir.nom/file", ".nom"}) {
    EXPECT_FALSE(is_scene_path(other)) << other;
  }
  EXPECT_TRUE(is_saved_work_path("zero/zerosave.anom"));
  EXPECT_FALSE(is_saved_work_path("zero/zero.nom"));
  EXPECT_TRUE(is_base_scene_path("zero/zero.nom"));
  EXPECT_EQ(path_extension("a/b.c/d"), "");
  EXPECT_EQ(path_extension("a/b.tar.slf"), ".slf");
}

}  // namespace
}  // namespace nomec

namespace nomec {
namespace {

// Views into a file's text stay valid when more files are added (an `.anom` adds its base
// scene while the syntax tree of the first file is in use), also for texts short enough to
// live inside the std::string object itself.
TEST(SourceManagerStability, TextViewsSurviveAddingFiles) {
  SourceManager sm;
  FileId first = sm.add_file("a.anom", "sp");
  std::string_view view = sm.text(first);
  const char* data = view.data();
  for (int i = 0; i < 100; ++i) sm.add_file("b" + std::to_string(i) + ".nome", "point p (0 0 0) endpoint\n");
  EXPECT_EQ(sm.text(first).data(), data);
  EXPECT_EQ(view, "sp");
}

}  // namespace
}  // namespace nomec
