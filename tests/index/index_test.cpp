// Tests of the language index on small inline scenes: definitions and uses (including
// `$bank.param`, `$bank_param` and 2016 `_`-joined vertex names), references, outline,
// completion on incomplete text, signature help, semantic tokens, folding, rename and hover.
#include "frontend/index/index.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace nomec::index {
namespace {

struct Doc {
  Analysis a;
  std::string text;
  DiagnosticEngine diags;
  const Index& ix() const { return *a.index; }
  // Offset of the `nth` occurrence of `needle`, plus `delta`.
  uint32_t at(std::string_view needle, int nth = 0, int delta = 0) const {
    size_t p = text.find(needle);
    for (int i = 0; i < nth && p != std::string::npos; ++i) p = text.find(needle, p + 1);
    EXPECT_NE(p, std::string::npos) << needle;
    return static_cast<uint32_t>(p + delta);
  }
  std::string_view str(SourceRange r) const { return a.sources->text(r); }
  SymbolId sym(std::string_view needle, int nth = 0, int delta = 0) const {
    auto o = ix().occurrence_at(a.file, at(needle, nth, delta));
    return o ? o->symbol : -1;
  }
};

std::unique_ptr<Doc> open(std::string text, std::string path = "t.nome", CheckOptions opts = {}) {
  auto d = std::make_unique<Doc>();
  d->text = text;
  d->a = analyze(path, std::move(text), opts, d->diags);
  return d;
}

const char* kFunnels = R"(bank fp
  set n 4 3 10 1
  set ro 1 0.1 2 0.1
endbank
funnel fun ({expr $fp_n} {expr $fp_ro} 0.5 1) endfunnel
group cf
  instance fun1 fun translate (0 0 1) endinstance
  instance fun2 fun endinstance
endgroup
instance cube cf endinstance
mesh m
  point p1 (0 0 0) endpoint
  point p2 (1 0 0) endpoint
  point p3 (0 1 0) endpoint
  face f1 (p1 p2 p3) endface
endmesh
instance mi m endinstance
face bridge (cube_fun1_hc0 cube_fun2_hc1 mi_p1) endface
)";

// A check's `parsed` callback belongs to that check: what the index keeps of its options
// for later checks (renames, includes) does not hold it, nor what it captured.
TEST(Index, KeepsNoParsedCallback) {
  auto held = std::make_shared<int>(0);
  CheckOptions options;
  options.parsed = [held] { ++*held; };
  DiagnosticEngine diags;
  Checked checked = check_document("t.nome", "point p (0 0 0) endpoint\n", std::move(options), diags, nullptr);
  EXPECT_EQ(*held, 1);
  EXPECT_FALSE(static_cast<bool>(checked.options.parsed));
  EXPECT_EQ(held.use_count(), 1);
}

TEST(Index, DefinitionsAndUses) {
  auto d = open(kFunnels);
  EXPECT_EQ(d->diags.error_count(), 0);
  SymbolId fun = d->sym("fun (");
  ASSERT_GE(fun, 0);
  EXPECT_EQ(d->ix().symbols()[fun].name, "fun");
  EXPECT_EQ(d->ix().symbols()[fun].kind, SymbolKind::Generator);
  EXPECT_EQ(d->ix().symbols()[fun].detail, "funnel (n ro ratio h)");
  EXPECT_EQ(d->ix().symbols()[d->sym("fun1 fun")].detail, "instance of funnel `fun`");
  EXPECT_EQ(d->ix().symbols()[d->sym("n 4 3")].detail, "fp.n = 4 in [3, 10] step 1");
  // `instance fun1 fun`: the target is a use of the generator.
  EXPECT_EQ(d->sym("fun translate"), fun);
  auto refs = d->ix().references(fun, true);
  ASSERT_EQ(refs.size(), 3u);
  EXPECT_TRUE(refs[0].is_definition);
  EXPECT_EQ(d->ix().references(fun, false).size(), 2u);
  // Slider uses: `$fp_n` splits into the bank `fp` and the slider `n`.
  SymbolId n = d->sym("n 4 3");
  ASSERT_GE(n, 0);
  EXPECT_EQ(d->ix().symbols()[n].kind, SymbolKind::Parameter);
  EXPECT_EQ(d->sym("$fp_n", 0, 4), n);
  SymbolId fp = d->sym("fp\n");
  EXPECT_EQ(d->ix().symbols()[fp].kind, SymbolKind::Bank);
  EXPECT_EQ(d->sym("$fp_n", 0, 1), fp);
  EXPECT_EQ(d->sym("$fp_n", 0, 0), fp);  // on the `$`
  auto nref = d->ix().references(n, false);
  ASSERT_EQ(nref.size(), 1u);
  EXPECT_EQ(d->str(nref[0].range), "n");
  // 2016 `_`-joined vertex names: `cube_fun1_hc0` uses the instances `cube` and `fun1`.
  SymbolId cube = d->sym("cube cf");
  SymbolId fun1 = d->sym("fun1 fun");
  EXPECT_EQ(d->sym("cube_fun1_hc0", 0, 1), cube);
  EXPECT_EQ(d->sym("cube_fun1_hc0", 0, 6), fun1);
  EXPECT_EQ(d->sym("cube_fun1_hc0", 0, 11), -1);  // `hc0` is a generated vertex
  // `mi_p1`: the instance and the mesh's point.
  EXPECT_EQ(d->sym("mi_p1", 0, 0), d->sym("mi m"));
  EXPECT_EQ(d->sym("mi_p1", 0, 3), d->sym("p1 (0"));
  // Points of a mesh used by its face.
  EXPECT_EQ(d->sym("p2 p3)"), d->sym("p2 (1"));
  // The group target.
  EXPECT_EQ(d->sym("cf endinstance"), d->sym("cf\n"));
}

TEST(Index, DottedParamsAndPaths) {
  auto d = open(R"(bank b
  set w 2 1 3 1
endbank
funnel f ({expr $b.w} 1 1 4) endfunnel
instance a f endinstance
face x (a.hc0 a.hc1 a.hc2) endface
)", "t.nom");
  EXPECT_EQ(d->diags.error_count(), 0);
  SymbolId w = d->sym("w 2");
  EXPECT_EQ(d->sym("$b.w", 0, 3), w);
  EXPECT_EQ(d->sym("$b.w", 0, 1), d->sym("b\n"));
  SymbolId a = d->sym("a f");
  EXPECT_EQ(d->sym("a.hc1"), a);
  EXPECT_EQ(d->ix().references(a, true).size(), 4u);
}

TEST(Index, Outline) {
  auto d = open(kFunnels);
  auto top = d->ix().outline(d->a.file);
  std::vector<std::string> names;
  for (SymbolId s : top) names.push_back(d->ix().symbols()[s].name);
  EXPECT_EQ(names, (std::vector<std::string>{"fp", "fun", "cf", "cube", "m", "mi", "bridge"}));
  // Children through Symbol::parent.
  std::vector<std::string> in_cf;
  for (const Symbol& s : d->ix().symbols()) {
    if (s.parent == top[2]) in_cf.push_back(s.name);
  }
  EXPECT_EQ(in_cf, (std::vector<std::string>{"fun1", "fun2"}));
  EXPECT_EQ(d->ix().symbols()[top[1]].node.is_valid(), true);
}


std::vector<std::string> labels(const std::vector<CompletionItem>& items) {
  std::vector<std::string> out;
  for (const auto& i : items) out.push_back(i.label);
  return out;
}
bool has(const std::vector<std::string>& v, std::string_view s) { return std::find(v.begin(), v.end(), s) != v.end(); }

TEST(Index, CompletionOnIncompleteText) {
  // The last statement is still being typed: no `endinstance`, no target yet.
  std::string text = std::string(kFunnels) + "instance z ";
  auto d = open(text);
  auto at_end = static_cast<uint32_t>(text.size());
  auto targets = labels(d->ix().complete(d->a.file, at_end));
  EXPECT_TRUE(has(targets, "fun"));
  EXPECT_TRUE(has(targets, "cf"));
  EXPECT_TRUE(has(targets, "m"));
  EXPECT_FALSE(has(targets, "p1"));    // a point cannot be instanced
  EXPECT_FALSE(has(targets, "fun1"));  // nor an instance
  // With a prefix.
  auto d2 = open(std::string(kFunnels) + "instance z f");
  auto f = labels(d2->ix().complete(d2->a.file, static_cast<uint32_t>(d2->text.size())));
  EXPECT_EQ(f, (std::vector<std::string>{"fun"}));
  // Sliders after `$`, in the 2016 form for a NOME file.
  auto d3 = open(std::string(kFunnels) + "funnel g ({expr $fp");
  auto p = labels(d3->ix().complete(d3->a.file, static_cast<uint32_t>(d3->text.size())));
  EXPECT_EQ(p, (std::vector<std::string>{"$fp_n", "$fp_ro"}));
  // Options and the end keyword inside an instance.
  auto d4 = open(std::string(kFunnels) + "instance z fun tr");
  auto o = labels(d4->ix().complete(d4->a.file, static_cast<uint32_t>(d4->text.size())));
  EXPECT_EQ(o, (std::vector<std::string>{"translate", "transform"}));
  auto d5 = open(std::string(kFunnels) + "instance z fun ");
  auto o5 = d5->ix().complete(d5->a.file, static_cast<uint32_t>(d5->text.size()));
  EXPECT_TRUE(has(labels(o5), "endinstance"));
  EXPECT_TRUE(has(labels(o5), "rotate"));
  // Statement keywords at the top level.
  auto d6 = open(std::string(kFunnels) + "me");
  auto k = d6->ix().complete(d6->a.file, static_cast<uint32_t>(d6->text.size()));
  EXPECT_TRUE(has(labels(k), "mesh"));
  EXPECT_TRUE(has(labels(k), "merge"));
  EXPECT_TRUE(std::all_of(k.begin(), k.end(), [](const CompletionItem& i) { return i.is_keyword && !i.detail.empty(); }));
  // Vertex paths in a face: instances, then the instance's children after `.`.
  auto d7 = open(std::string(kFunnels) + "face q (cube.");
  auto v = labels(d7->ix().complete(d7->a.file, static_cast<uint32_t>(d7->text.size())));
  EXPECT_EQ(v, (std::vector<std::string>{"cube.fun1", "cube.fun2"}));
  auto d8 = open(std::string(kFunnels) + "face q (mi.");
  auto v8 = labels(d8->ix().complete(d8->a.file, static_cast<uint32_t>(d8->text.size())));
  EXPECT_EQ(v8, (std::vector<std::string>{"mi.p1", "mi.p2", "mi.p3"}));
  // Nothing inside a comment, nothing while naming a new definition.
  auto d9 = open(std::string(kFunnels) + "# instance z f");
  EXPECT_TRUE(d9->ix().complete(d9->a.file, static_cast<uint32_t>(d9->text.size())).empty());
  auto d10 = open(std::string(kFunnels) + "mesh ne");
  EXPECT_TRUE(d10->ix().complete(d10->a.file, static_cast<uint32_t>(d10->text.size())).empty());
}

TEST(Index, CompletionDottedSlidersInNome3) {
  auto d = open("bank b\n  set w 2 1 3 1\nendbank\ntorus t ($", "t.nom");
  auto p = labels(d->ix().complete(d->a.file, static_cast<uint32_t>(d->text.size())));
  EXPECT_TRUE(has(p, "$b.w"));
  EXPECT_TRUE(has(p, "$time"));
}

TEST(Index, SignatureHelp) {
  auto d = open(std::string(kFunnels) + "funnel g (4 1.5 ");
  auto h = d->ix().signature_help(d->a.file, static_cast<uint32_t>(d->text.size()));
  ASSERT_TRUE(h);
  EXPECT_EQ(h->label, "funnel NAME (n ro ratio h)");
  ASSERT_EQ(h->parameters.size(), 4u);
  EXPECT_EQ(h->label.substr(h->parameters[1].first, h->parameters[1].second - h->parameters[1].first), "ro");
  EXPECT_EQ(h->active_parameter, 2);
  EXPECT_NE(h->parameter_docs[0].find("count"), std::string::npos);
  // The sign rule: `1 -2` is two elements, `1 - 2` one.
  auto d2 = open(std::string(kFunnels) + "funnel g (4 1 -2");
  EXPECT_EQ(d2->ix().signature_help(d2->a.file, static_cast<uint32_t>(d2->text.size()))->active_parameter, 2);
  auto d3 = open(std::string(kFunnels) + "funnel g (4 1 - 2");
  EXPECT_EQ(d3->ix().signature_help(d3->a.file, static_cast<uint32_t>(d3->text.size()))->active_parameter, 1);
  // Nested braces count as one element.
  auto d4 = open(std::string(kFunnels) + "funnel g ({expr $fp_n * (2 + 1)} ");
  EXPECT_EQ(d4->ix().signature_help(d4->a.file, static_cast<uint32_t>(d4->text.size()))->active_parameter, 1);
  // Transform lists and the rotate angle.
  auto d5 = open(std::string(kFunnels) + "instance z fun rotate (0 0 1) (");
  auto h5 = d5->ix().signature_help(d5->a.file, static_cast<uint32_t>(d5->text.size()));
  ASSERT_TRUE(h5);
  EXPECT_EQ(h5->label, "rotate (ax ay az) (degrees)");
  auto d6 = open(std::string(kFunnels) + "instance z fun translate (1 ");
  auto h6 = d6->ix().signature_help(d6->a.file, static_cast<uint32_t>(d6->text.size()));
  ASSERT_TRUE(h6);
  EXPECT_EQ(h6->label, "translate (x y z)");
  EXPECT_EQ(h6->active_parameter, 1);
  // Outside any list: none.
  EXPECT_FALSE(d->ix().signature_help(d->a.file, d->at("group cf")));
}

TEST(Index, SemanticTokens) {
  auto d = open(std::string("(* a\n comment *)\n") + kFunnels);
  auto toks = d->ix().semantic_tokens(d->a.file);
  ASSERT_FALSE(toks.empty());
  for (size_t i = 1; i < toks.size(); ++i) EXPECT_LE(toks[i - 1].range.end, toks[i].range.begin);
  auto type_at = [&](uint32_t off) -> std::optional<SemanticToken> {
    for (const auto& t : toks) {
      if (t.range.begin <= off && off < t.range.end) return t;
    }
    return std::nullopt;
  };
  EXPECT_EQ(type_at(0)->type, TokenType::Comment);
  EXPECT_EQ(type_at(d->at("bank"))->type, TokenType::Keyword);
  EXPECT_EQ(type_at(d->at("endbank"))->type, TokenType::Keyword);
  EXPECT_EQ(type_at(d->at("translate"))->type, TokenType::Keyword);
  EXPECT_EQ(type_at(d->at("0.5"))->type, TokenType::Number);
  auto n = type_at(d->at("$fp_n", 0, 4));
  EXPECT_EQ(n->type, TokenType::Parameter);
  EXPECT_FALSE(n->is_definition);
  EXPECT_EQ(d->str(n->range), "n");
  auto def = type_at(d->at("fun ("));
  EXPECT_EQ(def->type, TokenType::Name);
  EXPECT_TRUE(def->is_definition);
  EXPECT_TRUE(type_at(d->at("n 4 3"))->is_definition);
}

TEST(Index, FunctionTokensAndHover) {
  auto d = open("point p ({expr sin(pi/2)} 0 0) endpoint\n");
  auto toks = d->ix().semantic_tokens(d->a.file);
  bool found = false;
  for (const auto& t : toks) {
    if (d->str(t.range) == "sin") {
      EXPECT_EQ(t.type, TokenType::Function);
      found = true;
    }
  }
  EXPECT_TRUE(found);
  auto h = d->ix().hover(d->a.file, d->at("sin"));
  ASSERT_TRUE(h);
  EXPECT_NE(h->markdown.find("sine"), std::string::npos);
}

TEST(Index, FoldingRanges) {
  auto d = open(std::string("(* one\n two *)\n# line\n") + kFunnels);
  auto f = d->ix().folding_ranges(d->a.file);
  std::vector<std::string> firsts;
  for (const auto& r : f) firsts.push_back(std::string(d->str(r.range).substr(0, 5)));
  // The block comment, the bank, the group, the mesh; one-line statements do not fold.
  EXPECT_EQ(firsts, (std::vector<std::string>{"(* on", "bank ", "group", "mesh "}));
  EXPECT_TRUE(f[0].is_comment);
  EXPECT_FALSE(f[1].is_comment);
}

TEST(Index, RenameSlider) {
  auto d = open(kFunnels);
  auto pr = d->ix().prepare_rename(d->a.file, d->at("$fp_n", 0, 4));
  ASSERT_TRUE(pr);
  EXPECT_EQ(d->str(*pr), "n");
  auto r = d->ix().rename(d->a.file, d->at("$fp_n", 0, 4), "sides");
  ASSERT_TRUE(std::holds_alternative<std::vector<TextEdit>>(r)) << std::get<std::string>(r);
  auto edits = std::get<std::vector<TextEdit>>(r);
  ASSERT_EQ(edits.size(), 2u);
  EXPECT_EQ(d->str(edits[0].range), "n");
  EXPECT_EQ(edits[0].range.begin, d->at("n 4 3"));
  EXPECT_EQ(edits[1].range.begin, d->at("$fp_n", 0, 4));
  // The bank: every `$fp_…` changes its bank part.
  auto rb = d->ix().rename(d->a.file, d->at("$fp_ro", 0, 1), "fq");
  ASSERT_TRUE(std::holds_alternative<std::vector<TextEdit>>(rb)) << std::get<std::string>(rb);
  EXPECT_EQ(std::get<std::vector<TextEdit>>(rb).size(), 3u);
}

TEST(Index, RenameRefusals) {
  auto d = open(kFunnels);
  auto fun = d->at("fun (");
  auto bad = [&](uint32_t off, std::string_view name) {
    auto r = d->ix().rename(d->a.file, off, name);
    EXPECT_TRUE(std::holds_alternative<std::string>(r)) << name;
    return std::holds_alternative<std::string>(r) ? std::get<std::string>(r) : std::string();
  };
  EXPECT_NE(bad(fun, "mesh").find("keyword"), std::string::npos);
  EXPECT_NE(bad(fun, "endfunnel").find("keyword"), std::string::npos);
  EXPECT_NE(bad(fun, "2x").find("not a valid name"), std::string::npos);
  EXPECT_NE(bad(fun, "a.b").find("not a valid name"), std::string::npos);
  EXPECT_NE(bad(fun, "").find("not a valid name"), std::string::npos);
  EXPECT_NE(bad(fun, "translate").find("option"), std::string::npos);
  EXPECT_NE(bad(fun, "cf").find("already defined"), std::string::npos);
  EXPECT_NE(bad(d->at("n 4 3"), "ro").find("already defined"), std::string::npos);
  // `fun1` appears in the 2016 name `cube_fun1_hc0`: a new name with `_` is refused …
  EXPECT_NE(bad(d->at("fun1 fun"), "f_1").find("_"), std::string::npos);
  // … and one without is fine, and renames the part inside the joined name.
  auto ok = d->ix().rename(d->a.file, d->at("fun1 fun"), "top");
  ASSERT_TRUE(std::holds_alternative<std::vector<TextEdit>>(ok)) << std::get<std::string>(ok);
  auto edits = std::get<std::vector<TextEdit>>(ok);
  ASSERT_EQ(edits.size(), 2u);
  EXPECT_EQ(edits[1].range.begin, d->at("cube_fun1_hc0", 0, 5));
  // Nothing to rename on a keyword.
  EXPECT_FALSE(d->ix().prepare_rename(d->a.file, d->at("endmesh")));
  EXPECT_TRUE(std::holds_alternative<std::string>(d->ix().rename(d->a.file, d->at("endmesh"), "x")));
}

TEST(Index, RenameRecheckCatchesCapture) {
  // Renaming `fun2` to `fun` would make `cube_fun2_hc1` read as … `cube_fun_…`? No: a new
  // name that makes a 2016 joined name resolve differently must be refused. Here `cf` has
  // instances `ab` and `ab_c`; renaming `x` to `ab` is harmless, but renaming `ab_c`'s
  // sibling so that `g_ab_c_hc0` becomes ambiguous is caught by the re-check.
  auto d = open(R"(funnel fun (4 1 0.5 1) endfunnel
group cf
  instance ab fun endinstance
  instance xy fun endinstance
endgroup
instance g cf endinstance
face q (g_ab_hc0 g_ab_hc1 g_xy_hc0) endface
)");
  ASSERT_EQ(d->diags.error_count(), 0);
  auto r = d->ix().rename(d->a.file, d->at("xy fun"), "ab");
  ASSERT_TRUE(std::holds_alternative<std::string>(r));
  EXPECT_NE(std::get<std::string>(r).find("already defined"), std::string::npos);
}

TEST(Index, HoverSlideSliderMadeByTcl) {
  // A SLIDE slider is a Tk `scale` the scene's Tcl makes: hover shows its value and range.
  auto d = open(R"(tclinit {
  package require slideui
  set swp_q0x 0.9
  CreateScale .w q0x swp_q0x "q0x" 0 2 0.1
}
point q0 ({expr $swp_q0x} 0 0) endpoint
)",
                "t.slf");
  ASSERT_EQ(d->diags.error_count(), 0);
  auto h = d->ix().hover(d->a.file, d->at("$swp_q0x", 0, 6));
  ASSERT_TRUE(h);
  EXPECT_EQ(d->str(h->range), "q0x");
  const std::string& md = h->markdown;
  EXPECT_NE(md.find("0.9"), std::string::npos) << md;
  EXPECT_NE(md.find("| 0.9 | 0 | 2 | 0.1 |"), std::string::npos) << md;
  EXPECT_NE(md.find("bank `swp`"), std::string::npos) << md;
}

TEST(Index, SlideSliderMadeByAHelperHasItsCallAsDefinition) {
  // `CreateSLIDESubdivisionUI` (nomec's slideui) makes the slider `oSub(subdivisions)`; the
  // file never spells `subdivisions` in Tcl, so the slider is defined at the first place the
  // file names its bank, the helper's call.
  auto d = open(R"(tclinit {
  package require slideui
  CreateSLIDESubdivisionObject oSub
  CreateSLIDESubdivisionUI .w oSub
}
point p ({expr $oSub(subdivisions)} 0 0) endpoint
)",
                "t.slf");
  ASSERT_EQ(d->diags.error_count(), 0);
  const Symbol* slider = nullptr;
  for (const Symbol& s : d->ix().symbols()) {
    if (s.name.find("subdivisions") != std::string::npos) slider = &s;
  }
  ASSERT_NE(slider, nullptr);
  EXPECT_EQ(d->str(slider->name_range), "oSub");
  EXPECT_EQ(slider->name_range.begin, d->at("oSub\n  CreateSLIDESubdivisionUI"));
  // Hover on its use shows it; the word at the call is the bank, not the slider's name, so
  // renaming the slider is refused rather than rewriting the call.
  auto h = d->ix().hover(d->a.file, d->at("subdivisions)}"));
  ASSERT_TRUE(h);
  EXPECT_EQ(h->symbol, slider->id);
  EXPECT_NE(h->markdown.find("| 2 | 0 | 5 | 1 |"), std::string::npos) << h->markdown;
  auto r = d->ix().rename(d->a.file, d->at("subdivisions)}"), "levels");
  EXPECT_TRUE(std::holds_alternative<std::string>(r));
}

TEST(Index, HoverSlider) {
  auto d = open(kFunnels);
  auto h = d->ix().hover(d->a.file, d->at("$fp_n", 0, 4));
  ASSERT_TRUE(h);
  EXPECT_EQ(d->str(h->range), "n");
  EXPECT_EQ(h->symbol, d->sym("n 4 3"));
  const std::string& md = h->markdown;
  EXPECT_NE(md.find("bank `fp`"), std::string::npos) << md;
  EXPECT_NE(md.find("| 4 | 3 | 10 | 1 |"), std::string::npos) << md;
  // The slider changes the funnel, so every instance of it and the group instance above.
  EXPECT_NE(md.find("`cf.fun1`"), std::string::npos) << md;
  EXPECT_NE(md.find("`cf.fun2`"), std::string::npos) << md;
  EXPECT_NE(md.find("`cube`"), std::string::npos) << md;
  EXPECT_EQ(md.find("`mi`"), std::string::npos) << md;
  // Hover on the `set` line itself.
  auto hs = d->ix().hover(d->a.file, d->at("n 4 3"));
  ASSERT_TRUE(hs);
  EXPECT_EQ(hs->markdown, md);
}

// Hover on a camera or light shows every field with its value, SLIDE's defaults included;
// the words of a render's camera path are uses of the group, instance and camera they name.
TEST(Index, HoverCameraAndLightValues) {
  auto d = open(R"(camera cam projection SLF_PERSPECTIVE frustum (-0.1 -0.1 -2) (0.1 0.1 -0.01) endcamera
camera plain endcamera
light sun type SLF_DIRECTIONAL endlight
group gCam
  instance cam id iCam translate (0 0 1) endinstance
endgroup
window Window endwindow
viewport vp Window endviewport
render vp gCam.iCam.cam gCam
  light sun
endrender
)",
                "t.slf");
  EXPECT_EQ(d->diags.error_count(), 0);
  auto cam = d->ix().hover(d->a.file, d->at("cam projection"));
  ASSERT_TRUE(cam);
  EXPECT_NE(cam->markdown.find("**camera `cam`**"), std::string::npos) << cam->markdown;
  EXPECT_NE(cam->markdown.find("- `projection` perspective"), std::string::npos) << cam->markdown;
  EXPECT_NE(cam->markdown.find("- `frustum` (-0.1 -0.1 -2) (0.1 0.1 -0.01)"), std::string::npos) << cam->markdown;
  auto plain = d->ix().hover(d->a.file, d->at("plain"));
  ASSERT_TRUE(plain);
  EXPECT_NE(plain->markdown.find("- `projection` parallel (default)"), std::string::npos) << plain->markdown;
  EXPECT_NE(plain->markdown.find("- `frustum` (-1 -1 -100) (1 1 -0.02) (default)"), std::string::npos) << plain->markdown;
  auto sun = d->ix().hover(d->a.file, d->at("sun type"));
  ASSERT_TRUE(sun);
  EXPECT_NE(sun->markdown.find("- `type` directional"), std::string::npos) << sun->markdown;
  EXPECT_NE(sun->markdown.find("- `color` (0.5 0.5 0.5) (default)"), std::string::npos) << sun->markdown;
  auto win = d->ix().hover(d->a.file, d->at("Window endwindow"));
  ASSERT_TRUE(win);
  EXPECT_NE(win->markdown.find("- `background` (0 0 0) (default)"), std::string::npos) << win->markdown;
  // `gCam.iCam.cam`: each part names what it passes through.
  for (const char* part : {"gCam.iCam", "iCam.cam", "cam gCam\n", "vp gCam"}) EXPECT_GE(d->sym(part), 0) << part;
  EXPECT_EQ(d->sym("gCam.iCam"), d->sym("gCam\n"));
  EXPECT_EQ(d->sym("iCam.cam"), d->sym("iCam translate"));
  EXPECT_EQ(d->sym("cam gCam\n"), d->sym("cam projection"));
  EXPECT_EQ(d->sym("vp gCam"), d->sym("vp Window"));
}

TEST(Index, HoverGeneratorInstanceKeyword) {
  auto d = open(kFunnels);
  auto g = d->ix().hover(d->a.file, d->at("fun ("));
  ASSERT_TRUE(g);
  EXPECT_NE(g->markdown.find("**funnel `fun`**"), std::string::npos) << g->markdown;
  EXPECT_NE(g->markdown.find("| `ro` | $fp.ro = 1 | radius of the base ring"), std::string::npos) << g->markdown;
  auto i = d->ix().hover(d->a.file, d->at("fun1 fun"));
  ASSERT_TRUE(i);
  EXPECT_NE(i->markdown.find("instance of funnel `fun`"), std::string::npos) << i->markdown;
  EXPECT_NE(i->markdown.find("`translate` (0 | 0 | 1)"), std::string::npos) << i->markdown;
  EXPECT_TRUE(d->ix().symbols()[i->symbol].node.is_valid());
  auto m = d->ix().hover(d->a.file, d->at("m\n"));
  ASSERT_TRUE(m);
  EXPECT_NE(m->markdown.find("3 points, 1 face"), std::string::npos) << m->markdown;
  auto k = d->ix().hover(d->a.file, d->at("endgroup"));
  ASSERT_TRUE(k);
  EXPECT_EQ(k->markdown, "**`endgroup`** — closes `group`");
  auto k2 = d->ix().hover(d->a.file, d->at("instance cube") + 2);
  ASSERT_TRUE(k2);
  EXPECT_NE(k2->markdown.find("places a mesh"), std::string::npos);
  EXPECT_FALSE(d->ix().hover(d->a.file, d->at("(0 0 0)") + 1));
}

TEST(Index, HighGenusBlocksInOutlineAndHover) {
  auto d = open(R"(mesh sq
  point a (0 0 0) endpoint
  point b (1 0 0) endpoint
  point c (1 1 0) endpoint
  face f (a b c) endface
endmesh
menger sponge level 1 thickness 0.2
  instance k sq endinstance
endmenger
handle h faces (k.f k.f)
  instance k sq endinstance
endhandle
)");
  auto top = d->ix().outline(d->a.file);
  std::vector<std::string> names;
  for (SymbolId s : top) names.push_back(d->ix().symbols()[s].name);
  EXPECT_EQ(names, (std::vector<std::string>{"sq", "sponge", "h"}));
  auto kw = d->ix().hover(d->a.file, d->at("menger sponge") + 1);
  ASSERT_TRUE(kw);
  EXPECT_NE(kw->markdown.find("generalized Menger sponge"), std::string::npos) << kw->markdown;
  auto opt = d->ix().hover(d->a.file, d->at("thickness") + 1);
  ASSERT_TRUE(opt);
  EXPECT_NE(opt->markdown.find("tunnel depth"), std::string::npos) << opt->markdown;
  auto faces = d->ix().hover(d->a.file, d->at("faces") + 1);
  ASSERT_TRUE(faces);
  EXPECT_NE(faces->markdown.find("the two faces a handle joins"), std::string::npos) << faces->markdown;
}

// SLIDE's disk, ring and cyclide have nomec's defaults (docs/dialects.md); hover on a field
// shows its meaning and default, hover on the keyword the shape.
TEST(Index, SlideQuadricFieldsShowTheirDefaults) {
  auto d = open("disk dk thetaslices 8 enddisk\nring rg outerradius 2 endring\n"
                "cyclide cy eccentricity 0.1 endcyclide\n",
                "t.slf");
  auto slices = d->ix().hover(d->a.file, d->at("thetaslices") + 1);
  ASSERT_TRUE(slices);
  EXPECT_NE(slices->markdown.find("default 16"), std::string::npos) << slices->markdown;
  auto outer = d->ix().hover(d->a.file, d->at("outerradius") + 1);
  ASSERT_TRUE(outer);
  EXPECT_NE(outer->markdown.find("twice the inner radius"), std::string::npos) << outer->markdown;
  auto ecc = d->ix().hover(d->a.file, d->at("eccentricity") + 1);
  ASSERT_TRUE(ecc);
  EXPECT_NE(ecc->markdown.find("0 is a torus (default half the minorradius: 0.125)"), std::string::npos) << ecc->markdown;
  auto kw = d->ix().hover(d->a.file, d->at("disk dk") + 1);
  ASSERT_TRUE(kw);
  EXPECT_NE(kw->markdown.find("fan of triangles around a centre vertex"), std::string::npos) << kw->markdown;
}

TEST(Index, IncludedFileSymbols) {
  CheckOptions opts;
  opts.read_file = [](const std::string& path) -> std::optional<std::string> {
    if (path.ends_with("shapes.slf")) return std::string("surface red color (1 0 0) endsurface\n");
    return std::nullopt;
  };
  auto d = open("include \"shapes.slf\"\npoint a (0 0 0) endpoint\npoint b (1 0 0) endpoint\npoint c (0 1 0) endpoint\n"
                "face f (a b c) surface red endface\n",
                "main.slf", opts);
  SymbolId red = d->sym("red");
  ASSERT_GE(red, 0);
  const Symbol& s = d->ix().symbols()[red];
  EXPECT_NE(s.name_range.file, d->a.file);
  EXPECT_EQ(d->a.sources->text(s.name_range), "red");
  EXPECT_EQ(d->ix().outline(s.name_range.file).size(), 1u);
}

TEST(Index, SlideLateBindingAndInstanceIds) {
  auto d = open(R"(group scene
  instance box id b1 endinstance
  instance box endinstance
endgroup
object box (f1) endobject
point p (0 0 0) endpoint
point q (1 0 0) endpoint
point r (0 1 0) endpoint
face f1 (p q r) endface
instance scene endinstance
)", "late.slf");
  ASSERT_EQ(d->diags.error_count(), 0);
  // `box` and `f1` are used above their definitions: SLIDE binds late.
  SymbolId box = d->sym("box (f1)");
  ASSERT_GE(box, 0);
  EXPECT_EQ(d->ix().symbols()[box].kind, SymbolKind::Object);
  EXPECT_EQ(d->sym("box id"), box);
  EXPECT_EQ(d->sym("box endinstance"), box);
  EXPECT_EQ(d->sym("f1) endobject"), d->sym("f1 (p"));
  EXPECT_EQ(d->ix().references(box, false).size(), 2u);
  // `id b1` names the first instance; the second is named by its target and has no
  // definition of its own, so it cannot be renamed.
  SymbolId b1 = d->sym("b1");
  ASSERT_GE(b1, 0);
  EXPECT_EQ(d->ix().symbols()[b1].kind, SymbolKind::Instance);
  EXPECT_TRUE(d->ix().references(b1, true)[0].is_definition);
  EXPECT_EQ(d->sym("scene endinstance"), d->sym("scene\n"));
  auto r = d->ix().rename(d->a.file, d->at("box (f1)"), "cube");
  ASSERT_TRUE(std::holds_alternative<std::vector<TextEdit>>(r)) << std::get<std::string>(r);
  EXPECT_EQ(std::get<std::vector<TextEdit>>(r).size(), 3u);
}

TEST(Index, BuildFromOwnCheck) {
  // The language server's way: its own SourceManager and CheckResult, then `build`.
  auto sources = std::make_shared<SourceManager>();
  DiagnosticEngine diags;
  CheckOptions opts;
  opts.record_names = true;
  std::string text = kFunnels;
  auto check = std::make_shared<const CheckResult>(check_source(*sources, "t.nome", text, opts, diags));
  auto ix = build(sources, check, opts);
  FileId f = check->asts.front()->file;
  auto o = ix->occurrence_at(f, static_cast<uint32_t>(text.find("fun translate")));
  ASSERT_TRUE(o);
  EXPECT_EQ(ix->symbols()[o->symbol].name, "fun");
  // Rename re-checks with the given options: a clash made by the new name is refused.
  auto ok = ix->rename(f, o->range.begin, "spout");
  ASSERT_TRUE(std::holds_alternative<std::vector<TextEdit>>(ok)) << std::get<std::string>(ok);
  EXPECT_EQ(std::get<std::vector<TextEdit>>(ok).size(), 3u);
  // Without `record_names`, only definitions are known.
  auto sources2 = std::make_shared<SourceManager>();
  auto check2 = std::make_shared<const CheckResult>(check_source(*sources2, "t.nome", text, CheckOptions{}, diags));
  EXPECT_TRUE(check2->asts.empty());
  EXPECT_TRUE(check2->name_uses.empty());
}

TEST(Index, CompletionInsideMeshUsesItsPoints) {
  std::string text = "mesh m\n  point a (0 0 0) endpoint\n  point b (1 0 0) endpoint\n  face f (a ";
  auto d = open(text);
  auto v = labels(d->ix().complete(d->a.file, static_cast<uint32_t>(text.size())));
  EXPECT_TRUE(has(v, "a"));
  EXPECT_TRUE(has(v, "b"));
  // In the mesh body: its statements and its end keyword.
  std::string t2 = "mesh m\n  point a (0 0 0) endpoint\n  ";
  auto d2 = open(t2);
  auto k = labels(d2->ix().complete(d2->a.file, static_cast<uint32_t>(t2.size())));
  EXPECT_TRUE(has(k, "point"));
  EXPECT_TRUE(has(k, "face"));
  EXPECT_TRUE(has(k, "endmesh"));
  EXPECT_FALSE(has(k, "endgroup"));
}

}  // namespace
}  // namespace nomec::index
