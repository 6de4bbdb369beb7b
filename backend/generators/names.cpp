// Vertex-name aliases of the generators (NOME3 `v1_`/`v2_`/`v3_` → 2016 `hc`/`bc`/`lc`).
#include "backend/generators/names.h"

namespace nomec::backend {

std::vector<std::pair<std::string, std::string>> vertex_aliases(std::string_view keyword) {
  if (keyword == "funnel") {
    return {{"v2_", "bc"}, {"v1_", "hc"}};
  }
  if (keyword == "tunnel") {
    return {{"v2_", "bc"}, {"v1_", "hc"}, {"v3_", "lc"}};
  }
  return {};
}

std::string canonical_vertex_name(std::string_view keyword, std::string_view name) {
  for (const auto& [alias, canonical] : vertex_aliases(keyword)) {
    if (name.size() > alias.size() && name.substr(0, alias.size()) == alias) {
      return canonical + std::string(name.substr(alias.size()));
    }
  }
  return std::string(name);
}

}  // namespace nomec::backend
