// Generator statements, driven by the generator catalogue (see handlers.h): the positional
// list of the dialect (arity, counts), the options of the generator, function texts lowered
// to expressions of their variables, and the catalogue's argument-domain rules on every
// value known at check time, so `--check` rejects what the backend would.
#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include "frontend/check/handlers.h"

namespace nomec::check {

namespace {

bool is_counted(ir::ArgType t) { return t == ir::ArgType::Count || t == ir::ArgType::Whole; }

// A count the original converted to a whole number by cutting off its fraction: in a
// NOME 2016 / NOME2 file one written as a plain number (`stoi`; an `{expr …}` count was
// rounded, compat.md D7); in a NOME3 file every count (`static_cast<int>`,
// generators-original.md §1). Only a value that is not whole (or not known now) is marked.
bool is_truncated_count(Context& c, const ast::Ast& a, ast::ExprId e, ir::ExprId lowered, ir::ArgType type) {
  if (c.dialect() == Dialect::Nome3) {
    if (type != ir::ArgType::Count) return false;
    ir::EvalResult v = ir::evaluate(c.module(), lowered);
    return !v.ok || v.value != std::trunc(v.value);
  }
  if (!is_nome_family(c.dialect())) return false;
  const ast::Expr* x = &a.expr(e);
  if (x->kind == ast::ExprKind::Unary && !x->in_braces) x = &a.expr(x->lhs());
  // A whole number reads the same either way: only a fraction is marked.
  return x->kind == ast::ExprKind::Number && !x->in_braces && x->number() != std::trunc(x->number());
}

void check_count(Context& c, ir::ExprId e, SourceRange r, std::string_view what, bool truncated = false) {
  ir::EvalResult v = ir::evaluate(c.module(), e);
  if (!v.ok || std::fabs(v.value - std::round(v.value)) <= 1e-9) return;
  if (truncated) {
    const double t = std::trunc(v.value);
    c.diags().emit(DiagKind::NonIntegerCount, r,
                   fmt::format("`{}` is a count but has the value {}; it will be truncated to {}{}", what, v.value, t,
                               t != std::round(v.value) ? fmt::format(", not rounded to {}", std::round(v.value)) : ""))
        .note(SourceRange{}, c.dialect() == Dialect::Nome3
                                 ? "NOME3 converted every count to a whole number by cutting off its fraction"
                                 : "NOME 2016 and NOME2 read a count written as a number by cutting off its fraction, "
                                   "and rounded only a count given as `{expr …}`");
    return;
  }
  c.diags().emit(DiagKind::NonIntegerCount, r,
                 fmt::format("`{}` is a count but has the value {}; it will be rounded to {}", what, v.value, std::round(v.value)));
}

// The value of each element of a positional list, where it is known now (scratch
// diagnostics: the list is lowered again, with its diagnostics, when it is read).
std::vector<std::optional<double>> list_values(Context& c, const ast::Ast& a, const ast::ParenList& list) {
  std::vector<std::optional<double>> out;
  DiagnosticEngine scratch;
  std::swap(scratch, c.diags());
  // The scratch expressions (and the names they record) are dropped again.
  ir::Module& m = c.module();
  const size_t exprs = m.exprs.size(), lists = m.expr_lists.size(), externals = m.externals.size();
  const size_t uses = c.name_uses != nullptr ? c.name_uses->size() : 0;
  for (ast::ExprId e : list.elems) {
    ir::EvalResult v = ir::evaluate(c.module(), lower_expr(c, a, e, false));
    out.push_back(v.ok ? std::optional<double>(v.value) : std::nullopt);
  }
  m.exprs.resize(exprs);
  m.expr_lists.resize(lists);
  m.externals.resize(externals);
  if (c.name_uses != nullptr) c.name_uses->resize(uses);
  std::swap(scratch, c.diags());
  return out;
}

// The text of each element of a list as written, with the braces of an `{expr …}` (an
// expression's range holds only what is inside them).
std::vector<std::string_view> element_texts(Context& c, const ast::Ast& a, const ast::ParenList& list) {
  std::vector<std::string_view> out;
  const std::string_view all = c.sources().text(list.range);  // `( … )`
  const uint32_t base = list.range.begin;
  for (ast::ExprId e : list.elems) {
    const ast::Expr& x = a.expr(e);
    if (x.range.file != list.range.file || x.range.begin < base || x.range.end > list.range.end) {
      out.push_back(c.sources().text(x.range));
      continue;
    }
    size_t from = x.range.begin - base, to = x.range.end - base;
    if (x.in_braces) {
      // Back over `expr` and spaces to `{`, forward over spaces to `}`.
      size_t f = from;
      while (f > 0 && all[f - 1] != '{' && all[f - 1] != '(') --f;
      size_t t = to;
      while (t < all.size() && (all[t] == ' ' || all[t] == '\t')) ++t;
      if (f > 0 && all[f - 1] == '{' && t < all.size() && all[t] == '}') {
        from = f - 1;
        to = t + 1;
      }
    }
    out.push_back(all.substr(from, to - from));
  }
  return out;
}

// Does reading the list in order `sig` make every count argument a valid count (a whole
// number ≥ 3)? nullopt when a count's value is not known now.
std::optional<bool> counts_valid(const ir::GeneratorInfo& info, const ir::Signature& sig,
                                 const std::vector<std::optional<double>>& values) {
  bool any = false;
  for (size_t i = 0; i < sig.args.size() && i < values.size(); ++i) {
    if (sig.args[i] == ir::kNoArg || info.args[sig.args[i]].type != ir::ArgType::Count) continue;
    if (!values[i]) return std::nullopt;
    any = true;
    if (std::fabs(*values[i] - std::round(*values[i])) > 1e-9 || *values[i] < 3) return false;
  }
  return any ? std::optional<bool>(true) : std::nullopt;
}

std::string reading_text(const ir::Signature& sig, const std::vector<std::optional<double>>& values) {
  std::vector<std::string> parts;
  for (size_t i = 0; i < sig.args.size() && i < values.size(); ++i) {
    parts.push_back(fmt::format("{} = {}", sig.names[i], values[i] ? ir::format_argument(*values[i]) : "?"));
  }
  return fmt::format("({}): {}", fmt::join(sig.names.begin(), sig.names.begin() + static_cast<ptrdiff_t>(sig.args.size()), " "),
                     fmt::join(parts, ", "));
}

// A generator statement being read: its node, its catalogue entry, its bindings so far.
struct GenReader {
  Context& c;
  const ast::Ast& a;
  const ast::Stmt& s;
  ir::NodeId id;
  const ir::GeneratorInfo& info;
  std::vector<ir::GenArgBinding> bindings;

  // The positional list; false when it has the wrong number of arguments.
  bool read_positional(const ir::Signature& sig, const ast::Item& list_item) {
    const ast::ParenList& list = a.list(list_item.list);
    if (sig.is_point_list) {
      ir::GenArgBinding b;
      b.arg = sig.args[0];
      b.refs = read_names(c, a, list_item, id, Ns::Point);
      b.range = list.range;
      bindings.push_back(b);
      if (info.kind == ir::GenKind::Convexhull && list.elems.size() < 4) {
        const std::string& name = c.module().node(id).name;
        c.diags()
            .emit(DiagKind::GeometryFailed, list.range,
                  fmt::format("`{}` `{}`: a convex hull needs at least 4 points (not all in one plane), got {}", s.keyword,
                              name.substr(name.rfind('.') + 1), list.elems.size()))
            .note(SourceRange{}, "the hull of fewer points has no inside; a flat polygon is a `face`");
      }
      return true;
    }
    c.check_commas(a, list_item.list);
    std::vector<ast::ExprId> values;
    read_flags(sig, list, values);
    const size_t n = values.size();
    const size_t want = sig.args.size();
    const size_t numbers = want + value_optional(sig);
    const bool ok = n == want || n == numbers;
    if (!ok) report_arity(sig, list, n);
    for (size_t i = 0; i < n; ++i) {
      const SourceRange r = a.expr(values[i]).range;
      SmallVec<ir::ExprId, 4> exprs;
      exprs.push_back(lower_expr(c, a, values[i], false));
      if (i >= numbers) continue;  // an extra argument: checked, reported above
      const ir::ArgIndex arg = i < want ? sig.args[i] : sig.optional[i - want];
      const std::string_view name = sig.names[i];
      ir::GenArgBinding b;
      if (arg != ir::kNoArg && is_counted(info.args[arg].type)) {
        b.is_truncated = is_truncated_count(c, a, values[i], exprs[0], info.args[arg].type);
        check_count(c, exprs[0], r, name, b.is_truncated);
      }
      b.arg = arg;
      b.value = c.add_operand(id, name, std::move(exprs), r);
      b.range = r;
      bindings.push_back(b);
    }
    return ok;
  }

  // The argument-order eras (compat.md A4): the list is read in the dialect's order
  // unless that makes a count argument invalid while `other` makes every count valid; then
  // it is read in `other` with a warning naming both readings and a fix-it that rewrites
  // the list in the dialect's order.
  const ir::Signature& choose_order(const ir::Signature& sig, const ir::Signature* other, const ast::Item& list_item) {
    const ast::ParenList& list = a.list(list_item.list);
    if (other == nullptr || sig.is_point_list || list.elems.size() != sig.args.size() ||
        other->args.size() != sig.args.size()) {
      return sig;
    }
    const std::vector<std::optional<double>> values = list_values(c, a, list);
    if (counts_valid(info, sig, values) != false || counts_valid(info, *other, values) != true) return sig;
    // The same values in the dialect's order, from their source text.
    const std::vector<std::string_view> written = element_texts(c, a, list);
    std::vector<std::string_view> texts;
    for (size_t i = 0; i < sig.args.size(); ++i) {
      for (size_t j = 0; j < other->args.size(); ++j) {
        if (other->args[j] == sig.args[i]) texts.push_back(written[j]);
      }
    }
    const std::string reordered = fmt::format("({})", fmt::join(texts, " "));
    const std::string era = other->era.empty() ? std::string("another era's") : fmt::format("the {}", other->era);
    const std::string& name = c.module().node(id).name;
    auto names = [](const ir::Signature& g) {
      return fmt::format("({})", fmt::join(g.names.begin(), g.names.begin() + static_cast<ptrdiff_t>(g.args.size()), " "));
    };
    auto d = c.diags().emit(DiagKind::ArgumentOrder, list.range,
                            fmt::format("the arguments of `{}` `{}` seem to be in {} order: as {} they give no valid "
                                        "count, as {} they do; reading them as {}",
                                        s.keyword, name.substr(name.rfind('.') + 1), era, names(sig), names(*other),
                                        names(*other)));
    d.note(SourceRange{}, fmt::format("the `{}` reading {}", dialect_name(c.dialect()), reading_text(sig, values)));
    d.note(SourceRange{}, fmt::format("the reading used {}", reading_text(*other, values)));
    if (texts.size() == sig.args.size()) d.fixit(list.range, reordered, fmt::format("write the list in the `{}` order", dialect_name(c.dialect())));
    return *other;
  }

  bool is_flag_arg(ir::ArgIndex arg) const { return arg != ir::kNoArg && info.args[arg].type == ir::ArgType::Flag; }

  // The optional arguments of a list that are numbers (the others are flag words).
  size_t value_optional(const ir::Signature& sig) const {
    size_t k = 0;
    for (ir::ArgIndex arg : sig.optional) k += is_flag_arg(arg) ? 0 : 1;
    return k;
  }

  // NOME3 writes a generator's flags inside its list, after the numbers, in any order
  // (`cylinder c (1 2 360 8 botcap topcap)`). Moves the values to `values` and binds each
  // flag word; a flag given twice is an error (NOME3: "Named argument is repeated").
  void read_flags(const ir::Signature& sig, const ast::ParenList& list, std::vector<ast::ExprId>& values) {
    std::vector<std::string_view> flag_names;
    for (size_t k = 0; k < sig.optional.size(); ++k) {
      if (is_flag_arg(sig.optional[k])) flag_names.push_back(sig.names[sig.args.size() + k]);
    }
    std::vector<std::pair<ir::ArgIndex, SourceRange>> seen;
    for (ast::ExprId e : list.elems) {
      const ast::Expr& x = a.expr(e);
      if (flag_names.empty() || x.kind != ast::ExprKind::Name || values.size() < sig.args.size()) {
        values.push_back(e);
        continue;
      }
      const auto it = std::find(flag_names.begin(), flag_names.end(), x.text);
      if (it == flag_names.end()) {
        std::string hint = closest_match(x.text, flag_names);
        if (hint.empty()) {
          values.push_back(e);  // perhaps a parameter: read as a number
          continue;
        }
        c.diags()
            .emit(DiagKind::UnknownArgument, x.range,
                  fmt::format("unknown flag `{}` for `{}`; did you mean `{}`?", x.text, s.keyword, hint))
            .fixit(x.range, hint, fmt::format("replace with `{}`", hint));
        continue;
      }
      const ir::ArgIndex arg = *info.arg_named(*it);
      const auto prev = std::find_if(seen.begin(), seen.end(), [&](const auto& p) { return p.first == arg; });
      if (prev != seen.end()) {
        c.diags()
            .emit(DiagKind::RepeatedArgument, x.range,
                  fmt::format("`{}` is given twice; NOME3 rejects a repeated named argument", x.text))
            .note(prev->second, "first given here")
            .fixit(x.range, "", fmt::format("remove this `{}`", x.text));
        continue;
      }
      seen.emplace_back(arg, x.range);
      ir::GenArgBinding b;
      b.arg = arg;
      b.is_flag = true;
      b.range = x.range;
      bindings.push_back(b);
    }
  }

  void report_arity(const ir::Signature& sig, const ast::ParenList& list, size_t n) {
    const size_t want = sig.args.size();
    std::vector<std::string_view> args(sig.names.begin(), sig.names.begin() + static_cast<ptrdiff_t>(want));
    std::vector<std::string_view> optional, flags;
    for (size_t k = 0; k < sig.optional.size(); ++k) {
      (is_flag_arg(sig.optional[k]) ? flags : optional).push_back(sig.names[want + k]);
    }
    std::string expect = optional.empty() ? fmt::format("{} arguments ({}", want, fmt::join(args, " "))
                                          : fmt::format("{} or {} arguments ({} [{}]", want, want + optional.size(),
                                                        fmt::join(args, " "), fmt::join(optional, " "));
    for (std::string_view f : flags) expect += fmt::format(" [{}]", f);
    expect += ")";
    auto d = c.diags().emit(DiagKind::ListArity, list.range,
                            fmt::format("`{}` takes {}, got {}{}", info.keyword, expect, n, c.split_text(a, list)));
    if (info.kind == ir::GenKind::Torus && n + 1 == want) {
      // nome3/olympictorus.nom: no NOME3 or JIPCAD torus took 6 arguments.
      d.note(SourceRange{}, "every known NOME3 and JIPCAD version of `torus` takes these 7 arguments; with one missing, "
                            "nomec cannot tell which it is");
    }
    if (info.kind == ir::GenKind::Funnel) {
      d.note(SourceRange{}, fmt::format("in the `{}` dialect the funnel arguments are ({})", dialect_name(c.dialect()),
                                        fmt::join(args, " ")));
    }
  }

  // The number a digit keyword carries (`bspline3`: order 3), as that argument's value.
  void digit_argument(int k) {
    ir::Expr e;
    e.kind = ir::ExprKind::Const;
    e.value = k;
    e.range = s.open_kw;
    SmallVec<ir::ExprId, 4> exprs;
    exprs.push_back(c.module().add_expr(e));
    ir::GenArgBinding b;
    b.arg = info.digit_arg;
    b.value = c.add_operand(id, info.args[info.digit_arg].name, std::move(exprs), s.open_kw);
    b.range = s.open_kw;
    bindings.push_back(b);
  }

  void option(const OptionValue& v) {
    if (v.spec->key != Opt::GenArg || v.spec->arg == ir::kNoArg) return;  // display options
    const ir::ArgInfo& arg = info.args[v.spec->arg];
    ir::GenArgBinding b;
    b.arg = v.spec->arg;
    b.range = v.word;
    switch (arg.type) {
      case ir::ArgType::Function: {
        std::span<const std::string_view> vars(info.variables);
        SmallVec<ir::ExprId, 4> exprs;
        FunctionOrigin origin;
        if (c.dialect() == Dialect::Nome3) {
          origin.generator = info.keyword;
          origin.has_pi = info.kind == ir::GenKind::Genimplicitsurf;
        }
        exprs.push_back(lower_function(c, a, v.raw, vars, origin));
        b.value = c.add_operand(id, v.spec->name, std::move(exprs), v.value_range);
        break;
      }
      case ir::ArgType::Points: b.refs = v.names; break;
      case ir::ArgType::Path: b.ref = v.ref; break;
      case ir::ArgType::Flag:
        b.is_flag = true;
        b.value = v.operand;
        break;
      default:
        b.value = v.operand;
        if (v.operand.is_valid() && is_counted(arg.type)) {
          const ir::Operand& o = c.module().operand(v.operand);
          b.is_truncated = v.value_expr.is_valid() && !o.exprs.empty() &&
                           is_truncated_count(c, a, v.value_expr, c.module().refs(o.exprs)[0], arg.type);
          if (!o.exprs.empty()) check_count(c, c.module().refs(o.exprs)[0], v.value_range, v.spec->name, b.is_truncated);
        }
        break;
    }
    bindings.push_back(b);
  }

  // NOME3's sphere and ellipsoid cut their angles to whole degrees (`(int)`, Sphere.cpp:28-30).
  void note_truncated_angles(const std::vector<std::optional<double>>& known) {
    for (const ir::GenArgBinding& b : bindings) {
      if (b.arg == ir::kNoArg || info.args[b.arg].type != ir::ArgType::Angle || !known[b.arg]) continue;
      const double v = *known[b.arg];
      if (v == std::trunc(v)) continue;
      c.diags()
          .emit(DiagKind::TruncatedAngle, b.range,
                fmt::format("`{}` has the value {}; as in NOME3 it is cut to {} degrees", info.display_name(b.arg, c.dialect()),
                            v, std::trunc(v)))
          .note(SourceRange{}, "NOME3's sphere and ellipsoid take their angles in whole degrees");
    }
  }

  // A partial torus with a full tube: NOME3 closed each θ segment with a quad from row
  // phi_segs back to row 0, which lie on each other (docs/generators.md, differences).
  void note_dropped_faces(const std::vector<std::optional<double>>& known) {
    if (info.kind == ir::GenKind::Sphere || info.kind == ir::GenKind::Ellipsoid) note_truncated_angles(known);
    if (info.kind != ir::GenKind::Torus) return;
    using A = ir::gen_arg::Torus;
    const std::optional<double> tmax = known[ir::arg_index(A::theta_max)], pmin = known[ir::arg_index(A::phi_min)],
                                pmax = known[ir::arg_index(A::phi_max)], ts = known[ir::arg_index(A::theta_segs)];
    if (!tmax || !pmin || !pmax || !ts || *tmax == 360.0 || std::fabs(*pmax - *pmin - 360.0) > 1e-9) return;
    const long n = std::lround(*ts);
    c.diags()
        .emit(DiagKind::DegenerateFacesDropped, s.open_kw,
              fmt::format("NOME3 gave this torus {} more faces of zero area, one per θ segment, joining its last ring "
                          "around the tube to the first one it lies on; nomec leaves them out",
                          n))
        .note(SourceRange{}, "the tube is the same; only the face count differs from NOME3's (docs/generators.md, "
                             "\"Differences from the original\")");
  }

  // The catalogue's domain rules on the values known now, with the message `--emit` gives.
  void check_domain() {
    const ir::Module& m = c.module();
    std::vector<std::optional<double>> known(info.args.size());
    for (const ir::GenArgBinding& b : bindings) {
      if (b.arg == ir::kNoArg || !b.value.is_valid() || info.args[b.arg].type == ir::ArgType::Function) continue;
      const ir::Operand& o = m.operand(b.value);
      if (o.exprs.size != 1) continue;
      ir::EvalResult v = ir::evaluate(m, m.refs(o.exprs)[0]);
      if (v.ok) known[b.arg] = b.is_truncated ? std::trunc(v.value) : v.value;
    }
    std::optional<ir::ArgProblem> problem = ir::check_arguments(info.kind, c.dialect(), known);
    if (!problem) {
      note_dropped_faces(known);
      return;
    }
    SourceRange at = s.open_kw;
    for (const ir::GenArgBinding& b : bindings) {
      if (b.arg == problem->arg && b.range.is_valid()) at = b.range;
    }
    const std::string& name = m.node(id).name;
    c.diags()
        .emit(DiagKind::GeometryFailed, at,
              fmt::format("`{}` `{}`: {}", s.keyword, name.substr(name.rfind('.') + 1), problem->message))
        .note(SourceRange{}, problem->hint);
  }
};

}  // namespace

ir::NodeId handle_generator(Context& c, const ast::Ast& a, const ast::Stmt& s, const Ctx& ctx) {
  const ir::GenKind gen = *generator_of(s);
  const ir::GeneratorInfo& info = ir::generator(gen);
  size_t pos = 0;
  auto name = c.read_name(s, pos, fmt::format("{} g (…) end{}", s.keyword, s.keyword));
  ir::NodeId id = c.node_for(s, c.qualify(ctx, name.value_or("")), ctx);
  c.module().get<ir::GeneratorData>(id).gen = gen;
  if (gen == ir::GenKind::Tunnel && s.close_text == "endfunnel") {
    c.diags()
        .emit(DiagKind::TunnelEndfunnel, s.close_kw, "`tunnel` closed with `endfunnel` (NOME 2016 style)")
        .fixit(s.close_kw, "endtunnel", "replace with `endtunnel`");
  }
  GenReader r{c, a, s, id, info, {}};
  const ir::Signature* sig = info.signature(c.dialect());
  const ir::Signature* other = info.other_order(c.dialect());
  // A JIPCAD-era NOME3 file is read in JIPCAD's order first (its tunnel).
  if (other != nullptr && other->era == "JIPCAD" && c.dialect() == Dialect::Nome3 && c.is_jipcad) std::swap(sig, other);
  if (std::optional<int> k = info.keyword_digits(s.keyword); k && info.digit_arg != ir::kNoArg) r.digit_argument(*k);
  bool took_args = false;
  bool arity_ok = true;
  auto positional = [&](const ast::Item& it) -> bool {
    if (it.kind != ItemKind::List || sig == nullptr || took_args) return false;
    took_args = true;
    arity_ok = r.read_positional(r.choose_order(*sig, other, it), it);
    return true;
  };
  read_body(c, a, s, pos, id, generator_options(gen, c.dialect()), [&](const OptionValue& v) { r.option(v); }, positional);
  if (sig != nullptr && !took_args && !sig->is_point_list) {
    c.diags().emit(DiagKind::MissingArgument, name ? s.items[0].range : s.open_kw,
                   fmt::format("`{}` needs its arguments `({})`", s.keyword,
                               fmt::join(sig->names.begin(), sig->names.begin() + static_cast<ptrdiff_t>(sig->args.size()), " ")));
  }
  if (arity_ok) r.check_domain();
  ir::Module& m = c.module();
  m.get<ir::GeneratorData>(id).args = {static_cast<uint32_t>(m.gen_args.size()), static_cast<uint32_t>(r.bindings.size())};
  m.gen_args.insert(m.gen_args.end(), r.bindings.begin(), r.bindings.end());
  return id;
}

}  // namespace nomec::check
