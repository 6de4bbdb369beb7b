// No remembered walks: linked into `prediction_seed_tool`, which makes the real ones
// (prediction_seed.h).
#include "frontend/parse/prediction_seed.h"

namespace nomec::parse_detail {

std::span<const uint16_t> prediction_seed() { return {}; }

}  // namespace nomec::parse_detail
