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

TEST(Index, DefinitionsAndUses) {
  auto d = open(kFunnels);
  EXPECT_EQ(d->diags.error_count(), 0);
  SymbolId fun = d->sym("fun (");
  ASSERT_GE(fun, 0);
  EXPECT_EQ(d->ix().symbols()[fun].name, "fun");
  EXPECT_EQ(d->ix().symbols()[fun].kind, SymbolKind::Generator);
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

}  // namespace
}  // namespace nomec::index
