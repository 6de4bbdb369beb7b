// The Tcl engine (see engine.h): a safe Tcl 8.6 interpreter per scene, the commands a SLIDE
// scene may use in place of the hidden ones, the Tk stubs, the `slide` command, limits, and
// read traces.
#include "frontend/tcl/engine.h"

#include <tcl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <set>

#include "frontend/tcl/fallback.h"
#include "frontend/tcl/guard.h"

namespace nomec::tcl {

struct Engine::State {
  Tcl_Interp* interp = nullptr;
  std::string dir;
  ReadFile read_file;
  HasFile has_file;
  Limits limits;
  Preset preset;
  std::vector<Slider> sliders;
  std::vector<SlideCall> calls;
  std::vector<Problem> notes;
  std::set<std::string> noted;
  std::set<std::string> watched;
  std::vector<std::string>* reads = nullptr;   // set while a script runs
  std::vector<std::string>* writes = nullptr;  // set while `run_tracking_writes` runs
  std::optional<Problem> refusal;             // the last refused command (for its kind)
  int source_depth = 0;
  Guard guard;
  std::optional<std::string> broken;  // Tcl panicked (the interpreter is abandoned): why
  // `info cmdcount` and `info globals` as Tcl implements them, taken before any scene code
  // runs: a scene may redefine `info`, and nomec must not run the scene's code to set limits.
  Tcl_ObjCmdProc* cmdcount = nullptr;
  Tcl_ObjCmdProc* info_globals = nullptr;
};

namespace {

using State = Engine::State;

thread_local bool t_made_interp = false;  // this thread has Tcl data to free (finish_thread)

const std::vector<std::string_view> kRefused = {"exec",  "open",   "socket", "cd",    "exit",   "load",
                                                "file",  "glob",   "pwd",    "fconfigure", "unload", "after",
                                                "vwait", "interp", "::tcl::chan::pipe", "::tcl::chan::create"};

std::string_view arg(Tcl_Obj* o) {
  int n = 0;
  const char* s = Tcl_GetStringFromObj(o, &n);
  return {s, static_cast<size_t>(n)};
}

void set_result(Tcl_Interp* interp, std::string_view text) {
  Tcl_SetObjResult(interp, Tcl_NewStringObj(text.data(), static_cast<int>(text.size())));
}

int refuse(ClientData data, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  auto* s = static_cast<State*>(data);
  std::string name(objc > 0 ? arg(objv[0]) : "");
  if (name.rfind("::tcl::chan::", 0) == 0) name = "chan " + name.substr(13);  // as the scene wrote it
  std::string msg = name == "open"
                        ? "`open` is not available in a SLIDE scene checked by nomec (a scene may not write files, "
                          "and reads only the files it `source`s next to it)"
                        : "`" + name + "` is not available in a SLIDE scene checked by nomec (a scene may not run "
                          "programs, use files, pipes, sockets or the process, or wait)";
  s->refusal = Problem{ProblemKind::Refused, msg, 0, name};
  set_result(interp, msg);
  return TCL_ERROR;
}

// A widget path's own command (`$root.sample conf -bg …`): does nothing.
int widget_self(ClientData, Tcl_Interp* interp, int, Tcl_Obj* const[]) {
  Tcl_ResetResult(interp);
  return TCL_OK;
}

// Does nothing and returns "" (`pack`, `wm`, `bind` …).
int noop(ClientData, Tcl_Interp* interp, int, Tcl_Obj* const[]) {
  Tcl_ResetResult(interp);
  return TCL_OK;
}

// `winfo exists .w` and the like: no window exists headless.
int winfo(ClientData, Tcl_Interp* interp, int, Tcl_Obj* const[]) {
  set_result(interp, "0");
  return TCL_OK;
}

// The value of option `name` (Tk accepts unique abbreviations: `-var` for `-variable`).
std::optional<std::string> option(int objc, Tcl_Obj* const objv[], std::string_view name, size_t min_len) {
  std::optional<std::string> found;
  for (int i = 2; i + 1 < objc; i += 2) {
    std::string_view o = arg(objv[i]);
    if (o.size() >= min_len && o.size() <= name.size() && name.substr(0, o.size()) == o) found = std::string(arg(objv[i + 1]));
  }
  return found;
}

double number_or(const std::optional<std::string>& s, double fallback) {
  if (!s) return fallback;
  char* end = nullptr;
  double v = std::strtod(s->c_str(), &end);
  return end != s->c_str() ? v : fallback;
}

int decimals_of(double res) {
  int d = 0;
  while (d < 9 && std::fabs(res * std::pow(10.0, d) - std::round(res * std::pow(10.0, d))) > 1e-9) ++d;
  return d;
}

// Creates the variable with `value` when it is unset (Tk's check and radio buttons, entries).
void create_if_unset(Tcl_Interp* interp, const std::optional<std::string>& var, const char* value) {
  if (!var || var->empty()) return;
  if (Tcl_GetVar2(interp, var->c_str(), nullptr, TCL_GLOBAL_ONLY) == nullptr) {
    Tcl_SetVar2(interp, var->c_str(), nullptr, value, TCL_GLOBAL_ONLY);
  }
}

// A scale bound to a variable: Tk rounds the value to the resolution counted from `-from`,
// clamps it to the range and writes it back when it changed (slide.md §7.2).
void record_scale(State& s, int objc, Tcl_Obj* const objv[]) {
  std::optional<std::string> var = option(objc, objv, "-variable", 4);
  if (!var || var->empty()) return;
  Slider sl;
  sl.variable = *var;
  sl.from = number_or(option(objc, objv, "-from", 3), 0);
  sl.to = number_or(option(objc, objv, "-to", 3), 100);
  sl.resolution = number_or(option(objc, objv, "-resolution", 4), 1);
  const char* cur = Tcl_GetVar2(s.interp, var->c_str(), nullptr, TCL_GLOBAL_ONLY);
  double v = sl.from;
  bool numeric = false;
  if (cur != nullptr) {
    char* end = nullptr;
    double parsed = std::strtod(cur, &end);
    numeric = end != cur;
    if (numeric) v = parsed;
  }
  double r = v;
  if (sl.resolution > 0) r = sl.from + std::round((v - sl.from) / sl.resolution) * sl.resolution;
  r = std::clamp(r, std::min(sl.from, sl.to), std::max(sl.from, sl.to));
  if (cur == nullptr || !numeric || std::fabs(r - v) > 1e-12) {
    char text[64];
    std::snprintf(text, sizeof text, "%.*f", sl.resolution > 0 ? decimals_of(sl.resolution) : 6, r);
    Tcl_SetVar2(s.interp, var->c_str(), nullptr, text, TCL_GLOBAL_ONLY);
    r = std::strtod(text, nullptr);
    sl.rounded = cur != nullptr && numeric;
    sl.written = v;
  }
  sl.value = r;
  if (std::optional<double> given = s.preset ? s.preset(sl.variable, sl.from, sl.to) : std::nullopt) {
    char text[64];
    std::snprintf(text, sizeof text, "%.17g", *given);
    Tcl_SetVar2(s.interp, var->c_str(), nullptr, text, TCL_GLOBAL_ONLY);
    sl.value = *given;
  }
  auto same = std::find_if(s.sliders.begin(), s.sliders.end(), [&](const Slider& o) { return o.variable == sl.variable; });
  if (same != s.sliders.end()) {
    *same = sl;
  } else {
    s.sliders.push_back(sl);
  }
}

// `frame .p.x …`, `scale …`, `radiobutton …`: returns the path and gives it a command.
int widget(ClientData data, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  auto* s = static_cast<State*>(data);
  if (objc < 2) {
    set_result(interp, std::string("wrong # args: should be \"") + std::string(arg(objv[0])) + " pathName ?-option value ...?\"");
    return TCL_ERROR;
  }
  std::string_view kind = arg(objv[0]);
  if (kind == "scale") record_scale(*s, objc, objv);
  if (kind == "checkbutton") create_if_unset(interp, option(objc, objv, "-variable", 4), "0");
  if (kind == "radiobutton") create_if_unset(interp, option(objc, objv, "-variable", 4), "");
  if (kind == "entry") create_if_unset(interp, option(objc, objv, "-textvariable", 3), "");
  std::string path(arg(objv[1]));
  Tcl_CreateObjCommand(interp, path.c_str(), widget_self, nullptr, nullptr);
  set_result(interp, path);
  return TCL_OK;
}

bool safe_relative(std::string_view p);

// `slide create TYPE NAME …` / `slide delete TYPE NAME`: recorded for the checker.
int slide_cmd(ClientData data, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  auto* s = static_cast<State*>(data);
  if ((objc == 4 || objc == 5) && arg(objv[1]) == "unavailable") {  // from the prelude's lost-package procs
    std::string proc(arg(objv[2])), group(arg(objv[3])), file(objc == 5 ? arg(objv[4]) : "");
    std::string msg = "`" + proc + "` belongs to SLIDE's lost `slideui`/`parselib` packages; nomec makes `g" + group +
                      "` an empty group and `o" + group + "` an empty object";
    if (proc == "CreateSTLObject" || proc == "CreateSIFObject") {  // NAME FILE, not there (see `slide import`)
      msg = "`" + proc + "` imports the mesh file `" + file + "`, which is " +
            (file.empty() ? "not named" : safe_relative(file) ? "not next to the scene" : "not a file next to the scene") +
            "; `g" + group + "` stays an empty group and `o" + group + "` an empty object: nothing of it is drawn";
    }
    s->notes.push_back({ProblemKind::Fallback, msg, 0, proc});
    Tcl_ResetResult(interp);
    return TCL_OK;
  }
  if (objc == 4 && arg(objv[1]) == "import") {  // `slide import NAME FILE`: 1 when FILE is next to the scene
    const std::string file(arg(objv[3]));
    const bool here = !file.empty() && safe_relative(file) &&
                      (s->has_file ? s->has_file(s->dir + file) : s->read_file && s->read_file(s->dir + file).has_value());
    // Recorded as `import import NAME FILE`: no `slide create` call can make that first word.
    if (here) s->calls.push_back(SlideCall{{"import", "import", std::string(arg(objv[2])), file}});
    set_result(interp, here ? "1" : "0");
    return TCL_OK;
  }
  if (objc < 4 || (arg(objv[1]) != "create" && arg(objv[1]) != "delete")) {
    set_result(interp, "wrong # args: should be \"slide create|delete type id ?args …?\"");
    return TCL_ERROR;
  }
  SlideCall call;
  for (int i = 1; i < objc; ++i) call.words.emplace_back(arg(objv[i]));
  s->calls.push_back(std::move(call));
  set_result(interp, arg(objv[3]));
  return TCL_OK;
}

bool safe_relative(std::string_view p) {
  if (p.empty() || p[0] == '/' || p[0] == '~') return false;
  size_t at = 0;
  while (at <= p.size()) {
    size_t slash = p.find('/', at);
    std::string_view part = p.substr(at, slash == std::string_view::npos ? std::string_view::npos : slash - at);
    if (part == "..") return false;
    if (slash == std::string_view::npos) break;
    at = slash + 1;
  }
  return true;
}

// `source FILE`: a file next to the scene, read through the checker's reader. A missing
// SLIDE helper file (SLIDEUI.tcl …) is replaced by nomec's own version of it.
int source_cmd(ClientData data, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  auto* s = static_cast<State*>(data);
  if (objc != 2 && objc != 4) {
    set_result(interp, "wrong # args: should be \"source ?-encoding name? fileName\"");
    return TCL_ERROR;
  }
  std::string name(arg(objv[objc - 1]));
  if (!safe_relative(name)) {
    std::string msg = "`source " + name + "`: a SLIDE scene may only source files in its own folder";
    s->refusal = Problem{ProblemKind::Refused, msg, 0, name};
    set_result(interp, msg);
    return TCL_ERROR;
  }
  std::optional<std::string> text = s->read_file ? s->read_file(s->dir + name) : std::nullopt;
  const size_t slash = name.rfind('/');
  std::string_view base = std::string_view(name).substr(slash == std::string::npos ? 0 : slash + 1);
  if (!text) {
    if (std::optional<std::string_view> own = fallback_script(base)) {
      if (s->noted.insert("fallback:" + name).second) {
        s->notes.push_back({ProblemKind::Fallback,
                            "`" + name + "` is not next to the scene; nomec uses its own version of it (slide.md §7)", 0, name});
      }
      text = std::string(*own);
    } else {
      std::string msg = "couldn't read file \"" + name + "\" (looked for " + s->dir + name + ")";
      s->refusal = Problem{ProblemKind::MissingSource, msg, 0, name};
      set_result(interp, msg);
      return TCL_ERROR;
    }
  }
  if (s->source_depth > 32) {
    set_result(interp, "`source` nests too deeply (a file sources itself?)");
    return TCL_ERROR;
  }
  std::string script = normalize_newlines(*text);
  ++s->source_depth;
  int rc = Tcl_EvalEx(interp, script.c_str(), static_cast<int>(script.size()), 0);
  --s->source_depth;
  if (rc == TCL_ERROR) {
    std::string info = "\n    (file \"" + name + "\" line " + std::to_string(Tcl_GetErrorLine(interp)) + ")";
    Tcl_AddErrorInfo(interp, info.c_str());
  }
  return rc == TCL_RETURN ? TCL_OK : rc;
}

char* read_trace(ClientData data, Tcl_Interp*, const char* name1, const char* name2, int) {
  auto* s = static_cast<State*>(data);
  if (s->reads != nullptr) {
    std::string n = name2 != nullptr ? std::string(name1) + "(" + name2 + ")" : std::string(name1);
    if (std::find(s->reads->begin(), s->reads->end(), n) == s->reads->end()) s->reads->push_back(n);
  }
  return nullptr;
}

char* write_trace(ClientData data, Tcl_Interp*, const char* name1, const char*, int) {
  auto* s = static_cast<State*>(data);
  if (s->writes != nullptr && std::find(s->writes->begin(), s->writes->end(), name1) == s->writes->end()) {
    s->writes->emplace_back(name1);
  }
  return nullptr;
}

// Tcl's own implementation of `info SUBCOMMAND` (nullptr when it has none).
Tcl_ObjCmdProc* info_proc(Tcl_Interp* in, const char* subcommand) {
  Tcl_CmdInfo info;
  const std::string name = std::string("::tcl::info::") + subcommand;
  if (Tcl_GetCommandInfo(in, name.c_str(), &info) == 0 || info.objProc == nullptr) return nullptr;
  return info.objProc;
}

// Calls `info SUBCOMMAND` as Tcl implements it, whatever the scene made of `info`; its
// result is the interpreter's result. (The ensemble hands a subcommand its own name as its
// only word.)
int call_info(Tcl_Interp* in, Tcl_ObjCmdProc* proc, const char* subcommand) {
  if (proc == nullptr) return TCL_ERROR;
  Tcl_Obj* word = Tcl_NewStringObj(subcommand, -1);
  Tcl_IncrRefCount(word);
  const int rc = proc(nullptr, in, 1, &word);
  Tcl_DecrRefCount(word);
  return rc;
}

// The names of the interpreter's global variables.
std::vector<std::string> globals(State& s) {
  Tcl_Interp* in = s.interp;
  std::vector<std::string> out;
  if (call_info(in, s.info_globals, "globals") != TCL_OK) return out;
  Tcl_Obj* list = Tcl_GetObjResult(in);
  Tcl_IncrRefCount(list);
  int n = 0;
  Tcl_Obj** items = nullptr;
  if (Tcl_ListObjGetElements(in, list, &n, &items) == TCL_OK) {
    for (int i = 0; i < n; ++i) out.emplace_back(arg(items[i]));
  }
  Tcl_DecrRefCount(list);
  Tcl_ResetResult(in);
  return out;
}

void install(State& s) {
  Tcl_Interp* in = s.interp;
  s.cmdcount = info_proc(in, "cmdcount");
  s.info_globals = info_proc(in, "globals");
  Tcl_MakeSafe(in);  // hides exec, open, socket, cd, exit, load, source, file, glob …
  for (std::string_view name : kRefused) {
    Tcl_CreateObjCommand(in, std::string(name).c_str(), refuse, &s, nullptr);
  }
  Tcl_CreateObjCommand(in, "source", source_cmd, &s, nullptr);
  Tcl_CreateObjCommand(in, "slide", slide_cmd, &s, nullptr);
  for (const char* w : {"toplevel", "frame", "labelframe", "scale", "label", "button", "checkbutton", "radiobutton",
                        "entry", "canvas", "listbox", "menu", "menubutton", "message", "text", "scrollbar", "spinbox",
                        "panedwindow"}) {
    Tcl_CreateObjCommand(in, w, widget, &s, nullptr);
  }
  for (const char* w : {"pack", "grid", "place", "wm", "bind", "focus", "raise", "lower", "destroy", "tk_chooseColor",
                        "tkwait", "image", "font", "option", "tk", "bell", "grab", "slfwin", "bindtags", "selection",
                        "clipboard", "puts"}) {
    Tcl_CreateObjCommand(in, w, noop, &s, nullptr);
  }
  Tcl_CreateObjCommand(in, "winfo", winfo, &s, nullptr);
  s.guard.interp = in;
  install_guards(s.guard);
  std::string setup(prelude_script());
  Tcl_EvalEx(in, setup.c_str(), static_cast<int>(setup.size()), TCL_EVAL_GLOBAL);
}

}  // namespace

const std::vector<std::string_view>& refused_commands() { return kRefused; }

Engine::Engine(std::string dir, ReadFile read_file, Limits limits, Preset preset, HasFile has_file)
    : s_(std::make_unique<State>()) {
  t_made_interp = true;
  static std::once_flag once;
  std::call_once(once, [] { Tcl_FindExecutable(nullptr); });
  s_->interp = Tcl_CreateInterp();
  s_->dir = std::move(dir);
  s_->read_file = std::move(read_file);
  s_->limits = limits;
  s_->preset = std::move(preset);
  s_->has_file = std::move(has_file);
  install(*s_);
}

Engine::~Engine() {
  // An interpreter Tcl panicked in is left as it is (its state is half-changed).
  if (s_ && s_->interp != nullptr && !s_->broken) Tcl_DeleteInterp(s_->interp);
}

namespace {

// Arms the command-count and time limits for one script, or for one touch of a variable
// (setting or reading one runs the scene's traces on it, which are scripts too).
void arm_limits(State& s) {
  Tcl_Interp* in = s.interp;
  Tcl_LimitTypeReset(in, TCL_LIMIT_COMMANDS);
  Tcl_LimitTypeReset(in, TCL_LIMIT_TIME);
  Tcl_WideInt count = 0;
  if (call_info(in, s.cmdcount, "cmdcount") == TCL_OK) Tcl_GetWideIntFromObj(nullptr, Tcl_GetObjResult(in), &count);
  Tcl_ResetResult(in);
  const int64_t limit = count + s.limits.commands;
  Tcl_LimitSetCommands(in, limit > INT32_MAX ? INT32_MAX : static_cast<int>(limit));
  Tcl_Time t;
  Tcl_GetTime(&t);
  const int ms = std::max(s.limits.milliseconds, 1);
  t.sec += ms / 1000;
  t.usec += static_cast<long>(ms % 1000) * 1000;
  if (t.usec >= 1000000) {
    t.sec += 1;
    t.usec -= 1000000;
  }
  Tcl_LimitSetTime(in, &t);
  Tcl_LimitSetGranularity(in, TCL_LIMIT_TIME, 100);
  Tcl_LimitTypeSet(in, TCL_LIMIT_COMMANDS);
  Tcl_LimitTypeSet(in, TCL_LIMIT_TIME);
}

void disarm_limits(State& s) {
  Tcl_LimitTypeReset(s.interp, TCL_LIMIT_COMMANDS);
  Tcl_LimitTypeReset(s.interp, TCL_LIMIT_TIME);
}

// The outcome of a script that returned `rc`; reads Tcl's result and errorInfo while the
// limits are still armed (a trace on `::errorInfo` is the scene's code), then disarms them.
Outcome finish(State& s, int rc) {
  Outcome o;
  Tcl_Interp* in = s.interp;
  if (rc == TCL_OK || rc == TCL_RETURN) {
    // A huge whole number would take minutes to print (guard.h, kMaxDigits).
    if (auto msg = too_many_digits(Tcl_GetObjResult(in), "the script's result")) {
      s.guard.refusal = *msg;
      Tcl_SetObjResult(in, Tcl_NewStringObj(msg->c_str(), -1));
      rc = TCL_ERROR;
    }
  }
  o.result = Tcl_GetStringResult(in);
  const bool limited = Tcl_LimitExceeded(in) != 0;
  // errorInfo is read with its traces quiet: Tcl's own copy, not through the variable.
  std::string info;
  if (rc != TCL_OK && rc != TCL_RETURN) {
    Tcl_Obj* options = Tcl_GetReturnOptions(in, rc);
    Tcl_IncrRefCount(options);
    Tcl_Obj* key = Tcl_NewStringObj("-errorinfo", -1);
    Tcl_IncrRefCount(key);
    Tcl_Obj* value = nullptr;
    if (Tcl_DictObjGet(nullptr, options, key, &value) == TCL_OK && value != nullptr) info = Tcl_GetString(value);
    Tcl_DecrRefCount(key);
    Tcl_DecrRefCount(options);
  }
  const int line = Tcl_GetErrorLine(in);
  disarm_limits(s);
  if (rc == TCL_OK || rc == TCL_RETURN) {
    o.ok = true;
  } else if (s.guard.refusal || limited) {
    o.problems.push_back({s.guard.refusal ? ProblemKind::Memory : ProblemKind::Limit,
                          s.guard.refusal ? *s.guard.refusal : o.result, line, info});
  } else if (rc == TCL_BREAK || rc == TCL_CONTINUE) {
    o.problems.push_back({ProblemKind::Error, rc == TCL_BREAK ? "`break` outside a loop" : "`continue` outside a loop", 0, ""});
  } else {
    Problem p{ProblemKind::Error, o.result, line, info};
    if (s.refusal && o.result == s.refusal->message) p.kind = s.refusal->kind;
    o.problems.push_back(std::move(p));
  }
  s.refusal.reset();
  s.guard.refusal.reset();
  Tcl_ResetResult(in);
  return o;
}

// Marks the interpreter abandoned after a Tcl panic inside `what`, and says so in `o`.
void abandon(State& s, const std::string& panic, Outcome& o) {
  s.broken = "Tcl gave up (" + panic + "); nomec stopped this scene's Tcl here, and runs none of it after";
  o.problems.push_back({ProblemKind::Memory, *s.broken, 0, ""});
}

// Runs `text` at global level within the limits and guards; nullopt and `o` filled when the
// interpreter cannot run it (Tcl panicked now or earlier). The limits stay armed for `finish`.
std::optional<int> eval_guarded(State& s, const std::string& text, Outcome& o) {
  if (s.broken) {
    o.problems.push_back({ProblemKind::Memory, *s.broken, 0, ""});
    return std::nullopt;
  }
  Tcl_Obj* script = Tcl_NewStringObj(text.c_str(), static_cast<int>(text.size()));
  Tcl_IncrRefCount(script);
  arm_limits(s);
  arm_guard(s.guard);
  int rc = TCL_OK;
  std::string panic;
  if (!guarded_call(&panic, [&] { rc = Tcl_EvalObjEx(s.interp, script, TCL_EVAL_GLOBAL); })) {
    abandon(s, panic, o);
    return std::nullopt;  // the script object stays: the abandoned interpreter may hold it
  }
  Tcl_DecrRefCount(script);
  return rc;
}

// Runs `touch` (which reads, sets or traces variables, so may run the scene's traces)
// within the limits and guards; false when the interpreter is or becomes abandoned.
template <typename F>
bool touch_guarded(State& s, F&& touch) {
  if (s.broken) return false;
  arm_limits(s);
  arm_guard(s.guard);
  std::string panic;
  Outcome ignored;
  if (!guarded_call(&panic, touch)) {
    abandon(s, panic, ignored);
    return false;
  }
  disarm_limits(s);
  s.refusal.reset();
  s.guard.refusal.reset();
  Tcl_ResetResult(s.interp);
  return true;
}

// Tk's scale follows its variable: a script that sets the variable after making the scale
// (`scale … -variable x0`, then `set x0 1.0`) moves the slider, rounded to its resolution
// and clamped to its range as when it was made; a value given from outside (`-D`) stays.
void refresh_sliders(State& s) {
  if (s.sliders.empty() || s.broken) return;
  touch_guarded(s, [&] {
    for (Slider& sl : s.sliders) {
      const char* cur = Tcl_GetVar2(s.interp, sl.variable.c_str(), nullptr, TCL_GLOBAL_ONLY);
      if (cur == nullptr) continue;
      char* end = nullptr;
      const double v = std::strtod(cur, &end);
      if (end == cur || !std::isfinite(v)) continue;
      if (std::optional<double> given = s.preset ? s.preset(sl.variable, sl.from, sl.to) : std::nullopt) {
        if (v != *given) {
          char text[64];
          std::snprintf(text, sizeof text, "%.17g", *given);
          Tcl_SetVar2(s.interp, sl.variable.c_str(), nullptr, text, TCL_GLOBAL_ONLY);
        }
        sl.value = *given;
        continue;
      }
      if (v == sl.value) continue;
      double r = v;
      if (sl.resolution > 0) r = sl.from + std::round((v - sl.from) / sl.resolution) * sl.resolution;
      r = std::clamp(r, std::min(sl.from, sl.to), std::max(sl.from, sl.to));
      if (std::fabs(r - v) > 1e-12) {
        char text[64];
        std::snprintf(text, sizeof text, "%.*f", sl.resolution > 0 ? decimals_of(sl.resolution) : 6, r);
        Tcl_SetVar2(s.interp, sl.variable.c_str(), nullptr, text, TCL_GLOBAL_ONLY);
        r = std::strtod(text, nullptr);
        sl.rounded = true;
        sl.written = v;
      } else {
        sl.rounded = false;
      }
      sl.value = r;
    }
  });
}

}  // namespace

Outcome Engine::run(std::string_view script) {
  std::string text = normalize_newlines(script);
  std::vector<std::string> reads;
  s_->reads = &reads;
  Outcome failed;
  std::optional<int> rc = eval_guarded(*s_, text, failed);
  Outcome o = rc ? finish(*s_, *rc) : std::move(failed);
  s_->reads = nullptr;
  o.reads = std::move(reads);
  if (rc) refresh_sliders(*s_);
  return o;
}

Outcome Engine::run_tracking_writes(std::string_view script) {
  if (s_->broken) return run(script);
  constexpr int kFlags = TCL_GLOBAL_ONLY | TCL_TRACE_WRITES;
  std::vector<std::string> before;
  if (!touch_guarded(*s_, [&] {
        before = globals(*s_);
        for (const std::string& g : before) Tcl_TraceVar2(s_->interp, g.c_str(), nullptr, kFlags, write_trace, s_.get());
      })) {
    return run(script);  // says why
  }
  std::vector<std::string> writes;
  s_->writes = &writes;
  Outcome o = run(script);
  s_->writes = nullptr;
  std::vector<std::string> after;
  if (!touch_guarded(*s_, [&] {
        for (const std::string& g : before) Tcl_UntraceVar2(s_->interp, g.c_str(), nullptr, kFlags, write_trace, s_.get());
        after = globals(*s_);
      })) {
    return o;  // the interpreter may not be touched again
  }
  for (std::string& g : after) {
    if (std::find(before.begin(), before.end(), g) == before.end() &&
        std::find(writes.begin(), writes.end(), g) == writes.end()) {
      writes.push_back(std::move(g));
    }
  }
  std::erase_if(writes, [](const std::string& w) { return w == "errorInfo" || w == "errorCode"; });
  o.writes = std::move(writes);
  return o;
}

Outcome Engine::value(std::string_view script) {
  std::string text = normalize_newlines(script);
  std::vector<std::string> reads;
  s_->reads = &reads;
  Outcome failed;
  std::optional<int> rc = eval_guarded(*s_, text, failed);
  if (!rc) {
    s_->reads = nullptr;
    return failed;
  }
  Outcome o = finish(*s_, *rc);
  s_->reads = nullptr;
  o.reads = std::move(reads);
  if (!o.ok) return o;
  char* end = nullptr;
  o.number = std::strtod(o.result.c_str(), &end);
  while (end != nullptr && *end == ' ') ++end;
  if (o.result.empty() || end == o.result.c_str() || (end != nullptr && *end != '\0') || !std::isfinite(o.number)) {
    o.ok = false;
    o.problems.push_back({ProblemKind::Error, "the value is `" + o.result + "`, not a number", 0, ""});
  }
  return o;
}

std::optional<std::string> Engine::get(std::string_view name) const {
  std::optional<std::string> out;
  const std::string n(name);
  touch_guarded(*s_, [&] {
    if (const char* v = Tcl_GetVar2(s_->interp, n.c_str(), nullptr, TCL_GLOBAL_ONLY)) out = std::string(v);
  });
  return out;
}

void Engine::set(std::string_view name, std::string_view value) {
  const std::string n(name), v(value);
  touch_guarded(*s_, [&] { Tcl_SetVar2(s_->interp, n.c_str(), nullptr, v.c_str(), TCL_GLOBAL_ONLY); });
}

void Engine::watch(const std::string& name) {
  if (s_->broken || !s_->watched.insert(name).second) return;
  touch_guarded(*s_, [&] {
    Tcl_TraceVar2(s_->interp, name.c_str(), nullptr, TCL_GLOBAL_ONLY | TCL_TRACE_READS, read_trace, s_.get());
  });
}

void Engine::set_time_limit(int milliseconds) { s_->limits.milliseconds = milliseconds; }

const std::vector<Slider>& Engine::sliders() const { return s_->sliders; }
const std::vector<SlideCall>& Engine::slide_calls() const { return s_->calls; }

std::vector<Problem> Engine::take_notes() {
  std::vector<Problem> out;
  out.swap(s_->notes);
  return out;
}

void finish_thread() {
  if (!t_made_interp) return;
  t_made_interp = false;
  Tcl_FinalizeThread();
}

}  // namespace nomec::tcl
