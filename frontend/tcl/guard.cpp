// Resource guards of the embedded interpreter (see guard.h).
#include "frontend/tcl/guard.h"

#include <tclTomMath.h>

#include <malloc.h>

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define NOMEC_TCL_SANITIZED 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define NOMEC_TCL_SANITIZED 1
#endif
#ifdef NOMEC_TCL_SANITIZED
#include <sanitizer/allocator_interface.h>
#endif

#include <algorithm>
#include <csetjmp>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string_view>

namespace nomec::tcl {

namespace {

constexpr int64_t kHuge = int64_t{1} << 50;  // saturation of size arithmetic

int64_t add(int64_t a, int64_t b) { return std::min(kHuge, a + b); }
int64_t mul(int64_t a, int64_t b) {
  if (a <= 0 || b <= 0) return 0;
  return a > kHuge / b ? kHuge : a * b;
}

// The size of a value without building its string: its characters when it has them, its
// element count when it is a list, else a small number (numbers and other internal forms).
int64_t size_of(Tcl_Obj* o) {
  if (o->bytes != nullptr) return o->length;
  if (o->typePtr != nullptr && std::strcmp(o->typePtr->name, "list") == 0) {
    int n = 0;
    if (Tcl_ListObjLength(nullptr, o, &n) == TCL_OK) return n;
  }
  return 32;
}

// Decimal digits of a whole number held as a Tcl bignum without its text; 0 for anything else.
int64_t bignum_digits(Tcl_Obj* o) {
  if (o->bytes != nullptr || o->typePtr == nullptr || std::strcmp(o->typePtr->name, "bignum") != 0) return 0;
  mp_int big;
  if (Tcl_GetBignumFromObj(nullptr, o, &big) != TCL_OK) return 0;
  const int bits = mp_count_bits(&big);
  mp_clear(&big);
  return static_cast<int64_t>(bits * 0.30102999566398120) + 1;
}

int64_t sum_of(int objc, Tcl_Obj* const objv[], int from) {
  int64_t total = 0;
  for (int i = from; i < objc; ++i) total = add(total, size_of(objv[i]));
  return total;
}

// Digits at `p` as a saturated number; advances `p`.
int64_t digits(const char*& p) {
  int64_t v = 0;
  while (*p >= '0' && *p <= '9') v = std::min(kHuge, v * 10 + (*p++ - '0'));
  return v;
}

int64_t wide_arg(Tcl_Obj* o) {
  Tcl_WideInt w = 0;
  if (Tcl_GetWideIntFromObj(nullptr, o, &w) != TCL_OK) return 0;
  return w < 0 ? 0 : std::min<int64_t>(w, kHuge);
}

// `format FMT ARG…`: the format's text, each field's width or precision, and its argument.
int64_t predict_format(Tcl_Interp*, int objc, Tcl_Obj* const objv[]) {
  if (objc < 2) return 0;
  const char* p = Tcl_GetString(objv[1]);
  int64_t total = objv[1]->length;
  int next = 2;
  while ((p = std::strchr(p, '%')) != nullptr) {
    ++p;
    if (*p == '%') {
      ++p;
      continue;
    }
    const char* save = p;
    digits(p);
    if (*p == '$') {
      ++p;  // an XPG position
    } else {
      p = save;
    }
    while (*p != '\0' && std::strchr("-+ 0#", *p) != nullptr) ++p;
    int64_t width = *p == '*' ? (++p, next < objc ? wide_arg(objv[next++]) : 0) : digits(p);
    if (*p == '.') {
      ++p;
      width = std::max(width, *p == '*' ? (++p, next < objc ? wide_arg(objv[next++]) : 0) : digits(p));
    }
    while (*p != '\0' && std::strchr("hlLqjzt", *p) != nullptr) ++p;
    total = add(total, width);
    if (*p != '\0' && next < objc) total = add(total, size_of(objv[next++]));
    if (*p != '\0') ++p;
  }
  return total;
}

// `binary format FMT ARG…`: every count in the format, at 8 bytes each, and the arguments.
int64_t predict_binary_format(Tcl_Interp*, int objc, Tcl_Obj* const objv[]) {
  if (objc < 2) return 0;
  int64_t total = 0;
  for (const char* p = Tcl_GetString(objv[1]); *p != '\0';) {
    if (*p >= '0' && *p <= '9') {
      total = add(total, mul(digits(p), 8));
    } else {
      ++p;
    }
  }
  return add(total, mul(sum_of(objc, objv, 2), 8));
}

int64_t predict_string_repeat(Tcl_Interp*, int objc, Tcl_Obj* const objv[]) {
  return objc == 3 ? mul(size_of(objv[1]), wide_arg(objv[2])) : 0;
}

int64_t predict_lrepeat(Tcl_Interp*, int objc, Tcl_Obj* const objv[]) {
  return objc >= 2 ? mul(wide_arg(objv[1]), objc - 2) : 0;
}

int64_t variable_size(Tcl_Interp* interp, Tcl_Obj* name) {
  Tcl_Obj* v = Tcl_ObjGetVar2(interp, name, nullptr, 0);
  return v == nullptr ? 0 : size_of(v);
}

int64_t predict_append(Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  return objc >= 2 ? add(variable_size(interp, objv[1]), sum_of(objc, objv, 2)) : 0;
}

int64_t predict_lappend(Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  return objc >= 2 ? add(variable_size(interp, objv[1]), objc - 2) : 0;
}

int64_t predict_concat(Tcl_Interp*, int objc, Tcl_Obj* const objv[]) { return add(sum_of(objc, objv, 1), objc); }

int64_t predict_join(Tcl_Interp*, int objc, Tcl_Obj* const objv[]) {
  if (objc < 2) return 0;
  int n = 0;
  Tcl_Obj** elems = nullptr;
  if (Tcl_ListObjGetElements(nullptr, objv[1], &n, &elems) != TCL_OK) return 0;
  const int64_t sep = objc > 2 ? size_of(objv[2]) : 1;
  return add(sum_of(n, elems, 0), mul(n, sep));
}

// `string map ?-nocase? MAP S`: every character of S may become the longest replacement.
int64_t predict_string_map(Tcl_Interp*, int objc, Tcl_Obj* const objv[]) {
  if (objc < 3) return 0;
  int n = 0;
  Tcl_Obj** elems = nullptr;
  if (Tcl_ListObjGetElements(nullptr, objv[objc - 2], &n, &elems) != TCL_OK) return 0;
  int64_t longest = 1;
  for (int i = 1; i < n; i += 2) longest = std::max(longest, size_of(elems[i]));
  return mul(size_of(objv[objc - 1]), longest);
}

// `regsub ?switches? EXP S SUB ?VAR?`: every position of S may match and become SUB, with
// each `&` or `\N` in SUB standing for up to all of S.
int64_t predict_regsub(Tcl_Interp*, int objc, Tcl_Obj* const objv[]) {
  int i = 1;
  while (i < objc && Tcl_GetString(objv[i])[0] == '-') {
    if (std::strcmp(Tcl_GetString(objv[i]), "--") == 0) {
      ++i;
      break;
    }
    i += std::strcmp(Tcl_GetString(objv[i]), "-start") == 0 ? 2 : 1;
  }
  if (i + 2 >= objc) return 0;
  const int64_t s = size_of(objv[i + 1]);
  const char* sub = Tcl_GetString(objv[i + 2]);
  int64_t refs = 0;
  for (const char* p = sub; *p != '\0'; ++p) {
    if (*p == '&' || (*p == '\\' && p[1] >= '0' && p[1] <= '9')) ++refs;
  }
  return add(s, mul(s + 1, add(objv[i + 2]->length, mul(refs, s))));
}

using Predict = int64_t (*)(Tcl_Interp*, int, Tcl_Obj* const[]);

struct Wrapped {
  Guard* guard;
  const char* shown;  // the command as a scene writes it
  Predict predict;
  Tcl_ObjCmdProc* proc;
  ClientData data;
};

int refuse_size(Guard& g, Tcl_Interp* interp, const std::string& msg) {
  g.refusal = msg;
  Tcl_SetObjResult(interp, Tcl_NewStringObj(msg.c_str(), -1));
  Tcl_SetErrorCode(interp, "NOMEC", "MEMORY", nullptr);
  return TCL_ERROR;
}

std::string too_big(const char* what, int64_t size) {
  char text[320];
  std::snprintf(text, sizeof text,
                "%s would build a value of %s%lld characters or list elements; a SLIDE scene's Tcl may build values of "
                "at most %lld",
                what, size >= kHuge ? "more than " : "", static_cast<long long>(size >= kHuge ? kHuge : size),
                static_cast<long long>(kMaxValue));
  return text;
}

int wrapped_cmd(ClientData data, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  auto* w = static_cast<Wrapped*>(data);
  const int64_t size = w->predict(interp, objc, objv);
  if (size > kMaxValue) return refuse_size(*w->guard, interp, too_big(w->shown, size));
  const int rc = w->proc(w->data, interp, objc, objv);
  if (const int64_t made = rc == TCL_OK ? size_of(Tcl_GetObjResult(interp)) : 0; made > kMaxValue) {
    return refuse_size(*w->guard, interp, too_big(w->shown, made));
  }
  return rc;
}

void free_wrapped(ClientData data) { delete static_cast<Wrapped*>(data); }

int trace_cmd(ClientData data, Tcl_Interp* interp, int, const char* command, Tcl_Command, int objc,
              Tcl_Obj* const objv[]) {
  auto& g = *static_cast<Guard*>(data);
  std::string_view name = objc > 0 ? Tcl_GetString(objv[0]) : std::string_view(command);
  if (objc > kMaxValue) return refuse_size(g, interp, too_big(("`" + std::string(name) + "` with its arguments").c_str(), objc));
  for (int i = 0; i < objc; ++i) {
    if (size_of(objv[i]) > kMaxValue) {
      return refuse_size(g, interp, too_big(("an argument of `" + std::string(name) + "`").c_str(), size_of(objv[i])));
    }
    if (auto msg = too_many_digits(objv[i], ("an argument of `" + std::string(name) + "`").c_str())) {
      return refuse_size(g, interp, *msg);
    }
  }
  if ((++g.commands & 127) == 0) {  // a few hundred megabytes take few commands (`zlib inflate`)
    const size_t now = heap_in_use();
    if (now > g.baseline + kMaxGrowth) {
      return refuse_size(g, interp,
                         "the scene's Tcl holds " + std::to_string((now - g.baseline) >> 20) +
                             " MB more than when the script started; a SLIDE scene's Tcl may use at most " +
                             std::to_string(kMaxGrowth >> 20) + " MB");
    }
  }
  return TCL_OK;
}

thread_local std::jmp_buf* t_jump = nullptr;
thread_local char t_panic[512];

void on_panic(const char* format, ...) {
  va_list ap;
  va_start(ap, format);
  std::vsnprintf(t_panic, sizeof t_panic, format, ap);
  va_end(ap);
  if (t_jump != nullptr) std::longjmp(*t_jump, 1);
  std::fprintf(stderr, "Tcl panic: %s\n", t_panic);
  std::abort();
}

}  // namespace

std::optional<std::string> too_many_digits(Tcl_Obj* o, const char* what) {
  const int64_t digits = bignum_digits(o);
  if (digits <= kMaxDigits) return std::nullopt;
  return std::string(what) + " is a whole number of about " + std::to_string(digits) +
         " digits; a SLIDE scene's Tcl may use whole numbers of at most " + std::to_string(kMaxDigits) +
         " digits (write a floating-point number, e.g. `10.0**400`, for a large value)";
}

size_t heap_in_use() {
#ifdef NOMEC_TCL_SANITIZED
  return __sanitizer_get_current_allocated_bytes();  // the sanitizer's allocator, not glibc's
#else
  // The Tcl worker allocates with the C library's malloc (it is not linked with jemalloc),
  // whose counters these are.
  struct mallinfo2 m = mallinfo2();
  return m.uordblks + m.hblkhd;
#endif
}

void install_guards(Guard& g) {
  static const struct {
    const char* command;
    const char* shown;
    Predict predict;
  } kWrapped[] = {
      {"::tcl::string::repeat", "`string repeat`", predict_string_repeat},
      {"::tcl::string::cat", "`string cat`", predict_concat},
      {"::tcl::string::map", "`string map`", predict_string_map},
      {"::tcl::binary::format", "`binary format`", predict_binary_format},
      {"lrepeat", "`lrepeat`", predict_lrepeat},
      {"format", "`format`", predict_format},
      {"append", "`append`", predict_append},
      {"lappend", "`lappend`", predict_lappend},
      {"concat", "`concat`", predict_concat},
      {"join", "`join`", predict_join},
      {"regsub", "`regsub`", predict_regsub},
  };
  Tcl_SetPanicProc(on_panic);
  for (const auto& w : kWrapped) {
    Tcl_CmdInfo info;
    if (Tcl_GetCommandInfo(g.interp, w.command, &info) == 0 || info.objProc == nullptr) continue;
    auto* data = new Wrapped{&g, w.shown, w.predict, info.objProc, info.objClientData};
    Tcl_CreateObjCommand(g.interp, w.command, wrapped_cmd, data, free_wrapped);
  }
  // No TCL_ALLOW_INLINE_COMPILATION: every command is invoked, so it passes this trace and
  // Tcl's limit checks (compiled `set s $s$s` would otherwise pass neither).
  Tcl_CreateObjTrace(g.interp, 0, 0, trace_cmd, &g, nullptr);
}

void arm_guard(Guard& g) {
  g.refusal.reset();
  g.baseline = heap_in_use();
}

bool guarded_call_raw(void (*fn)(void*), void* arg, std::string* panic_message) {
  std::jmp_buf here;
  std::jmp_buf* const outer = t_jump;
  if (setjmp(here) != 0) {
    t_jump = outer;
    *panic_message = t_panic;
    return false;
  }
  t_jump = &here;
  fn(arg);
  t_jump = outer;
  return true;
}

}  // namespace nomec::tcl
