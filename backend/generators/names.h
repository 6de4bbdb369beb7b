// Vertex-name aliases of generators: NOME3 names some generated vertices differently from
// the 2016 program (a funnel's base ring is `bc0…` in 2016 and `v2_0…` in NOME3). The soup
// carries the canonical (2016) names; the backend resolves an alias by rewriting its prefix.
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace nomec::backend {

/// Alias prefix → canonical prefix for `keyword`, e.g. for `funnel`
/// {{"v2_", "bc"}, {"v1_", "hc"}}: `v2_3` names the vertex `bc3`. Empty for generators
/// without aliases.
std::vector<std::pair<std::string, std::string>> vertex_aliases(std::string_view keyword);

/// The canonical name of `name` for `keyword` (`v1_3` → `hc3` for a funnel); `name`
/// itself when no alias prefix applies.
std::string canonical_vertex_name(std::string_view keyword, std::string_view name);

}  // namespace nomec::backend
