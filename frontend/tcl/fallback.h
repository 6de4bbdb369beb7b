// Tcl text nomec runs in every SLIDE interpreter: the prelude (the values the SLIDE viewer
// exports, slide.md §5–§6, and the `slideui`/`parselib` packages, whose code is lost, with
// the values nomec chooses, docs/dialects.md) and its own versions of the SLIDE helper
// files (`SLIDEUI.tcl`, `MATH.tcl`, `SLFCONSTS.tcl`, `MOVIE.tcl`), written from slide.md §7
// for scenes whose helper files are not next to them.
#pragma once

#include <optional>
#include <string_view>

namespace nomec::tcl {

/// Run once when an interpreter is made.
std::string_view prelude_script();
/// nomec's version of a SLIDE helper file (by base name), or nullopt for other files.
std::optional<std::string_view> fallback_script(std::string_view base_name);

}  // namespace nomec::tcl
