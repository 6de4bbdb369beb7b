// Lowering expressions from the syntax tree into the IR (see handlers.h): names become
// sliders, constants or a function's variables, calls are checked against the function
// table, and each value is evaluated once so a division by zero is reported where it is
// written. The recursion is bounded: an expression nesting more than a thousand operations
// deep is refused with one `NestingTooDeep` error, and its deeper operations are not visited.
#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include "frontend/check/handlers.h"
#include "frontend/parse/parse.h"

namespace nomec::check {

namespace {

// Expressions deeper than this (e.g. `1+1+…+1` with thousands of terms) are refused, so
// evaluation, printing and the backend never see them.
constexpr int kMaxExprDepth = 1000;

// What names mean where an expression is lowered.
struct Scope {
  bool constant = false;                        // slider values: no slider references
  std::span<const std::string_view> variables;  // a function's variables (`u`, `v` …)
  FunctionOrigin origin = {};                   // for a function text: the constants NOME3 knew
};

ir::ExprId add(Context& c, ir::Expr e) { return c.module().add_expr(std::move(e)); }

ir::ExprId param_expr(Context& c, ir::NodeId p, SourceRange r) {
  ir::Expr e;
  e.kind = ir::ExprKind::Param;
  e.param = p;
  e.range = r;
  return add(c, std::move(e));
}

ir::ExprId constant_expr(Context& c, double v, SourceRange r) {
  ir::Expr e;
  e.kind = ir::ExprKind::Const;
  e.value = v;
  e.range = r;
  return add(c, std::move(e));
}

std::string tcl_var_hint(const Context& c, std::string_view name) {
  for (const std::string& suf : c.tcl_suffixes) {
    if (name.size() > suf.size() && name.substr(name.size() - suf.size()) == suf) {
      return "a slider made by `CreateScale` inside a Tcl proc";
    }
  }
  if (c.tcl_vars.contains(std::string(name))) return "a Tcl variable set in a `tclinit` block";
  return "";
}

std::vector<std::string> slider_names(const Context& c, bool dotted_style) {
  std::vector<std::string> all;
  all.reserve(c.params.size());
  for (const auto& [k, v] : c.params) all.push_back(k);
  std::sort(all.begin(), all.end());  // "did you mean" prefers the first best match
  if (!dotted_style) {
    for (std::string& shown : all) std::replace(shown.begin(), shown.end(), '.', '_');
  }
  return all;
}

// NOME3 evaluated function texts with exprtk (generators-original.md §11.2): it has no `e`,
// and the cartesian and parametric surfaces' symbol tables had no `pi` either, so NOME3
// made no surface from such a text. nomec reads them as the constants; a warning says the
// original would not have.
void warn_unknown_constant(Context& c, std::string_view name, SourceRange at, const FunctionOrigin& origin) {
  if (origin.generator.empty()) return;
  if (name == "pi" && origin.has_pi) return;
  c.diags()
      .emit(DiagKind::ConstantUnknownToOriginal, at,
            name == "pi" ? fmt::format("`pi` is not defined in NOME3's `{}` functions, so NOME3 made no surface from "
                                       "this text; nomec reads it as π",
                                       origin.generator)
                         : fmt::format("`e` is not a constant in NOME3's functions (its expression library has none), "
                                       "so NOME3 made no surface from this text; nomec reads it as 2.71828…"))
      .fixit(at, name == "pi" ? "3.141592653589793" : "2.718281828459045", "write the number, which NOME3 reads too");
}

// A name or `$` reference: a constant, a function variable, a built-in, or a slider.
ir::ExprId lower_name(Context& c, const ast::Expr& x, const Scope& scope) {
  const bool dollar = x.kind == ast::ExprKind::DollarRef;
  const std::string_view name = dollar ? x.text.substr(1) : x.text;
  if (!dollar) {
    for (size_t i = 0; i < scope.variables.size(); ++i) {
      if (scope.variables[i] == name) {
        ir::Expr e;
        e.kind = ir::ExprKind::Variable;
        e.variable = static_cast<uint8_t>(i);
        e.name = scope.variables[i];
        e.range = x.range;
        return add(c, std::move(e));
      }
    }
    if (name == "pi" || name == "e") {
      warn_unknown_constant(c, name, x.range, scope.origin);
      return constant_expr(c, name == "pi" ? M_PI : M_E, x.range);
    }
  }
  if (dollar && name == "SLF_PI") return constant_expr(c, M_PI, x.range);
  if (dollar && (name == "time" || name == "frame")) {
    ir::Expr e;
    e.kind = ir::ExprKind::Builtin;
    e.name = name == "time" ? std::string_view("time") : std::string_view("frame");
    e.range = x.range;
    return add(c, std::move(e));
  }
  if (ir::NodeId p = lookup_param_text(c, name); p.is_valid()) {
    if (scope.constant) {
      c.diags().emit(DiagKind::NotAConstant, x.range,
                     fmt::format("slider values must be constant, but this refers to `{}`", c.module().node(p).name));
      return error_expr(c, x.range);
    }
    return param_expr(c, p, x.range);
  }
  if (c.dialect() == Dialect::Slide && dollar && c.tcl_available) {
    // A Tcl global: its value after `tclinit` (slide.md §6).
    if (std::optional<double> v = tcl_number(c, name, x.range)) return constant_expr(c, *v, x.range);
    if (c.first_tcl_report(fmt::format("${}", name))) {
      c.diags().emit(DiagKind::TclDefinedName, x.range,
                     fmt::format("`${}` is not a slider, and the scene's Tcl code does not set it to a number", name));
    }
    return error_expr(c, x.range);
  }
  if (c.dialect() == Dialect::Slide && dollar) {
    std::string why = tcl_var_hint(c, name);
    if (c.first_tcl_report(fmt::format("${}", name))) {
      c.diags().emit(DiagKind::TclDefinedName, x.range,
                     fmt::format("`${}` is {}; nomec does not evaluate Tcl yet, so values that use it are not checked yet",
                                 name, why.empty() ? "not a slider of this file; it may be defined by Tcl code" : why));
    }
    return error_expr(c, x.range);
  }
  if (!dollar && !scope.variables.empty()) {
    std::vector<std::string> candidates(scope.variables.begin(), scope.variables.end());
    candidates.emplace_back("pi");
    std::string hint = closest_match(name, candidates);
    std::vector<std::string> shown;
    for (std::string_view v : scope.variables) shown.push_back(fmt::format("`{}`", v));
    auto d = c.diags().emit(DiagKind::UnknownName, x.range,
                            fmt::format("unknown name `{}` in the function; its variables are {}{}", name,
                                        fmt::join(shown, ", "), hint.empty() ? "" : fmt::format("; did you mean `{}`?", hint)));
    if (!hint.empty()) d.fixit(x.range, hint, fmt::format("replace with `{}`", hint));
    return error_expr(c, x.range);
  }
  const bool dotted_style = name.find('.') != std::string::npos || c.dialect() == Dialect::Nome3;
  std::string hint = closest_match(name, slider_names(c, dotted_style));
  if (!dollar) {
    c.diags().emit(DiagKind::ExpectedNumber, x.range,
                   fmt::format("`{}` is not a number or a slider{}", name, hint.empty() ? "" : fmt::format("; did you mean `${}`?", hint)));
    return error_expr(c, x.range);
  }
  auto d = c.diags().emit(DiagKind::UnknownParameter, x.range,
                          fmt::format("unknown slider `${}`{}", name, hint.empty() ? "" : fmt::format("; did you mean `${}`?", hint)));
  if (!hint.empty()) d.fixit(x.range, "$" + hint, fmt::format("replace with `${}`", hint));
  return error_expr(c, x.range);
}

// An expression without operands (or one refused as a whole).
ir::ExprId lower_leaf(Context& c, const ast::Expr& x, const Scope& scope) {
  switch (x.kind) {
    case ast::ExprKind::Number:
      if (!std::isfinite(x.number())) {
        c.diags().emit(DiagKind::NumberTooLarge, x.range,
                       fmt::format("the number `{}` is too large: numbers stop near 1.8e308", Context::clip(x.text)));
        return error_expr(c, x.range);
      }
      return constant_expr(c, x.number(), x.range);
    case ast::ExprKind::DollarRef:
    case ast::ExprKind::Name:
      return lower_name(c, x, scope);
    case ast::ExprKind::TclArrayRef:
      if (c.dialect() == Dialect::Slide && c.tcl_available) {
        // `$oSubdivision(type)`: a slider bound to the element, or the element's value.
        std::string_view t = x.text.substr(1);
        const size_t open = t.find('(');
        const std::string arr(t.substr(0, open)), key(t.substr(open + 1, t.size() - open - 2));
        if (auto it = c.params.find(arr + "." + key); it != c.params.end()) return param_expr(c, it->second, x.range);
        if (std::optional<double> v = tcl_number(c, t, x.range)) return constant_expr(c, *v, x.range);
        if (c.first_tcl_report(std::string(x.text))) {
          c.diags().emit(DiagKind::TclDefinedName, x.range,
                         fmt::format("`{}` is not set to a number by the scene's Tcl code", x.text));
        }
        return error_expr(c, x.range);
      }
      if (c.dialect() == Dialect::Slide) {
        if (c.first_tcl_report(std::string(x.text))) {
          c.diags().emit(DiagKind::TclDefinedName, x.range,
                         fmt::format("`{}` is an element of a Tcl array made by a `slideui` object in `tclinit`; nomec does "
                                     "not evaluate Tcl yet, so values that use it are not checked yet",
                                     x.text));
        }
        return error_expr(c, x.range);
      }
      c.diags().emit(DiagKind::UnknownParameter, x.range,
                     fmt::format("`{}` is a Tcl array element, which only SLIDE files can use", x.text));
      return error_expr(c, x.range);
    case ast::ExprKind::Raw:
      if (c.dialect() == Dialect::Slide && x.in_braces) {
        if (!c.options().run_tcl) return error_expr(c, x.range);
        c.diags().emit(DiagKind::TclDefinedName, x.range,
                       fmt::format("this value is a Tcl script (`{}`); nomec does not evaluate Tcl yet, so values that "
                                   "use it are not checked yet",
                                   Context::clip(x.text)));
        return error_expr(c, x.range);
      }
      c.diags().emit(DiagKind::ExpectedNumber, x.range, fmt::format("expected a number, found raw text `{}`", Context::clip(x.text)));
      return error_expr(c, x.range);
    case ast::ExprKind::String:
      c.diags().emit(DiagKind::ExpectedNumber, x.range, fmt::format("expected a number, found the string {}", x.text));
      return error_expr(c, x.range);
    case ast::ExprKind::Error:
    case ast::ExprKind::Unary:
    case ast::ExprKind::Binary:
    case ast::ExprKind::Call:
      break;
  }
  return error_expr(c, x.range);
}

// NOME3 applied `-` before `^`: warn where `-a^b` reads differently.
void warn_unary_minus_power(Context& c, const ast::Ast& a, const ast::Expr& x, ir::ExprId unary, ir::ExprId power) {
  const ast::Expr& operand = a.expr(x.lhs());
  ir::EvalResult v = ir::evaluate(c.module(), unary);
  if (!v.ok) return;
  const ir::Expr& pow = c.module().expr(power);
  ir::EvalResult b = ir::evaluate(c.module(), pow.lhs()), p = ir::evaluate(c.module(), pow.rhs());
  double nome3 = b.ok && p.ok ? std::pow(-b.value, p.value) : 0;
  c.diags()
      .emit(DiagKind::UnaryMinusPower, x.range,
            fmt::format("`-` applies after `^` here, giving {}; NOME3 applied it first, giving {}", v.value, nome3))
      .fixit(x.range, fmt::format("-({})", c.sources().text(operand.range)), "add parentheses to keep this meaning");
}

// A `^` written without parentheses or braces around it.
bool is_bare_power(const ast::Expr& x) {
  return x.kind == ast::ExprKind::Binary && x.op == '^' && !x.parenthesized && !x.in_braces;
}

ir::ExprId power_node(Context& c, ir::ExprId base, ir::ExprId exponent, SourceRange r) {
  ir::Expr e;
  e.kind = ir::ExprKind::Binary;
  e.op = '^';
  e.operands[0] = base;
  e.operands[1] = exponent;
  e.range = r;
  return add(c, std::move(e));
}

// `(… (b^c)^…)^z` (the lowered right operand, left-associative, `levels` powers deep) with
// `a` grafted in as the innermost base: `((a^b)^c)^…`.
ir::ExprId graft_base(Context& c, ir::ExprId a, ir::ExprId chain, int levels, SourceRange r) {
  const ir::Expr node = c.module().expr(chain);
  if (levels == 0 || node.kind != ir::ExprKind::Binary || node.op != '^') return power_node(c, a, chain, r);
  return power_node(c, graft_base(c, a, node.lhs(), levels - 1, r), node.rhs(), node.range);
}

// `a^b^c` in a NOME3 file: NOME3's grammar made `^` left-associative (compat.md §C2), so it
// means `(a^b)^c`, which is what the file's author saw. Build that, and warn where the
// usual reading `a^(b^c)` (every other dialect's) gives another value. `warn` is false for
// the inner links of a longer chain (the outermost power warns once for all of it).
ir::ExprId lower_nome3_power_chain(Context& c, const ast::Ast& a, const ast::Expr& x, ir::ExprId base, ir::ExprId rhs,
                                   bool warn) {
  // The operands as written (`a`, `b`, `c`, …); the right operand holds `levels` bare powers
  // and was lowered left-associative already.
  std::vector<const ast::Expr*> written{&a.expr(x.lhs())};
  int levels = 0;
  const ast::Expr* r = &a.expr(x.rhs());
  for (; is_bare_power(*r); r = &a.expr(r->rhs())) {
    ++levels;
    written.push_back(&a.expr(r->lhs()));
  }
  written.push_back(r);
  const ir::ExprId out = graft_base(c, base, rhs, levels, x.range);
  if (!warn) return out;
  // The operands' values, from the lowered chain: ((a^b)^c)^… walked down its left side.
  std::vector<double> values(written.size());
  ir::ExprId k = out;
  for (size_t i = written.size() - 1; i > 0; --i) {
    if (c.module().expr(k).kind != ir::ExprKind::Binary) return out;
    ir::EvalResult v = ir::evaluate(c.module(), c.module().expr(k).rhs());
    if (!v.ok) return out;
    values[i] = v.value;
    k = c.module().expr(k).lhs();
  }
  ir::EvalResult first = ir::evaluate(c.module(), k), nome3 = ir::evaluate(c.module(), out);
  if (!first.ok || !nome3.ok) return out;
  values[0] = first.value;
  double usual = values.back();
  for (size_t i = values.size() - 1; i-- > 0;) usual = std::pow(values[i], usual);
  if (usual == nome3.value || (std::isnan(usual) && std::isnan(nome3.value))) return out;
  auto text_of = [&](const ast::Expr* e) {
    std::string t(c.sources().text(e->range));
    return e->parenthesized || e->in_braces || e->kind == ast::ExprKind::Unary || e->kind == ast::ExprKind::Binary
               ? "(" + t + ")"
               : t;
  };
  std::string grouped = text_of(written[0]);
  for (size_t i = 1; i < written.size(); ++i) {
    grouped = (i == 1 ? grouped : "(" + grouped + ")") + "^" + text_of(written[i]);
  }
  c.diags()
      .emit(DiagKind::PowerAssociativity, x.range,
            fmt::format("NOME3 grouped `^` from the left: this is `{}` = {}; read from the right, as in the other "
                        "dialects and in mathematics, it would be {}",
                        grouped, nome3.value, usual))
      .fixit(x.range, grouped, "add parentheses to make the grouping explicit");
  return out;
}

// An operation whose operands are lowered (`kids`, in order).
// `chain_link` is true when `x` is the bare right operand of a `^` (a link of a longer chain);
// `left_power` when `^` groups from the left (NOME3 expressions outside function texts).
ir::ExprId lower_operation(Context& c, const ast::Ast& a, const ast::Expr& x, std::span<const ir::ExprId> kids,
                           bool chain_link, bool left_power) {
  ir::Expr e;
  e.range = x.range;
  switch (x.kind) {
    case ast::ExprKind::Unary: {
      e.kind = ir::ExprKind::Unary;
      e.op = x.op;
      e.operands[0] = kids[0];
      ir::ExprId id = add(c, std::move(e));
      const ast::Expr& operand = a.expr(x.lhs());
      // Only a bare `^` operand reads differently: `-(a^b)` is one operand in NOME3 too.
      if (c.dialect() == Dialect::Nome3 && x.op == '-' && is_bare_power(operand) &&
          c.module().expr(kids[0]).kind == ir::ExprKind::Binary) {
        warn_unary_minus_power(c, a, x, id, kids[0]);
      }
      return id;
    }
    case ast::ExprKind::Binary: {
      if (left_power && x.op == '^' && is_bare_power(a.expr(x.rhs()))) {
        return lower_nome3_power_chain(c, a, x, kids[0], kids[1], !chain_link);
      }
      e.kind = ir::ExprKind::Binary;
      e.op = x.op;
      e.operands[0] = kids[0];
      e.operands[1] = kids[1];
      return add(c, std::move(e));
    }
    case ast::ExprKind::Call: {
      std::optional<ir::Func> f = ir::func_by_name(x.text);
      if (!f) {
        std::vector<std::string> names(ir::func_names().begin(), ir::func_names().end());
        std::string hint = closest_match(x.text, names);
        auto d = c.diags().emit(DiagKind::UnknownFunction, x.range,
                                fmt::format("unknown function `{}`{}", x.text, hint.empty() ? "" : fmt::format("; did you mean `{}`?", hint)));
        if (!hint.empty()) {
          d.fixit(SourceRange{x.range.file, x.range.begin, static_cast<uint32_t>(x.range.begin + x.text.size())}, hint,
                  fmt::format("replace with `{}`", hint));
        }
        return error_expr(c, x.range);
      }
      if (ir::func_is_tcl_only(*f) && c.dialect() != Dialect::Slide) {
        c.diags().emit(DiagKind::UnknownFunction, x.range,
                       fmt::format("`{}` is a function of Tcl's `expr`, known in SLIDE (`.slf`) files only; this file is "
                                   "checked as `{}`",
                                   x.text, dialect_name(c.dialect())));
        return error_expr(c, x.range);
      }
      const int arity = ir::func_arity(*f);
      if ((arity >= 0 && static_cast<int>(kids.size()) != arity) || (arity < 0 && kids.empty())) {
        c.diags().emit(DiagKind::FunctionArity, x.range,
                       fmt::format("`{}` takes {} argument{}, got {}", x.text,
                                   arity < 0 ? std::string("at least 1") : std::to_string(arity), arity == 1 ? "" : "s",
                                   kids.size()));
        return error_expr(c, x.range);
      }
      return c.module().add_call(*f, kids, x.range);
    }
    default:
      return error_expr(c, x.range);
  }
}

// How many operands an operation in the syntax tree has, and its `i`th.
uint32_t operand_count(const ast::Expr& x) {
  switch (x.kind) {
    case ast::ExprKind::Unary: return 1;
    case ast::ExprKind::Binary: return 2;
    case ast::ExprKind::Call: return x.args_count();
    default: return 0;
  }
}
ast::ExprId operand_of(const ast::Ast& a, const ast::Expr& x, uint32_t i) {
  if (x.kind == ast::ExprKind::Call) return a.args_of(x)[i];
  return i == 0 ? x.lhs() : x.rhs();
}

bool is_operation(const ast::Expr& x) {
  return x.kind == ast::ExprKind::Unary || x.kind == ast::ExprKind::Binary || x.kind == ast::ExprKind::Call;
}

// Post-order, recursively: the operands in written order, then the operation. The depth is
// bounded (a node deeper than kMaxExprDepth becomes an error without its operands), so the
// recursion is too. `parent` is the syntax operation `id` is an operand of, if any.
ir::ExprId lower_node(Context& c, const ast::Ast& a, ast::ExprId id, ast::ExprId parent, int depth, const Scope& scope,
                      bool left_power) {
  const ast::Expr& x = a.expr(id);
  if (depth > kMaxExprDepth) {
    if (!c.reported_deep_expr) {
      c.reported_deep_expr = true;
      c.diags().emit(DiagKind::NestingTooDeep, x.range,
                     fmt::format("expression nests more than {} operations deep; split it into sliders or points", kMaxExprDepth));
    }
    return error_expr(c, x.range);
  }
  if (!is_operation(x)) return lower_leaf(c, x, scope);
  const uint32_t kids = operand_count(x);
  // Inline room for an operation's operands (a call may have more: they go to the heap).
  SmallVec<ir::ExprId, 4> lowered;
  for (uint32_t i = 0; i < kids; ++i) {
    lowered.push_back(lower_node(c, a, operand_of(a, x, i), id, depth + 1, scope, left_power));
  }
  bool chain_link = false;
  if (parent.is_valid()) {
    const ast::Expr& p = a.expr(parent);
    chain_link = is_bare_power(x) && is_bare_power(p) && p.rhs() == id;
  }
  return lower_operation(c, a, x, std::span<const ir::ExprId>(lowered.data(), lowered.size()), chain_link, left_power);
}

ir::ExprId lower_tree(Context& c, const ast::Ast& a, ast::ExprId root, const Scope& scope) {
  // Most values are one number or name: lowered without the recursion's set-up (the same
  // result: a leaf at depth 0 is lowered by lower_leaf there too).
  if (const ast::Expr& x = a.expr(root); !is_operation(x)) return lower_leaf(c, x, scope);
  // NOME3's grammar grouped `^` from the left (compat.md §C2). A function text (`funcX [ … ]`,
  // evaluated at variables) was not read by that grammar and keeps the usual grouping.
  const bool left_power = c.dialect() == Dialect::Nome3 && scope.variables.empty();
  return lower_node(c, a, root, ast::ExprId::None(), 0, scope, left_power);
}

// A SLIDE value in braces (`{expr $r*2}`, `{if {…} {expr 1} else {expr 0}}`, `%{ … }%`),
// evaluated by Tcl (slide.md §1, §6). Tcl's value is the value. When the expression is one
// nomec can also evaluate itself with the same result, that expression is kept, so a slider
// change re-evaluates it (the dependency graph sees its sliders); otherwise Tcl evaluates it
// again when a slider it depends on moves (tcl_live.cpp).
ir::ExprId lower_tcl_value(Context& c, const ast::Ast& a, ast::ExprId id, const Scope& scope);

bool is_tcl_raw(const ast::Expr& x) {
  return x.kind == ast::ExprKind::Raw && (x.in_braces || x.text.rfind("%{", 0) == 0);
}

ir::ExprId lower_checked(Context& c, const ast::Ast& a, ast::ExprId id, const Scope& scope) {
  if (scope.variables.empty() && c.tcl_available && (a.expr(id).in_braces || is_tcl_raw(a.expr(id)))) {
    return lower_tcl_value(c, a, id, scope);
  }
  const size_t first = c.module().exprs.size();
  ir::ExprId out = lower_tree(c, a, id, scope);
  if (!scope.variables.empty()) return out;  // a function is evaluated where it is used
  // Evaluated only if it may fail: the expressions lowered for this value are the ones
  // added since `first` (most values, `$r * cos(2 * pi / 8)`, cannot fail, nor overflow
  // with the numbers they hold now).
  const std::vector<ir::Expr>& added = c.module().exprs;
  if (!ir::may_fail_now(c.module(), std::span<const ir::Expr>(added).subspan(first))) return out;
  ir::EvalResult r = ir::evaluate(c.module(), out);
  if (!r.ok && !r.problem.empty()) {
    c.diags().emit(DiagKind::ExpressionDomain, r.where.is_valid() ? r.where : a.expr(id).range, r.problem);
    return error_expr(c, a.expr(id).range);
  }
  return out;
}

ir::ExprId lower_tcl_value(Context& c, const ast::Ast& a, ast::ExprId id, const Scope& scope) {
  const ast::Expr& x = a.expr(id);
  const bool raw = x.kind == ast::ExprKind::Raw;
  std::string script;
  if (raw) {
    std::string_view t = x.text;
    const size_t cut = t.rfind("%{", 0) == 0 ? 2 : 1;
    script = std::string(t.size() >= 2 * cut ? t.substr(cut, t.size() - 2 * cut) : t);
  } else {
    // The text inside the braces around the expression (its range may exclude parentheses).
    // The nearest `{` before the expression whose matching `}` comes after it (braces
    // inside the expression, `{expr {$r} * 2}`, are skipped).
    std::string_view file = c.sources().text(x.range.file);
    size_t open = x.range.begin, close = file.size();
    while (open > 0) {
      size_t depth = 0;
      while (open > 0) {
        --open;
        if (file[open] == '}') ++depth;
        if (file[open] == '{' && depth-- == 0) break;
      }
      if (file[open] != '{') break;
      close = open + 1;
      for (size_t d = 0; close < file.size(); ++close) {
        if (file[close] == '{') ++d;
        if (file[close] == '}' && d-- == 0) break;
      }
      if (close >= x.range.end) break;
    }
    std::string_view inner = file[open] == '{' && close < file.size() ? file.substr(open + 1, close - open - 1)
                                                                       : c.sources().text(x.range);
    size_t first = inner.find_first_not_of(" \t\r\n");
    const bool has_expr = first != std::string_view::npos && inner.substr(first, 4) == "expr" &&
                          (inner.size() == first + 4 || std::isspace(static_cast<unsigned char>(inner[first + 4])));
    // `{exrp …}`: the parser read (and reported) a misspelt `expr`; Tcl is given `expr`.
    size_t word_end = first == std::string_view::npos ? first : inner.find_first_of(" \t\r\n", first);
    const bool misspelt_expr = !has_expr && first != std::string_view::npos && word_end != std::string_view::npos &&
                               is_typo_of(inner.substr(first, word_end - first), "expr");
    if (misspelt_expr) {
      script = "expr" + std::string(inner.substr(word_end));
    } else {
      script = has_expr ? std::string(inner) : fmt::format("expr {{{}}}", inner);
    }
  }
  std::optional<TclValue> v = tcl_value(c, script, x.range);
  if (!v || !v->ok) return error_expr(c, x.range);
  if (!raw && !reads_tcl_update(c, script, *v)) {
    // nomec's own reading of the expression, checked quietly against Tcl's value.
    DiagnosticEngine scratch;
    std::swap(scratch, c.diags());
    ir::ExprId out = lower_tree(c, a, id, scope);
    std::swap(scratch, c.diags());
    ir::EvalResult r = ir::evaluate(c.module(), out);
    if (r.ok && std::fabs(r.value - v->value) <= 1e-9 * std::max(1.0, std::fabs(v->value))) return out;
  }
  // `%{ … }%` is evaluated once in SLIDE too; any other script follows its sliders.
  if (raw && x.text.rfind("%{", 0) == 0) return constant_expr(c, v->value, x.range);
  return live_tcl_value(c, std::move(script), *v, x.range);
}

}  // namespace

ir::ExprId error_expr(Context& c, SourceRange r) {
  ir::Expr e;
  e.kind = ir::ExprKind::Error;
  e.range = r;
  return add(c, std::move(e));
}

ir::ExprId lower_expr(Context& c, const ast::Ast& a, ast::ExprId id, bool constant) {
  return lower_checked(c, a, id, Scope{constant, {}});
}

ir::ExprId scalar_of_item(Context& c, const ast::Ast& a, const ast::Item& it, bool constant) {
  switch (it.kind) {
    case ItemKind::Value:
      return lower_expr(c, a, it.expr, constant);
    case ItemKind::List: {
      const ast::ParenList& l = a.list(it.list);
      if (l.elems.size() == 1) return lower_expr(c, a, l.elems[0], constant);
      c.diags().emit(DiagKind::ListArity, l.range,
                     fmt::format("expected one value, got a list of {}{}", l.elems.size(), c.split_text(a, l)));
      return error_expr(c, l.range);
    }
    case ItemKind::Word: {
      // A bare `bank.param` word as a value.
      ir::NodeId p = lookup_param_text(c, it.text);
      if (p.is_valid() && !constant) return param_expr(c, p, it.range);
      c.diags().emit(DiagKind::ExpectedNumber, it.range, fmt::format("expected a number, found `{}`", it.text));
      return error_expr(c, it.range);
    }
    default:
      return error_expr(c, it.range);
  }
}

ir::ExprId lower_function(Context& c, const ast::Ast& a, ast::ExprId raw, std::span<const std::string_view> vars,
                          FunctionOrigin origin) {
  const ast::Expr& x = a.expr(raw);
  // The function's own syntax tree is needed only while it is lowered: the IR's
  // expressions keep nothing of it (their texts view the file's text).
  ast::Ast fn;
  fn.file = x.range.file;
  ast::ExprId root = parse_function_text(c.sources().text(x.range.file), x.range.file, x.range, fn, c.diags());
  return lower_checked(c, fn, root, Scope{false, vars, origin});
}

}  // namespace nomec::check
