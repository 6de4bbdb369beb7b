// The evaluator of SLIDE's live Tcl values (see tcl_live.h): a thread of its own that owns
// the replayed interpreter, and the job hand-over to it.
#include "frontend/check/tcl_live.h"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <system_error>
#include <thread>

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
  std::mutex call;
  std::deque<std::string> scripts;
  std::deque<std::string> texts;  // on one line, for dumps
  std::vector<bool> follows_update;
  bool started = false;
  std::thread thread;

  // The hand-over, guarded by `m`.
  std::mutex m;
  std::condition_variable wake, finished;
  bool stop = false, has_job = false, done = false;
  uint32_t job_script = 0;
  std::span<const double> job_values;
  ir::ExternalResult job_result;

  // The worker thread's own.
  std::unique_ptr<tcl::Interp> interp;
  std::vector<double> current;  // the slider values the interpreter holds
  bool update_fresh = true;     // the `tclupdate` blocks ran since the values last changed
  std::optional<std::string> update_problem;
  std::atomic<int> update_runs{0};
};

namespace {

using Worker = TclEvaluator::Worker;

std::string problem_text(const tcl::Problem& p, std::string_view what) {
  switch (p.kind) {
    case tcl::ProblemKind::Error: return "Tcl error in " + std::string(what) + ": " + p.message;
    case tcl::ProblemKind::Limit:
      return std::string(what) + " was stopped: " + p.message + " (a loop that never ends?)";
    case tcl::ProblemKind::Memory: return std::string(what) + " was stopped: " + p.message;
    case tcl::ProblemKind::Refused:
    case tcl::ProblemKind::MissingSource:
    case tcl::ProblemKind::Fallback: return p.message;
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
// the sliders at their checked values, then the `tclupdate` blocks once.
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
  for (const std::string& text : w.scene.init) w.interp->run(text);
  w.current.clear();
  for (const TclScene::Slider& s : w.scene.sliders) w.current.push_back(s.value);
  run_update(w);
}

ir::ExternalResult run_job(Worker& w, uint32_t script, std::span<const double> values) {
  if (script >= w.scripts.size()) return {0, false, "no such Tcl value"};
  if (!w.interp) build(w);
  if (values.size() != w.current.size()) return {0, false, "the scene's sliders changed since its Tcl was checked"};
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
  if (o.ok) return {o.number, true, {}};
  if (o.problems.empty()) return {0, false, "Tcl gave this value no number"};
  return {0, false, problem_text(o.problems.front(), "this value")};
}

void loop(Worker* w) {
  std::unique_lock lock(w->m);
  for (;;) {
    w->wake.wait(lock, [w] { return w->stop || w->has_job; });
    if (!w->has_job) break;  // stopped
    w->has_job = false;
    const uint32_t script = w->job_script;
    const std::span<const double> values = w->job_values;
    lock.unlock();
    ir::ExternalResult r;
    try {
      r = run_job(*w, script, values);
    } catch (const std::exception& e) {  // memory exhausted: an error of this value, not of the process
      r = {0, false, std::string("nomec could not evaluate this value's Tcl: ") + e.what()};
    }
    lock.lock();
    w->job_result = std::move(r);
    w->done = true;
    w->finished.notify_one();
  }
  lock.unlock();
  w->interp.reset();  // on the thread that made it
  tcl::finish_thread();  // and Tcl's data for this thread
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

TclEvaluator::TclEvaluator(TclScene scene) : w_(std::make_unique<Worker>(std::move(scene))) {
  for (const TclScene::Slider& s : w_->scene.sliders) inputs_.push_back(s.param);
}

TclEvaluator::~TclEvaluator() {
  if (!w_->started) return;
  {
    std::lock_guard lock(w_->m);
    w_->stop = true;
  }
  w_->wake.notify_one();
  w_->thread.join();
}

uint32_t TclEvaluator::add(std::string script, bool follows_update) {
  std::lock_guard lock(w_->call);
  w_->texts.push_back(one_line(script));
  w_->scripts.push_back(std::move(script));
  w_->follows_update.push_back(follows_update);
  return static_cast<uint32_t>(w_->scripts.size() - 1);
}

std::string_view TclEvaluator::text(uint32_t script) const {
  std::lock_guard lock(w_->call);
  return script < w_->texts.size() ? std::string_view(w_->texts[script]) : std::string_view("?");
}

int TclEvaluator::update_runs() const { return w_->update_runs.load(); }

ir::ExternalResult TclEvaluator::evaluate(uint32_t script, std::span<const double> values) const {
  std::lock_guard call(w_->call);
  if (!w_->started) {
    try {
      w_->thread = std::thread(loop, w_.get());
    } catch (const std::system_error&) {
      return {0, false, "nomec could not start the thread that evaluates this scene's Tcl"};
    }
    w_->started = true;
  }
  {
    std::lock_guard lock(w_->m);
    w_->job_script = script;
    w_->job_values = values;
    w_->has_job = true;
    w_->done = false;
  }
  w_->wake.notify_one();
  std::unique_lock lock(w_->m);
  w_->finished.wait(lock, [this] { return w_->done; });
  return std::move(w_->job_result);
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
  for (const tcl::Slider& s : c.tcl->sliders()) {
    auto it = c.tcl_sliders.find(s.variable);
    if (it == c.tcl_sliders.end()) continue;
    scene.sliders.push_back({s.variable, it->second, c.module().param(it->second).value, s.resolution});
  }
  c.tcl_live = std::make_shared<TclEvaluator>(std::move(scene));
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
