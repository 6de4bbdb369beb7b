// libFuzzer target for the front end: any bytes go through `nomec::check_source` as a NOME,
// NOME3 or SLIDE file (chosen by the first byte). The run must not crash, trip a sanitizer
// or throw, every diagnostic range (and its notes' and fix-its') must lie inside its file,
// and rendering a diagnostic must not fail. No file system access: includes and `.anom`
// base scenes are reported as unreadable, and SLIDE files' Tcl is not run (slide_fuzzer runs
// it through its worker; here a SLIDE text is checked as `--no-tcl` checks it). One check of
// each input, so it runs fast; parse_fuzzer holds the parser's equivalences.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "frontend/check/check.h"
#include "fuzz/ranges.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const char* const kPaths[] = {"fuzz.nome", "fuzz.nom", "fuzz.slf"};
  const char* path = kPaths[size > 0 ? data[0] % 3 : 0];
  const std::string text(reinterpret_cast<const char*>(data), size);
  nomec::SourceManager sources;
  nomec::DiagnosticEngine diags;
  nomec::CheckOptions options;
  options.read_file = [](const std::string&) -> std::optional<std::string> { return std::nullopt; };
  options.run_tcl = false;
  try {
    (void)nomec::check_source(sources, path, text, options, diags);
    diags.sort_and_dedupe();
  } catch (...) {
    std::abort();  // "No stage throws" (ARCHITECTURE.md)
  }
  for (const nomec::Diagnostic& d : diags.diagnostics()) {
    nomec::fuzz::abort_unless_inside(sources, d);
    // Rendering reads the source line under each range: exercise it too (the first few of
    // an input's diagnostics: the others take the same path).
    if (&d - diags.diagnostics().data() < 4) (void)nomec::render_text(sources, d, false, false);
  }
  return 0;
}
