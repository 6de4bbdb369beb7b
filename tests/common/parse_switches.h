// One of the parse's test switches (`ParseSwitches`, frontend/parse/piece.h: the reference
// lexer, the tree-based builder, remembered predictions, resumed recovery) set on this
// thread for a scope, for the differential tests that parse a text both ways; what was set
// before is put back when the scope ends.
#pragma once

#include "frontend/parse/piece.h"

namespace nomec::testing_switches {

class ScopedParseSwitch {
 public:
  /// e.g. `ScopedParseSwitch tree(&ParseSwitches::tree_builder, true);`
  ScopedParseSwitch(bool parse_detail::ParseSwitches::*which, bool value)
      : saved_(parse_detail::ParseSwitches::current()) {
    parse_detail::ParseSwitches set = saved_;
    set.*which = value;
    set.apply();
  }
  ~ScopedParseSwitch() { saved_.apply(); }
  ScopedParseSwitch(const ScopedParseSwitch&) = delete;
  ScopedParseSwitch& operator=(const ScopedParseSwitch&) = delete;

 private:
  parse_detail::ParseSwitches saved_;
};

}  // namespace nomec::testing_switches
