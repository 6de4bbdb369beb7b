// Values the IR cannot compute itself: an `External` expression (ir.h) names a script that
// the code which made the module evaluates, through this interface, whenever the module's
// parameters change. SLIDE's `{if {$par_n >= 2} {expr $SLF_FULL} else …}` is one: its Tcl
// is run by frontend/check over frontend/tcl, which ir/ must not know (ARCHITECTURE.md,
// layers). The module holds its evaluator by shared_ptr, so copies of a module share it.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "ir/ids.h"

namespace nomec::ir {

/// The value of an external script, or why it has none (e.g. "Tcl error in this value:
/// divide by zero").
struct ExternalResult {
  double value = 0;
  bool ok = false;
  std::string problem;
};

/// Evaluates the external scripts of one module. Implementations must be safe to call from
/// any thread, one call at a time or concurrently, and must not throw.
class ExternalEvaluator {
 public:
  virtual ~ExternalEvaluator() = default;
  /// The parameters every evaluation is given the current values of, in this order.
  virtual std::span<const NodeId> inputs() const = 0;
  /// Script `script`'s value when the parameters `inputs()` have the values `values`.
  virtual ExternalResult evaluate(uint32_t script, std::span<const double> values) const = 0;
  /// The script as written, for dumps and messages.
  virtual std::string_view text(uint32_t script) const = 0;
};

}  // namespace nomec::ir
