// Internal: one geometry function per entry of the generator catalogue, `make_<Kind>`,
// building a `Generated` from the arguments or failing with `detail::fail` (see common.h).
// Declared from ir/generators.def, so a catalogue entry without its function does not link.
#pragma once

#include "backend/generators/common.h"

namespace nomec::backend::detail {

#define NOMEC_GENERATOR(Kind, Keyword, Output, Summary) Generated make_##Kind(const ArgReader& a);
#include "ir/generators.def"

}  // namespace nomec::backend::detail
