// Text dumps of an AST (every node, id, range and text) and of diagnostics (in emission
// order, with notes and fix-its), and of a whole parse with both, for the differential tests
// that compare two parses (tests/incremental, tests/unit/*_diff_test.cpp and others).
#pragma once

#include <fmt/format.h>

#include <string>

#include "frontend/ast/ast.h"
#include "frontend/diagnostics/diagnostic.h"
#include "frontend/parse/parse.h"

namespace nomec::testing_dump {

inline std::string dump_range(nomec::SourceRange r) {
  return fmt::format("{}:{}-{}", r.file.index, r.begin, r.end);
}

template <typename Items>
inline std::string dump_items(const Items& items) {
  std::string s;
  for (const auto& i : items) {
    s += fmt::format(" [{} {} '{}' e{} l{} s{}]", static_cast<int>(i.kind), dump_range(i.range),
                     i.text, i.expr.index, i.list.index, i.block.index);
  }
  return s;
}

inline std::string dump_ast(const nomec::ast::Ast& a) {
  std::string s = fmt::format("file {}\ntop:{}\n", a.file.index, dump_items(a.top));
  for (size_t k = 0; k < a.stmts.size(); ++k) {
    const auto& st = a.stmts[k];
    s += fmt::format("s{} kind {} '{}' {} open {} close {} '{}' repair {}:{}\n", k, static_cast<int>(st.kind),
                     st.keyword, dump_range(st.range), dump_range(st.open_kw), dump_range(st.close_kw),
                     st.close_text, static_cast<int>(st.close_repair), dump_items(st.items));
  }
  for (size_t k = 0; k < a.exprs.size(); ++k) {
    const auto& e = a.exprs[k];
    s += fmt::format("e{} {} '{}' {} {} {} '{}' {} l{} r{}", k, static_cast<int>(e.kind),
                     e.op == 0 ? ' ' : e.op, e.in_braces, e.parenthesized, dump_range(e.range), e.text, e.number(),
                     e.lhs().index, e.rhs().index);
    for (auto arg : a.args_of(e)) s += fmt::format(" a{}", arg.index);
    s += "\n";
  }
  for (size_t k = 0; k < a.lists.size(); ++k) {
    const auto& l = a.lists[k];
    s += fmt::format("l{} {}", k, dump_range(l.range));
    for (auto e : l.elems) s += fmt::format(" e{}", e.index);
    for (const auto& c : a.commas_of(nomec::ast::ListId{static_cast<int32_t>(k)})) s += " ," + dump_range(c.range);
    s += "\n";
  }
  return s;
}

inline std::string dump_diags(const nomec::DiagnosticEngine& diags) {
  std::string s;
  for (const auto& d : diags.diagnostics()) {
    s += fmt::format("{} {} {}\n", nomec::diag_kind_name(d.kind), dump_range(d.range), d.message);
    for (const auto& n : d.notes) s += fmt::format("  note {} {}\n", dump_range(n.range), n.message);
    for (const auto& f : d.fixits) {
      s += fmt::format("  fixit {} '{}' {}\n", dump_range(f.range), f.replacement, f.description);
    }
  }
  return s;
}

/// `text` parsed as a whole file (`parse_file` with `threads`): its AST's dump, `--`, its
/// diagnostics' dump. `clean`, when given, says whether the parse reported no error.
inline std::string parse_dump(const std::string& text, nomec::ParseThreads threads = nomec::ParseThreads::Automatic,
                              bool* clean = nullptr) {
  nomec::SourceManager sources;
  nomec::DiagnosticEngine diags;
  const nomec::FileId f = sources.add_file("doc.nome", text);
  const nomec::ast::Ast a = nomec::parse_file(sources, f, diags, threads);
  if (clean != nullptr) *clean = diags.error_count() == 0;
  return dump_ast(a) + "--\n" + dump_diags(diags);
}

}  // namespace nomec::testing_dump
