// Index construction and the position queries (occurrence_at, references, outline). One
// pass over the syntax trees finds every definition and pairs it with its IR node by range;
// uses come from the checker's recorded name resolutions, the IR's parameter expressions
// and vertex references (split into their instance-path parts), and bank `list`s and
// `savedparameter` lines. Everything is linear in the size of the scene plus a sort.
#include "frontend/index/index.h"

#include <algorithm>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <unordered_map>

#include "frontend/ast/ast.h"
#include "ir/generator_catalogue.h"

namespace nomec::index {

using ast::BlockKind;
using ast::ItemKind;

std::string_view symbol_kind_name(SymbolKind kind) {
  switch (kind) {
    case SymbolKind::Bank: return "bank";
    case SymbolKind::Parameter: return "slider";
    case SymbolKind::Point: return "point";
    case SymbolKind::Polyline: return "polyline";
    case SymbolKind::Face: return "face";
    case SymbolKind::Mesh: return "mesh";
    case SymbolKind::Object: return "object";
    case SymbolKind::Group: return "group";
    case SymbolKind::Instance: return "instance";
    case SymbolKind::Generator: return "generator";
    case SymbolKind::Surface: return "surface";
    case SymbolKind::Block: return "block";
    case SymbolKind::Other: return "definition";
  }
  return "definition";
}

namespace {

struct RangeKey {
  int32_t file;
  uint32_t begin, end;
  friend auto operator<=>(const RangeKey&, const RangeKey&) = default;
};
struct NodeAt {
  RangeKey key;
  ir::NodeId node;
};
// (parent symbol, name) → symbol, without building a string per lookup.
struct MemberKey {
  SymbolId parent;
  std::string_view name;
  friend bool operator==(const MemberKey&, const MemberKey&) = default;
};
struct MemberKeyHash {
  size_t operator()(const MemberKey& k) const {
    return std::hash<std::string_view>{}(k.name) ^ (static_cast<size_t>(k.parent) * 0x9E3779B97F4A7C15ull);
  }
};
RangeKey key_of(SourceRange r) { return {r.file.index, r.begin, r.end}; }

SymbolKind kind_of(BlockKind k) {
  switch (k) {
    case BlockKind::Bank: return SymbolKind::Bank;
    case BlockKind::Point: case BlockKind::Vertex: case BlockKind::Controlpoint: return SymbolKind::Point;
    case BlockKind::Polyline: return SymbolKind::Polyline;
    case BlockKind::Face: case BlockKind::Facet: return SymbolKind::Face;
    case BlockKind::Mesh: case BlockKind::Savedworkingmesh: case BlockKind::Consolidate: return SymbolKind::Mesh;
    case BlockKind::Object: return SymbolKind::Object;
    case BlockKind::Group: return SymbolKind::Group;
    case BlockKind::Instance: return SymbolKind::Instance;
    case BlockKind::Surface: return SymbolKind::Surface;
    default: break;
  }
  switch (ast::category(k)) {
    case ast::BlockCategory::Gen: return SymbolKind::Generator;
    case ast::BlockCategory::Pipe: return SymbolKind::Block;
    default: return SymbolKind::Other;
  }
}

bool less_range(const SourceRange& a, const SourceRange& b) {
  if (a.file.index != b.file.index) return a.file.index < b.file.index;
  if (a.begin != b.begin) return a.begin < b.begin;
  return a.end < b.end;
}

}  // namespace

class Builder {
 public:
  Builder(Index& ix) : ix_(ix), sm_(*ix.sources_), cr_(*ix.check_), m_(cr_.module) {}

  void run() {
    ix_.node_symbol_.assign(m_.nodes.size(), -1);
    node_by_range_.reserve(m_.nodes.size());
    ix_.symbols_.reserve(m_.nodes.size() / 2 + 16);
    occ_.reserve(cr_.name_uses.size() + m_.nodes.size() + m_.exprs.size() / 4);
    for (size_t i = 0; i < m_.nodes.size(); ++i) {
      const ir::Node& n = m_.nodes[i];
      if (n.kind == ir::NodeKind::Value || !n.range.is_valid()) continue;
      node_by_range_.push_back({key_of(n.range), ir::NodeId{static_cast<int32_t>(i)}});
    }
    // Stable: the first node made for a range (the declared one) wins.
    std::stable_sort(node_by_range_.begin(), node_by_range_.end(),
                     [](const NodeAt& a, const NodeAt& b) { return a.key < b.key; });
    for (const auto& a : cr_.asts) {
      ast_ = a.get();
      for (const ast::Item& it : a->top) {
        if (it.kind == ItemKind::Block) visit(a->stmt(it.block), -1, BlockKind::Bank, true);
      }
    }
    tcl_sliders();
    collect_uses();
    finish();
  }

 private:
  SymbolId add_symbol(std::string name, SymbolKind kind, SourceRange name_range, SourceRange full,
                      SymbolId parent, ir::NodeId node, bool add_def = true) {
    Symbol s;
    s.id = static_cast<SymbolId>(ix_.symbols_.size());
    s.name = std::move(name);
    s.kind = kind;
    s.name_range = name_range;
    s.full_range = full;
    s.parent = parent;
    s.node = node;
    if (node.is_valid() && ix_.node_symbol_[node.index] < 0) ix_.node_symbol_[node.index] = s.id;
    if (add_def && name_range.is_valid()) occ_.push_back({name_range, s.id, true});
    ix_.symbols_.push_back(std::move(s));
    return ix_.symbols_.back().id;
  }

  ir::NodeId node_at(SourceRange r) const {
    RangeKey k = key_of(r);
    auto it = std::lower_bound(node_by_range_.begin(), node_by_range_.end(), k,
                               [](const NodeAt& a, const RangeKey& key) { return a.key < key; });
    return it != node_by_range_.end() && it->key == k ? it->node : ir::NodeId::None();
  }

  // Does this statement define the word after its keyword?
  bool defines_name(const ast::Stmt& s, BlockKind parent_kind, bool top) const {
    switch (s.kind) {
      case BlockKind::Transform: case BlockKind::Delete: case BlockKind::Consolidate:
      case BlockKind::Consolidateface: case BlockKind::Sharp: case BlockKind::Lookat:
      case BlockKind::Savedparameter: case BlockKind::Path: case BlockKind::Bank:
      case BlockKind::Instance: case BlockKind::Render:  // `render VIEWPORT …` names what it uses
        return false;
      case BlockKind::Crosssection: return top;
      case BlockKind::Vertex: return parent_kind == BlockKind::Mesh;
      case BlockKind::Face:
      case BlockKind::Facet:
        return parent_kind != BlockKind::Delete && parent_kind != BlockKind::Savedworkingmesh;
      default: return true;
    }
  }

  void visit(const ast::Stmt& s, SymbolId parent, BlockKind parent_kind, bool top) {
    SymbolId me = -1;
    ir::NodeId node = node_at(s.range);
    const bool named = !s.items.empty() && s.items[0].kind == ItemKind::Word;
    if (s.kind == BlockKind::Bank) {
      if (named) {
        me = add_symbol(std::string(s.items[0].text), SymbolKind::Bank, s.items[0].range, s.range, parent, node);
        ix_.symbols_[me].detail = "bank";
        bank_symbol_.emplace(std::string(s.items[0].text), me);
        read_bank(s, me);
      }
    } else if (s.kind == BlockKind::Instance) {
      visit_instance(s, parent, node, me);
    } else if (named && defines_name(s, parent_kind, top)) {
      me = add_symbol(std::string(s.items[0].text), kind_of(s.kind), s.items[0].range, s.range, parent, node);
      std::optional<ir::GenKind> gen = statement_generator(s);
      const ir::Signature* sig = gen ? ir::generator(*gen).signature(cr_.dialect) : nullptr;
      if (sig != nullptr) {
        ix_.symbols_[me].detail = fmt::format("{} ({})", s.keyword,
                                              fmt::join(sig->names.begin(), sig->names.begin() + static_cast<ptrdiff_t>(sig->args.size()), " "));
      } else {
        ix_.symbols_[me].detail = std::string(s.keyword);
      }
      if (s.kind == BlockKind::Point || s.kind == BlockKind::Vertex) {
        if (parent >= 0) member_points_.emplace(member_key(parent, s.items[0].text), me);
      }
    } else if (s.kind == BlockKind::Savedparameter) {
      saved_.push_back({ast_, &s});
    } else if (s.kind == BlockKind::Consolidate && node.is_valid()) {
      // `consolidate` defines the mesh `consolidatemesh` at its keyword.
      me = add_symbol(m_.node(node).name, SymbolKind::Mesh, s.open_kw, s.range, parent, node, false);
      ix_.symbols_[me].detail = "consolidate";
    }
    SymbolId child_parent = me >= 0 ? me : parent;
    for (const ast::Item& it : s.items) {
      if (it.kind == ItemKind::Block) visit(ast_->stmt(it.block), child_parent, s.kind, false);
    }
  }

  void visit_instance(const ast::Stmt& s, SymbolId parent, ir::NodeId node, SymbolId& me) {
    if (s.items.empty() || s.items[0].kind != ItemKind::Word) return;
    bool slide = cr_.dialect == Dialect::Slide;
    SourceRange name_range = s.items[0].range;
    std::string name(s.items[0].text);
    bool add_def = true;
    if (slide) {
      // `instance TARGET [id NAME]`: the name is the `id`, else the target's name.
      add_def = false;
      for (size_t i = 1; i + 1 < s.items.size(); ++i) {
        if (s.items[i].kind == ItemKind::Word && s.items[i].text == "id" && s.items[i + 1].kind == ItemKind::Word) {
          name_range = s.items[i + 1].range;
          name = std::string(s.items[i + 1].text);
          add_def = true;
        }
      }
    }
    me = add_symbol(name, SymbolKind::Instance, name_range, s.range, parent, node, add_def);
    std::string detail = "instance";
    if (node.is_valid() && m_.node(node).kind == ir::NodeKind::Instance && m_.get<ir::InstanceData>(node).target.is_valid()) {
      const ir::Node& t = m_.node(m_.get<ir::InstanceData>(node).target);
      detail = fmt::format("instance of {} `{}`", t.keyword, t.name);
    }
    ix_.symbols_[me].detail = std::move(detail);
  }

  // SLIDE sliders: Tk `scale` widgets the scene's Tcl made (frontend/check/tcl.cpp), with
  // their bank (`swp` of `swp_q0x`) in the detail; defined where the checker found the
  // slider's name.
  void tcl_sliders() {
    for (ir::NodeId p : m_.params()) {
      const ir::Node& n = m_.node(p);
      if (n.keyword != "scale" || sym(p) >= 0) continue;
      const ir::ParamData& pd = m_.param(p);
      // A bank the file writes (`bank swp … endbank`) is its parent; Tcl's have no symbol.
      SymbolId bank = -1;
      if (auto b = bank_symbol_.find(pd.bank); b != bank_symbol_.end()) bank = b->second;
      std::string_view shortname = std::string_view(n.name).substr(std::min(n.name.size(), pd.bank.size() + 1));
      // Made by a helper whose call names only the bank (`CreateSLIDESubdivisionUI $w oSub`):
      // located at that call, with no definition occurrence there (the word is not the
      // slider's name, so the slider cannot be renamed); made where the file spells neither:
      // no symbol.
      const bool spelled = sm_.text(n.range) == shortname;
      if (!spelled && sm_.text(n.range) != pd.bank) continue;
      SymbolId sid = add_symbol(std::string(shortname), SymbolKind::Parameter, n.range, n.range, bank, p, spelled);
      ix_.symbols_[sid].detail = fmt::format("{} = {} in [{}, {}] step {} (a Tk `scale` made by the scene's Tcl code)",
                                             n.name, pd.value, pd.min, pd.max, pd.step);
      if (bank >= 0) member_params_.emplace(member_key(bank, shortname), sid);
    }
  }

  // `set NAME value min max step` lines and `list (names)` in a bank.
  void read_bank(const ast::Stmt& s, SymbolId bank) {
    for (size_t i = 1; i < s.items.size(); ++i) {
      const ast::Item& it = s.items[i];
      if (it.kind != ItemKind::Word) continue;
      if (it.text == "set" && i + 1 < s.items.size() && s.items[i + 1].kind == ItemKind::Word) {
        const ast::Item& name = s.items[i + 1];
        size_t j = i + 2;
        uint32_t end = name.range.end;
        while (j < s.items.size() && s.items[j].kind != ItemKind::Word && s.items[j].kind != ItemKind::Block) {
          end = s.items[j].range.end;
          ++j;
        }
        ir::NodeId p = node_at(name.range);
        if (!p.is_valid() || m_.node(p).kind != ir::NodeKind::Param) continue;  // duplicate: reported
        SymbolId sid = add_symbol(std::string(name.text), SymbolKind::Parameter, name.range,
                                  SourceRange{name.range.file, it.range.begin, end}, bank, p);
        const ir::ParamData& pn = m_.param(p);
        ix_.symbols_[sid].detail = fmt::format("{} = {} in [{}, {}] step {}", m_.node(p).name, pn.value, pn.min, pn.max, pn.step);
        member_params_.emplace(member_key(bank, name.text), sid);
        i = j - 1;
      } else if (it.text == "list" && i + 1 < s.items.size() && s.items[i + 1].kind == ItemKind::List) {
        lists_.push_back({ast_, s.items[i + 1].list, bank});
        ++i;
      }
    }
  }

  // Names view the source text (or the IR's strings), which outlive the builder.
  static MemberKey member_key(SymbolId parent, std::string_view name) { return {parent, name}; }

  SymbolId sym(ir::NodeId n) const {
    return n.is_valid() && n.index < static_cast<int32_t>(ix_.node_symbol_.size()) ? ix_.node_symbol_[n.index] : -1;
  }

  void use(SourceRange r, SymbolId s) {
    if (s >= 0 && r.is_valid() && r.end > r.begin) occ_.push_back({r, s, false});
  }

  // `$fp.n`, `$fp_n`, `fp.n`, `fp_n`: the bank part and the slider part.
  void param_use(SourceRange r, ir::NodeId p) {
    SymbolId ps = sym(p);
    if (ps < 0) return;
    const ir::Node& pn = m_.node(p);
    std::string_view text = sm_.text(r);
    uint32_t o = !text.empty() && text[0] == '$' ? 1 : 0;
    std::string_view rest = text.substr(o);
    std::string_view bank = m_.param(p).bank;
    std::string_view shortname = std::string_view(pn.name).substr(std::min(pn.name.size(), bank.size() + 1));
    if (rest.size() == bank.size() + 2 + shortname.size() && rest.substr(0, bank.size()) == bank &&
        rest[bank.size()] == '(' && rest.back() == ')') {  // SLIDE's Tcl array element `$oOffset(height)`
      use(SourceRange{r.file, static_cast<uint32_t>(r.begin + o + bank.size() + 1), r.end - 1}, ps);
      return;
    }
    if (rest.size() == bank.size() + 1 + shortname.size() && rest.substr(0, bank.size()) == bank &&
        (rest[bank.size()] == '.' || rest[bank.size()] == '_') && rest.substr(bank.size() + 1) == shortname) {
      SymbolId bs = ix_.symbols_[ps].parent;
      use(SourceRange{r.file, r.begin + o, static_cast<uint32_t>(r.begin + o + bank.size())}, bs);
      use(SourceRange{r.file, static_cast<uint32_t>(r.begin + o + bank.size() + 1), r.end}, ps);
      return;
    }
    use(SourceRange{r.file, r.begin + o, r.end}, ps);
  }

  SymbolId bank_param(SymbolId bank, std::string_view name) const {
    auto it = member_params_.find(member_key(bank, name));
    return it == member_params_.end() ? -1 : it->second;
  }

  // A saved-parameter word `fp_n` / `fp.n`: longest bank prefix, as the checker does.
  void saved_param_use(SourceRange r, std::string_view text) {
    for (size_t u = text.size(); u-- > 1;) {
      if (text[u] != '_' && text[u] != '.') continue;
      auto b = bank_symbol_.find(std::string(text.substr(0, u)));
      if (b == bank_symbol_.end()) continue;
      SymbolId p = bank_param(b->second, text.substr(u + 1));
      if (p < 0) continue;
      use(SourceRange{r.file, r.begin, static_cast<uint32_t>(r.begin + u)}, b->second);
      use(SourceRange{r.file, static_cast<uint32_t>(r.begin + u + 1), r.end}, p);
      return;
    }
  }

  void vertex_use(const ir::VertexRef& ref) {
    if (!ref.range.is_valid()) return;
    if (ref.point.is_valid()) {
      use(ref.range, sym(ref.point));
      return;
    }
    if (ref.instances.empty()) return;
    std::string_view text = sm_.text(ref.range);
    uint32_t at = 0;
    bool dotted = text.find('.', text.size() > 0 && text[0] == '.' ? 1 : 0) != std::string_view::npos;
    char sep = dotted ? '.' : '_';
    while (at < text.size() && text[at] == sep) ++at;
    SymbolId last = -1;
    for (ir::NodeId inst : ref.instances) {
      SymbolId s = sym(inst);
      if (s < 0) return;
      const std::string& nm = ix_.symbols_[s].name;
      if (text.compare(at, nm.size(), nm) != 0) return;
      use(SourceRange{ref.range.file, ref.range.begin + at, static_cast<uint32_t>(ref.range.begin + at + nm.size())}, s);
      at += static_cast<uint32_t>(nm.size());
      if (at >= text.size() || text[at] != sep) return;
      ++at;
      last = s;
    }
    // The last part: a point of the instanced mesh.
    ir::NodeId inst_node = ref.instances.back();
    ir::NodeId target = m_.get<ir::InstanceData>(inst_node).target;
    SymbolId ts = sym(target);
    (void)last;
    if (ts < 0) return;
    auto it = member_points_.find(member_key(ts, text.substr(at)));
    if (it != member_points_.end()) use(SourceRange{ref.range.file, ref.range.begin + at, ref.range.end}, it->second);
  }

  void collect_uses() {
    for (const NameUse& u : cr_.name_uses) use(u.use, sym(u.def));
    for (const ir::Expr& e : m_.exprs) {
      if (e.kind == ir::ExprKind::Param && e.param.is_valid()) param_use(e.range, e.param);
    }
    for (const ir::Node& n : m_.nodes) {
      for (ir::Slice<ir::VertexRef> list : ir::vertex_lists_of(m_, n)) {
        for (const ir::VertexRef& v : m_.refs(list)) vertex_use(v);
      }
    }
    for (const ListUse& l : lists_) {
      for (ast::ExprId e : l.ast->list(l.list).elems) {
        const ast::Expr& x = l.ast->expr(e);
        if (x.kind == ast::ExprKind::Name) use(x.range, bank_param(l.bank, x.text));
      }
    }
    for (const SavedUse& sv : saved_) {
      for (const ast::Item& it : sv.stmt->items) {
        if (it.kind == ItemKind::Word) saved_param_use(it.range, it.text);
      }
    }
  }

  void finish() {
    auto& occ = occ_;
    std::stable_sort(occ.begin(), occ.end(), [](const Occurrence& a, const Occurrence& b) {
      if (!(a.range == b.range)) return less_range(a.range, b.range);
      return a.is_definition > b.is_definition;
    });
    // One occurrence per place: the checker may resolve a word twice (e.g. a throw-away
    // colour check), and a definition wins over a use at the same range.
    std::vector<Occurrence>& out = ix_.occurrences_;
    out.reserve(occ.size());
    for (const Occurrence& o : occ) {
      if (!out.empty() && out.back().range.file == o.range.file && o.range.begin < out.back().range.end) continue;
      out.push_back(o);
    }
    size_t n = ix_.symbols_.size();
    ix_.ref_begin_.assign(n + 1, 0);
    for (const Occurrence& o : out) ++ix_.ref_begin_[o.symbol + 1];
    for (size_t i = 0; i < n; ++i) ix_.ref_begin_[i + 1] += ix_.ref_begin_[i];
    ix_.ref_items_.resize(out.size());
    std::vector<uint32_t> fill(ix_.ref_begin_.begin(), ix_.ref_begin_.end() - 1);
    for (size_t i = 0; i < out.size(); ++i) ix_.ref_items_[fill[out[i].symbol]++] = static_cast<uint32_t>(i);
  }

  struct ListUse {
    const ast::Ast* ast;
    ast::ListId list;
    SymbolId bank;
  };
  struct SavedUse {
    const ast::Ast* ast;
    const ast::Stmt* stmt;
  };

  Index& ix_;
  const SourceManager& sm_;
  const CheckResult& cr_;
  const ir::Module& m_;
  const ast::Ast* ast_ = nullptr;
  std::vector<NodeAt> node_by_range_;  // sorted by range
  std::unordered_map<std::string, SymbolId> bank_symbol_;
  std::unordered_map<MemberKey, SymbolId, MemberKeyHash> member_params_;
  std::unordered_map<MemberKey, SymbolId, MemberKeyHash> member_points_;
  std::vector<ListUse> lists_;
  std::vector<SavedUse> saved_;
  std::vector<Occurrence> occ_;
};

std::shared_ptr<const Index> build(std::shared_ptr<const SourceManager> sources,
                                   std::shared_ptr<const CheckResult> check, std::optional<CheckOptions> recheck) {
  auto ix = std::make_shared<Index>();
  ix->sources_ = std::move(sources);
  ix->check_ = std::move(check);
  if (recheck && !ix->check_->asts.empty()) {
    ix->options_ = std::move(recheck);
    ix->main_path_ = std::string(ix->sources_->name(ix->check_->asts.front()->file));
  }
  Builder(*ix).run();
  return ix;
}

Analysis analyze(const std::string& path, std::string text, CheckOptions options, DiagnosticEngine& diags) {
  return analyze(path, std::move(text), std::move(options), diags, nullptr);
}

Checked check_document(const std::string& path, std::string text, CheckOptions options, DiagnosticEngine& diags,
                       ParseCache* cache) {
  auto sources = std::make_shared<SourceManager>();
  options.record_names = true;
  int errors_before = diags.error_count();
  Checked c;
  auto check = std::make_shared<CheckResult>(check_source(*sources, path, std::move(text), options, diags, cache));
  c.file = check->asts.empty() ? FileId{0} : check->asts.front()->file;
  c.sources = std::move(sources);
  c.check = std::move(check);
  c.options = std::move(options);
  c.options.parsed = nullptr;  // belongs to this check (it may hold what its caller owns)
  c.options.cancelled = nullptr;
  c.path = path;
  c.error_count = diags.error_count() - errors_before;
  return c;
}

std::shared_ptr<const Index> build(const Checked& checked) {
  auto ix = std::make_shared<Index>();
  ix->sources_ = checked.sources;
  ix->check_ = checked.check;
  ix->options_ = checked.options;
  ix->main_path_ = checked.path;
  ix->error_count_ = checked.error_count;
  Builder(*ix).run();
  return ix;
}

Analysis analyze(const std::string& path, std::string text, CheckOptions options, DiagnosticEngine& diags,
                 ParseCache* cache) {
  Checked c = check_document(path, std::move(text), std::move(options), diags, cache);
  Analysis a;
  a.file = c.file;
  a.sources = c.sources;
  a.check = c.check;
  a.index = build(c);
  return a;
}

// ---------------- position queries ----------------

SymbolId Index::symbol_of(ir::NodeId node) const {
  return node.is_valid() && node.index < static_cast<int32_t>(node_symbol_.size()) ? node_symbol_[node.index] : -1;
}

std::optional<Occurrence> Index::occurrence_at(FileId file, uint32_t offset) const {
  auto find = [&](uint32_t off) -> const Occurrence* {
    // First occurrence starting after `off`; the one before it may contain `off`.
    auto it = std::upper_bound(occurrences_.begin(), occurrences_.end(), std::pair{file.index, off},
                               [](const std::pair<int32_t, uint32_t>& k, const Occurrence& o) {
                                 return k.first != o.range.file.index ? k.first < o.range.file.index : k.second < o.range.begin;
                               });
    if (it == occurrences_.begin()) return nullptr;
    const Occurrence& o = *std::prev(it);
    if (o.range.file == file && o.range.begin <= off && off < o.range.end) return &o;
    return nullptr;
  };
  if (const Occurrence* o = find(offset)) return *o;
  // The cursor just after a word (`fun1|`) or on the `$` of `$fp.n`.
  if (offset > 0) {
    if (const Occurrence* o = find(offset - 1)) return *o;
  }
  std::string_view text = sources_->text(file);
  if (offset < text.size() && text[offset] == '$') {
    if (const Occurrence* o = find(offset + 1)) return *o;
  }
  return std::nullopt;
}

std::vector<Occurrence> Index::references(SymbolId s, bool include_declaration) const {
  std::vector<Occurrence> out;
  if (s < 0 || s >= static_cast<SymbolId>(symbols_.size())) return out;
  for (uint32_t i = ref_begin_[s]; i < ref_begin_[s + 1]; ++i) {
    const Occurrence& o = occurrences_[ref_items_[i]];
    if (o.is_definition && !include_declaration) continue;
    out.push_back(o);
  }
  return out;
}

std::vector<SymbolId> Index::outline(FileId file) const {
  std::vector<SymbolId> out;
  for (const Symbol& s : symbols_) {
    if (s.parent < 0 && s.full_range.file == file) out.push_back(s.id);
  }
  std::stable_sort(out.begin(), out.end(), [&](SymbolId a, SymbolId b) {
    return symbols_[a].full_range.begin < symbols_[b].full_range.begin;
  });
  return out;
}

SymbolId Index::symbol_at(FileId file, uint32_t offset, SourceRange* range) const {
  std::optional<Occurrence> o = occurrence_at(file, offset);
  if (!o) return -1;
  if (range != nullptr) *range = o->range;
  return o->symbol;
}

}  // namespace nomec::index
