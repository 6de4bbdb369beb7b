// Dispatch from NOME keywords to the generator implementations; the only place where
// internal failures become `GeneratorError`s.
#include "backend/generators/generators.h"

#include <array>
#include <exception>
#include <new>
#include <utility>

#include "backend/generators/domain.h"
#include "backend/generators/impl.h"

namespace nomec::backend {
namespace {

using Maker = Generated (*)(const detail::ArgReader&);

struct Entry {
  std::string_view keyword;
  Maker make;
};

constexpr std::array kGenerators = {
    Entry{"funnel", &detail::make_funnel},
    Entry{"tunnel", &detail::make_tunnel},
    Entry{"circle", &detail::make_circle},
    Entry{"mobiusstrip", &detail::make_mobiusstrip},
    Entry{"rimribbon", &detail::make_rimribbon},
    Entry{"torus", &detail::make_torus},
    Entry{"sphere", &detail::make_sphere},
    Entry{"ellipsoid", &detail::make_ellipsoid},
    Entry{"cylinder", &detail::make_cylinder},
    Entry{"hyperboloid", &detail::make_hyperboloid},
    Entry{"dupin", &detail::make_dupin},
    Entry{"torusknot", &detail::make_torusknot},
    Entry{"helix", &detail::make_helix},
    Entry{"spiral", &detail::make_spiral},
    Entry{"genparametricsurf", &detail::make_genparametricsurf},
    Entry{"gencartesiansurf", &detail::make_gencartesiansurf},
    Entry{"genimplicitsurf", &detail::make_genimplicitsurf},
    Entry{"beziercurve", &detail::make_beziercurve},
    Entry{"bspline", &detail::make_bspline},
    Entry{"bsplinecurve", &detail::make_bspline},
};

const Entry* find(std::string_view keyword) {
  for (const Entry& e : kGenerators) {
    if (e.keyword == keyword) {
      return &e;
    }
  }
  return nullptr;
}

}  // namespace

bool is_generator(std::string_view keyword) { return find(keyword) != nullptr; }

GeneratorResult generate(std::string_view keyword, const GeneratorArgs& args) {
  GeneratorResult result;
  const Entry* e = find(keyword);
  if (e == nullptr) {
    result.error = GeneratorError{"", "unknown generator `" + std::string(keyword) + "`", ""};
    return result;
  }
  // The domain rules first, with the same messages `--check` gives for known values.
  if (auto problem = check_generator_arguments(keyword, args.dialect, args.numbers)) {
    result.error = GeneratorError{problem->argument, problem->message, problem->hint};
    return result;
  }
  try {
    detail::ArgReader reader(args);
    result.value = e->make(reader);
  } catch (const detail::Failure& f) {
    result.error = f.error;
  } catch (const std::bad_alloc&) {
    result.error = GeneratorError{"", "out of memory generating `" + std::string(keyword) + "`", ""};
  }
  return result;
}

}  // namespace nomec::backend
