// The evaluator of SLIDE's live Tcl values (see tcl_live.h): a thread of its own that owns
// the replayed interpreter, and the job hand-over to it.
#include "frontend/check/tcl_live.h"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <deque>

#include "frontend/check/handlers.h"

namespace nomec::check {

tcl::ReadFile TclFiles::recording(tcl::ReadFile inner) {
  return [this, inner = std::move(inner)](const std::string& path) -> std::optional<std::string> {
    std::optional<std::string> text = inner ? inner(path) : std::nullopt;
    std::lock_guard lock(mutex_);
    files_.emplace(path, text);
    return text;
  };
}

tcl::ReadFile TclFiles::replaying() {
  return [this](const std::string& path) -> std::optional<std::string> {
    std::lock_guard lock(mutex_);
    auto it = files_.find(path);
    return it == files_.end() ? std::nullopt : it->second;
  };
}

std::string tk_scale_text(double value, double resolution) {
  int digits = 0;
  while (resolution > 0 && digits < 9 &&
         std::fabs(resolution * std::pow(10.0, digits) - std::round(resolution * std::pow(10.0, digits))) > 1e-9) {
    ++digits;
  }
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", resolution > 0 ? digits : 6, value);
  if (std::fabs(std::strtod(text, nullptr) - value) > 1e-12 * std::max(1.0, std::fabs(value))) {
    std::snprintf(text, sizeof text, "%.17g", value);  // off the slider's steps (`--what-if`)
  }
  return text;
}

struct TclEvaluator::Worker {
  explicit Worker(TclScene s) : scene(std::move(s)) {}

  TclScene scene;
  // Guarded by `call`, which a caller holds for the whole of its evaluation.
  mutable std::mutex call;
  std::deque<std::string> scripts;
  std::deque<std::string> texts;  // on one line, for dumps
  std::vector<bool> follows_update;
  std::unique_ptr<tcl::Interp> interp;
  std::vector<double> current;  // the slider values the interpreter holds
  bool update_fresh = true;     // the `tclupdate` blocks ran since the values last changed
  std::optional<std::string> update_problem;
  std::optional<std::string> replay_problem;  // the replay itself failed: nothing more runs
  std::atomic<int> update_runs{0};
  // While the scene is checked, its Tcl draws on the check's budget (`check_budget`); after
  // `end_check`, each change of slider values (a move) has a budget of its own, and a value
  // already evaluated at the current values is answered from `memo`.
  std::shared_ptr<tcl::Budget> check_budget;
  bool checked = false;
  bool new_move = false;  // the next evaluation starts a move (draws a new budget)
  std::map<uint32_t, ir::ExternalResult> memo;
};

namespace {

using Worker = TclEvaluator::Worker;

std::string problem_text(const tcl::Problem& p, std::string_view what) {
  switch (p.kind) {
    case tcl::ProblemKind::Error: return "Tcl error in " + std::string(what) + ": " + p.message;
    case tcl::ProblemKind::Limit:
      return std::string(what) + " was stopped: " + p.message;
    case tcl::ProblemKind::Memory: return std::string(what) + " was stopped: " + p.message;
    case tcl::ProblemKind::Crashed: return std::string(what) + " was stopped: " + p.message;
    case tcl::ProblemKind::Stopped: return "the scene's Tcl was stopped earlier: " + p.message;
    case tcl::ProblemKind::Refused:
    case tcl::ProblemKind::MissingSource:
    case tcl::ProblemKind::Fallback:
    case tcl::ProblemKind::Unavailable: return p.message;
  }
  return p.message;
}

void run_update(Worker& w) {
  w.update_problem.reset();
  for (const std::string& text : w.scene.update) {
    tcl::Outcome o = w.interp->run(text);
    if (!o.ok && !w.update_problem && !o.problems.empty()) {
      w.update_problem = problem_text(o.problems.front(), "a `tclupdate` block");
    }
  }
  w.update_fresh = true;
  ++w.update_runs;
}

// The interpreter as the check left it before it read the values: the `tclinit` blocks with
// the sliders at their checked values, then the `tclupdate` blocks once. Its worker is a
// process of its own; the scene's files are the texts the check read.
void build(Worker& w) {
  std::map<std::string, double> preset;
  for (const TclScene::Slider& s : w.scene.sliders) preset[s.variable] = s.value;
  tcl::ReadFile reader = w.scene.files ? w.scene.files->replaying() : tcl::ReadFile{};
  w.interp = std::make_unique<tcl::Interp>(
      w.scene.dir, reader, tcl::Limits{},
      [preset = std::move(preset)](const std::string& var, double, double) -> std::optional<double> {
        auto it = preset.find(var);
        return it == preset.end() ? std::nullopt : std::optional<double>(it->second);
      });
  if (w.check_budget && !w.checked) w.interp->use_budget(w.check_budget);
  for (const std::string& text : w.scene.init) {
    tcl::Outcome o = w.interp->run(text);
    for (const tcl::Problem& p : o.problems) {
      if (p.kind == tcl::ProblemKind::Crashed || p.kind == tcl::ProblemKind::Limit ||
          p.kind == tcl::ProblemKind::Unavailable) {
        w.replay_problem = problem_text(p, "replaying the scene's `tclinit` blocks");
      }
    }
  }
  w.current.clear();
  for (const TclScene::Slider& s : w.scene.sliders) w.current.push_back(s.value);
  run_update(w);
}

ir::ExternalResult run_job(Worker& w, uint32_t script, std::span<const double> values) {
  if (script >= w.scripts.size()) return {0, false, "no such Tcl value"};
  if (w.replay_problem) return {0, false, *w.replay_problem};
  if (w.checked) {
    const bool moved = values.size() != w.current.size() || !std::equal(values.begin(), values.end(), w.current.begin());
    if (moved) {
      w.memo.clear();
      w.new_move = true;
    } else if (auto it = w.memo.find(script); it != w.memo.end()) {
      return it->second;
    }
    if (w.new_move && w.interp && w.interp->stopped()) w.interp.reset();  // crashed or overdue in an earlier move
  }
  if (!w.interp) {
    build(w);
    if (w.replay_problem) return {0, false, *w.replay_problem};
  }
  if (values.size() != w.current.size()) return {0, false, "the scene's sliders changed since its Tcl was checked"};
  if (w.checked && w.new_move) {
    // A move runs the `tclupdate` blocks and the values that changed: microseconds in real
    // scenes (CheckOptions::tcl_move_milliseconds).
    w.interp->use_budget(std::make_shared<tcl::Budget>(w.scene.move_milliseconds, "for each slider move"));
    w.new_move = false;
  }
  for (size_t i = 0; i < values.size(); ++i) {
    if (values[i] == w.current[i]) continue;
    const TclScene::Slider& s = w.scene.sliders[i];
    w.interp->set(s.variable, tk_scale_text(values[i], s.resolution));
    w.current[i] = values[i];
    w.update_fresh = false;
  }
  if (w.follows_update[script]) {
    if (!w.update_fresh) run_update(w);
    if (w.update_problem) return {0, false, *w.update_problem};
  }
  tcl::Outcome o = w.interp->value(w.scripts[script]);
  ir::ExternalResult r;
  if (o.ok) {
    r = {o.number, true, {}};
  } else if (o.problems.empty()) {
    r = {0, false, "Tcl gave this value no number"};
  } else {
    r = {0, false, problem_text(o.problems.front(), "this value")};
  }
  if (w.checked) w.memo[script] = r;
  return r;
}

// One line: runs of blanks (newlines too) become one space.
std::string one_line(std::string_view s) {
  std::string out;
  for (char ch : s) {
    const bool blank = ch == ' ' || ch == '\t' || ch == '\n' || ch == '\r';
    if (blank && (out.empty() || out.back() == ' ')) continue;
    out += blank ? ' ' : ch;
  }
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

}  // namespace

TclEvaluator::TclEvaluator(TclScene scene, std::shared_ptr<tcl::Budget> check_budget)
    : w_(std::make_unique<Worker>(std::move(scene))) {
  w_->check_budget = std::move(check_budget);
  for (const TclScene::Slider& s : w_->scene.sliders) inputs_.push_back(s.param);
}

TclEvaluator::~TclEvaluator() = default;

uint32_t TclEvaluator::add(std::string script, bool follows_update) {
  std::lock_guard lock(w_->call);
  w_->texts.push_back(one_line(script));
  w_->scripts.push_back(std::move(script));
  w_->follows_update.push_back(follows_update);
  return static_cast<uint32_t>(w_->scripts.size() - 1);
}

void TclEvaluator::end_check() {
  std::lock_guard lock(w_->call);
  w_->checked = true;
  w_->new_move = true;
  w_->check_budget.reset();
  w_->memo.clear();
}

std::string_view TclEvaluator::text(uint32_t script) const {
  std::lock_guard lock(w_->call);
  return script < w_->texts.size() ? std::string_view(w_->texts[script]) : std::string_view("?");
}

int TclEvaluator::update_runs() const { return w_->update_runs.load(); }

ir::ExternalResult TclEvaluator::evaluate(uint32_t script, std::span<const double> values) const {
  std::lock_guard call(w_->call);
  try {
    return run_job(*w_, script, values);
  } catch (const std::exception& e) {  // memory exhausted: an error of this value, not of the process
    return {0, false, std::string("nomec could not evaluate this value's Tcl: ") + e.what()};
  }
}

// ---- the check's side: which values are live, and what they depend on ----

namespace {

bool word_char(char ch) { return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_'; }

// Where `name` first occurs in `text` as a whole word (`$par_n`, `${par_n}`, `::par_n`,
// `[set par_n]`, `$oOffset(height)`), or npos.
size_t find_word(std::string_view text, std::string_view name) {
  for (size_t at = text.find(name); at != std::string_view::npos; at = text.find(name, at + 1)) {
    const size_t end = at + name.size();
    if ((at == 0 || !word_char(text[at - 1])) && (end >= text.size() || !word_char(text[end]))) return at;
  }
  return std::string_view::npos;
}

// `oOffset(height)` → `oOffset`.
std::string_view base_name(std::string_view var) { return var.substr(0, var.find('(')); }

}  // namespace

void note_tcl_update(Context& c, const tcl::Outcome& o, std::string_view text) {
  for (const std::string& w : o.writes) {
    if (c.tcl_update_writes.insert(w).second && c.tcl != nullptr) c.tcl->watch(w);
  }
  auto add_slider = [&](ir::NodeId id) {
    if (std::find(c.tcl_update_sliders.begin(), c.tcl_update_sliders.end(), id) == c.tcl_update_sliders.end()) {
      c.tcl_update_sliders.push_back(id);
    }
  };
  for (const std::string& r : o.reads) {
    if (auto it = c.tcl_sliders.find(r); it != c.tcl_sliders.end()) add_slider(it->second);
  }
  for (const auto& [var, id] : c.tcl_sliders) {
    if (find_word(text, var) != std::string_view::npos) add_slider(id);
  }
}

bool reads_tcl_update(const Context& c, std::string_view script, const TclValue& v) {
  for (const std::string& r : v.reads) {
    if (c.tcl_update_writes.contains(std::string(base_name(r)))) return true;
  }
  for (const std::string& w : c.tcl_update_writes) {
    if (find_word(script, w) != std::string_view::npos) return true;
  }
  return false;
}

namespace {

ir::ExprId constant(Context& c, double v, SourceRange r) {
  ir::Expr e;
  e.kind = ir::ExprKind::Const;
  e.value = v;
  e.range = r;
  return c.module().add_expr(std::move(e));
}

TclEvaluator& live_evaluator(Context& c) {
  if (c.tcl_live) return *c.tcl_live;
  TclScene scene;
  scene.dir = c.tcl_dir;
  scene.init = c.tcl_init_texts;
  scene.update = c.tcl_update_texts;
  scene.files = c.tcl_files;
  scene.move_milliseconds = std::max(c.options().tcl_move_milliseconds, 1);
  for (const tcl::Slider& s : c.tcl->sliders()) {
    auto it = c.tcl_sliders.find(s.variable);
    if (it == c.tcl_sliders.end()) continue;
    scene.sliders.push_back({s.variable, it->second, c.module().param(it->second).value, s.resolution});
  }
  c.tcl_live = std::make_shared<TclEvaluator>(std::move(scene), c.tcl_budget);
  c.module().external = c.tcl_live;
  return *c.tcl_live;
}

// The sliders a value depends on: those its script read, those it names (a branch not taken
// may read them), and, when it reads what a `tclupdate` block sets, those the blocks read.
std::vector<ir::NodeId> live_dependencies(Context& c, std::string_view script, const TclValue& v, bool& follows_update) {
  std::vector<ir::NodeId> deps = v.sliders;
  auto add = [&](ir::NodeId id) {
    if (std::find(deps.begin(), deps.end(), id) == deps.end()) deps.push_back(id);
  };
  for (const auto& [var, id] : c.tcl_sliders) {
    if (find_word(script, var) != std::string_view::npos) add(id);
  }
  follows_update = reads_tcl_update(c, script, v);
  if (follows_update) {
    for (ir::NodeId id : c.tcl_update_sliders) add(id);
  }
  return deps;
}

// A `Param` expression of slider `id` for the dependency graph, at its name in the value
// when the value names it (so hover and rename see it there), else empty at the value.
ir::ExprId dependency_expr(Context& c, ir::NodeId id, SourceRange where) {
  std::string_view text = c.sources().text(where);
  SourceRange r{where.file, where.begin, where.begin};
  for (const auto& [var, p] : c.tcl_sliders) {
    if (p != id) continue;
    const size_t at = find_word(text, var);
    if (at == std::string_view::npos) continue;
    const size_t from = at > 0 && text[at - 1] == '$' ? at - 1 : at;
    r = SourceRange{where.file, static_cast<uint32_t>(where.begin + from), static_cast<uint32_t>(where.begin + at + var.size())};
    break;
  }
  ir::Expr e;
  e.kind = ir::ExprKind::Param;
  e.param = id;
  e.range = r;
  return c.module().add_expr(std::move(e));
}

bool same(double a, double b) { return std::fabs(a - b) <= 1e-12 * std::max(1.0, std::fabs(b)); }

}  // namespace

ir::ExprId live_tcl_value(Context& c, std::string script, const TclValue& v, SourceRange where) {
  bool follows_update = false;
  std::vector<ir::NodeId> deps = live_dependencies(c, script, v, follows_update);
  if (deps.empty() || c.tcl == nullptr) return constant(c, v.value, where);
  std::sort(deps.begin(), deps.end(), [](ir::NodeId a, ir::NodeId b) { return a.index < b.index; });
  TclEvaluator& ev = live_evaluator(c);
  const uint32_t id = ev.add(script, follows_update);
  // The value must come out the same when the evaluator runs it on its own, twice: a script
  // that changes what it reads (`incr`), draws random numbers or depends on what another
  // value's script left behind cannot follow its sliders.
  std::vector<double> values;
  for (ir::NodeId p : ev.inputs()) values.push_back(c.module().param(p).value);
  const ir::ExternalResult first = ev.evaluate(id, values);
  const ir::ExternalResult again = ev.evaluate(id, values);
  const ir::ExternalResult& differs = !first.ok || !same(first.value, v.value) ? first : again;
  if (!differs.ok || !same(differs.value, v.value)) {
    const std::string got = differs.ok ? fmt::format("{}", differs.value) : fmt::format("`{}`", differs.problem);
    c.diags().emit(DiagKind::TclValueFixed, where,
                   fmt::format("Tcl computes {} here from the slider `{}`, but running this value's script again gives {}, "
                               "so nomec cannot re-run it when the slider moves (it changes what it reads, like `incr`, "
                               "or depends on chance or on other values' scripts); the value stays {} (use `-D` to "
                               "change it)",
                               v.value, c.module().node(deps.front()).name, got, v.value));
    return constant(c, v.value, where);
  }
  std::vector<ir::ExprId> params;
  for (ir::NodeId p : deps) params.push_back(dependency_expr(c, p, where));
  return c.module().add_external(id, v.value, params, where);
}

}  // namespace nomec::check
