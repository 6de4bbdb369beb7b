// SLIDE scenes shared by the tests that stop a scene's Tcl from the command line
// (tests/tcl/cli_test.cpp) and from the language server (tests/lsp/tcl_worker_test.cpp).
#pragma once

namespace nomec::testing_scenes {

// A slider whose variable has a write trace that never ends: every slider move runs it.
inline constexpr const char* kSliderTraceNeverEnds = R"(tclinit {
  set par_x 0.5
  scale .x -from 0 -to 1 -resolution 0.1 -variable par_x
  trace add variable par_x write {apply {args { while 1 {} }}}
}
point p0 (0 0 0) endpoint
point p1 ({if {$par_x > 0.2} {expr 1} else {expr 2}} 0 0) endpoint
point p2 (0 1 0) endpoint
face f (p0 p1 p2) endface
object o (f) endobject
instance o endinstance
)";

}  // namespace nomec::testing_scenes
