// libFuzzer target for SLIDE's Tcl as nomec runs it: any bytes are checked as a `.slf` file
// whose Tcl runs in the Tcl worker process (frontend/tcl/interp.h) under a small budget,
// so whatever the scene's Tcl does — crash Tcl, hang, exhaust memory, attack the sandbox —
// happens in the worker, and the fuzzer looks at what nomec makes of it: no crash,
// sanitizer report or exception in nomec, every diagnostic range inside its file, the
// slider moves of the values that follow sliders answered. The same bytes are also read as
// every frame of the worker protocol (a worker that lies must not overread nomec).
// Safe only because Tcl is out of process: an in-process Tcl would turn every deep `regexp`
// into a finding of Tcl's, not of nomec's.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "frontend/check/check.h"
#include "frontend/tcl/protocol.h"
#include "fuzz/ranges.h"
#include "ir/ir.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  namespace proto = nomec::tcl::protocol;
  (void)proto::decode_reply(bytes);
  (void)proto::decode_request(bytes);
  (void)proto::decode_callback(bytes);
  (void)proto::decode_callback_reply(bytes);

  nomec::SourceManager sources;
  nomec::DiagnosticEngine diags;
  nomec::CheckOptions options;
  options.dialect = nomec::Dialect::Slide;
  options.tcl_milliseconds = 150;  // a scene that loops costs the fuzzer this, not 10 s
  options.tcl_move_milliseconds = 50;
  options.read_file = [](const std::string& path) -> std::optional<std::string> {
    if (path.ends_with("lib.tcl")) return std::string("proc twice {x} { expr {2 * $x} }\nset from_lib 1\n");
    return std::nullopt;
  };
  try {
    nomec::CheckResult r = nomec::check_source(sources, "fuzz.slf", std::string(bytes), options, diags);
    // Move every slider to its other end and evaluate every value that follows sliders.
    nomec::ir::Module& m = r.module;
    for (size_t i = 0; i < m.nodes.size(); ++i) {
      const nomec::ir::NodeId id(static_cast<int32_t>(i));
      if (m.node(id).kind != nomec::ir::NodeKind::Param) continue;
      nomec::ir::ParamData& p = m.param(id);
      p.value = p.value == p.max ? p.min : p.max;
    }
    for (size_t i = 0; i < m.exprs.size(); ++i) {
      if (m.exprs[i].kind != nomec::ir::ExprKind::External) continue;
      (void)nomec::ir::evaluate(m, nomec::ir::ExprId(static_cast<int32_t>(i)));
    }
  } catch (...) {
    std::abort();  // "No stage throws" (ARCHITECTURE.md)
  }
  nomec::fuzz::abort_unless_inside(sources, diags);
  return 0;
}
