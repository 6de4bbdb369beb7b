// AST: the syntax of one file with exact ranges, independent of ANTLR. A block statement
// keeps its body as an ordered list of items (words, lists, values, nested blocks); the
// checker gives the items meaning per block kind. IDs index the arrays of `Ast`.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "base/id.h"
#include "base/small_vec.h"
#include "frontend/source/source_manager.h"

namespace nomec::ast {

/// Every block statement kind, e.g. `BlockKind::Mesh` for `mesh m … endmesh`; every
/// generator (`funnel fun (…) endfunnel`) is `BlockKind::Generator`.
enum class BlockKind : uint8_t {
#define NOMEC_BLOCK(Kind, Open, Category) Kind,
#include "frontend/ast/block_kinds.def"
#undef NOMEC_BLOCK
};

/// Number of block kinds in block_kinds.def.
inline constexpr int kBlockKindCount = 0
#define NOMEC_BLOCK(Kind, Open, Category) +1
#include "frontend/ast/block_kinds.def"
#undef NOMEC_BLOCK
    ;

enum class BlockCategory : uint8_t { Def, Gen, Pipe, Edit, Scene, Sub };

/// The keyword opening a block of this kind, e.g. `mesh`; for `Generator`, which has one
/// per generator, the word `generator` (messages that know the statement use its keyword).
std::string_view open_keyword(BlockKind kind);
BlockCategory category(BlockKind kind);
/// The kind a word opens (`mesh`, or a generator keyword of the catalogue such as `funnel`).
std::optional<BlockKind> block_of_keyword(std::string_view word);
/// The kind an end keyword closes (`endmesh`, `endfunnel`, …).
std::optional<BlockKind> block_of_end_keyword(std::string_view word);
/// The end keyword of an opening keyword: `end` + keyword.
std::string end_keyword(std::string_view keyword);
/// All opening keywords, generators' included (for "did you mean" on misspelled statements).
const std::vector<std::string_view>& all_open_keywords();

struct ExprTag;
struct ListTag;
struct StmtTag;
using ExprId = Id<ExprTag>;
using ListId = Id<ListTag>;
using StmtId = Id<StmtTag>;

enum class ExprKind : uint8_t {
  Number,       // `0.5`
  DollarRef,    // `$fp.n`, `$fp_n`, `$time` (text keeps the `$`)
  TclArrayRef,  // `$oSubdivision(type)`
  Name,         // a bare word in an expression: `p1`, `fp.n`, `pi`
  Call,         // `sin(x)`; text is the function name
  Unary,        // `-x`; op is '+' or '-'
  Binary,       // `a * b`; op is one of + - * / % ^ and 'i' for `//`
  Raw,          // `[ … ]` function text, `%{ … }%`, or a Tcl script in braces
  String,       // `"viewing.slf"`
  Error,        // unparsable; a syntax diagnostic was already emitted
};

/// One expression node, e.g. `{expr $fp_ro * 2}` becomes Binary(DollarRef, Number).
// Rationale: a large scene has about one expression per eight source bytes, so an
// expression is 40 bytes: what only some kinds have (a number's value, an operator's
// operands, a call's arguments) shares two words, read through accessors that look at
// `kind`, and a call's arguments are a slice of `Ast::args` (`Ast::args(e)`).
struct Expr {
  std::string_view text;  // name, reference, raw text (views the source)
  SourceRange range;
  ExprKind kind = ExprKind::Error;
  char op = 0;
  bool in_braces = false;      // written as `{expr …}` or `{…}`
  bool parenthesized = false;  // written as `( … )`; the range is inside the parentheses

  /// Unary operand or binary left; None for other kinds.
  ExprId lhs() const { return kind == ExprKind::Unary || kind == ExprKind::Binary ? ExprId(a_) : ExprId::None(); }
  /// Binary right; None for other kinds.
  ExprId rhs() const { return kind == ExprKind::Binary ? ExprId(b_) : ExprId::None(); }
  /// A Number's value; 0 for other kinds.
  double number() const {
    if (kind != ExprKind::Number) return 0;
    double v;
    static_assert(sizeof v == sizeof a_ + sizeof b_);
    std::memcpy(&v, &a_, sizeof v);
    return v;
  }
  void set_number(double v) { std::memcpy(&a_, &v, sizeof v); }
  void set_operands(ExprId lhs, ExprId rhs = ExprId::None()) {
    a_ = lhs.index;
    b_ = rhs.index;
  }
  /// A Call's arguments: `count` ids from `Ast::args[first]`.
  void set_args(uint32_t first, uint32_t count) {
    a_ = static_cast<int32_t>(first);
    b_ = static_cast<int32_t>(count);
  }
  uint32_t args_first() const { return kind == ExprKind::Call ? static_cast<uint32_t>(a_) : 0; }
  uint32_t args_count() const { return kind == ExprKind::Call ? static_cast<uint32_t>(b_) : 0; }

 private:
  alignas(8) int32_t a_ = -1;  // Number: the value's low half; Unary/Binary: lhs; Call: first argument
  int32_t b_ = -1;             // Number: the value's high half; Binary: rhs; Call: argument count
};

/// A parenthesised list, e.g. `(0 -0.5*$b.w 0)` with three elements.
struct ParenList {
  SourceRange range;
  SmallVec<ExprId, 4> elems;
};

/// A comma in a list, tolerated and warned about (`Ast::commas_of`). Kept apart from the
/// lists: few lists have one, and a large document has tens of thousands of lists.
struct ListComma {
  ListId list;
  SourceRange range;
};

enum class ItemKind : uint8_t { Word, List, Value, Block, Tcl, Include };

/// One element of a block body, or of the file's top level.
struct Item {
  ItemKind kind = ItemKind::Word;
  SourceRange range;
  std::string_view text;  // Word: the word; Tcl: the block text; Include: the path
  ExprId expr;            // Value
  ListId list;            // List
  StmtId block;           // Block
};

/// A block statement, e.g. `point p (1 2 3) endpoint`.
/// How the end of a single-line NOME 2016 statement was found (frontend/parse: statements
/// that end at the end of their line, compat.md §B2).
enum class CloseRepair : uint8_t {
  None,      // closed by its own end keyword as written (or not closed: a syntax error)
  Replaced,  // a wrong or misspelt end keyword ending its line was taken as its end
  Inserted,  // no end keyword: the statement ends at the end of its line (close_kw is empty there)
};

struct Stmt {
  std::string_view keyword;  // the opening keyword as written, e.g. `funnel` (views the source)
  std::string_view close_text;
  SourceRange range;
  SourceRange open_kw;
  SourceRange close_kw;  // invalid when the parser had to recover without one
  BlockKind kind;
  CloseRepair close_repair = CloseRepair::None;
  // Two items inline: most statements are a name and one list or value (`point p (…)`,
  // `face f (…)`); longer ones keep theirs on the heap.
  SmallVec<Item, 2> items;
};

struct Ast {
  FileId file;
  std::vector<Item> top;  // Block, Tcl, Include, or stray Word/List/Value items
  std::vector<Stmt> stmts;
  std::vector<Expr> exprs;
  std::vector<ExprId> args;  // calls' arguments, each call's contiguous (Expr::args_first)
  std::vector<ParenList> lists;
  std::vector<ListComma> commas;  // ordered by list, then by position

  const Stmt& stmt(StmtId id) const { return stmts[id.index]; }
  const Expr& expr(ExprId id) const { return exprs[id.index]; }
  const ParenList& list(ListId id) const { return lists[id.index]; }
  /// A call's arguments (empty for other kinds).
  std::span<const ExprId> args_of(const Expr& e) const { return {args.data() + e.args_first(), e.args_count()}; }
  /// The commas written in a list (usually none).
  std::span<const ListComma> commas_of(ListId id) const {
    auto [lo, hi] = std::equal_range(commas.begin(), commas.end(), ListComma{id, {}},
                                     [](const ListComma& a, const ListComma& b) { return a.list.index < b.list.index; });
    return {commas.data() + (lo - commas.begin()), static_cast<size_t>(hi - lo)};
  }
};

}  // namespace nomec::ast
