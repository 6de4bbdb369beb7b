// AST: the syntax of one file with exact ranges, independent of ANTLR. A block statement
// keeps its body as an ordered list of items (words, lists, values, nested blocks); the
// checker gives the items meaning per block kind. IDs index the arrays of `Ast`.
#pragma once

#include <cstdint>
#include <optional>
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
struct Expr {
  ExprKind kind = ExprKind::Error;
  char op = 0;
  bool in_braces = false;      // written as `{expr …}` or `{…}`
  bool parenthesized = false;  // written as `( … )`; the range is inside the parentheses
  SourceRange range;
  std::string_view text;  // name, reference, raw text (views the source)
  double number = 0;
  ExprId lhs;  // unary operand or binary left
  ExprId rhs;
  SmallVec<ExprId, 2> args;  // call arguments
};

/// A parenthesised list, e.g. `(0 -0.5*$b.w 0)` with three elements.
struct ParenList {
  SourceRange range;
  SmallVec<ExprId, 4> elems;
  SmallVec<SourceRange, 1> commas;  // tolerated, warned about
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
  SmallVec<Item, 4> items;
};

struct Ast {
  FileId file;
  std::vector<Item> top;  // Block, Tcl, Include, or stray Word/List/Value items
  std::vector<Stmt> stmts;
  std::vector<Expr> exprs;
  std::vector<ParenList> lists;

  const Stmt& stmt(StmtId id) const { return stmts[id.index]; }
  const Expr& expr(ExprId id) const { return exprs[id.index]; }
  const ParenList& list(ListId id) const { return lists[id.index]; }
};

}  // namespace nomec::ast
