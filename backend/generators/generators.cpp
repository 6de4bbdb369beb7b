// Dispatch from catalogue kinds to the generator implementations (a table generated from
// ir/generators.def); the only place where internal failures become `GeneratorError`s.
#include "backend/generators/generators.h"

#include <new>

#include "backend/generators/impl.h"

namespace nomec::backend {

namespace {

using Maker = Generated (*)(const detail::ArgReader&);

constexpr Maker kMakers[] = {
#define NOMEC_GENERATOR(Kind, Keyword, Output, Summary) &detail::make_##Kind,
#include "ir/generators.def"
};
static_assert(std::size(kMakers) == ir::kGenKindCount);

}  // namespace

GeneratorInput GeneratorInput::for_kind(ir::GenKind kind, Dialect dialect) {
  GeneratorInput in;
  in.kind = kind;
  in.dialect = dialect;
  const size_t n = ir::generator(kind).args.size();
  in.numbers.resize(n);
  in.flags.resize(n, 0);
  in.functions.resize(n);
  return in;
}

GeneratorResult generate(const GeneratorInput& input) {
  GeneratorResult result;
  // The domain rules first, with the same messages `--check` gives for known values.
  if (auto problem = ir::check_arguments(input.kind, input.dialect, input.numbers)) {
    result.error = GeneratorError{problem->arg, problem->message, problem->hint};
    return result;
  }
  try {
    detail::ArgReader reader(input);
    result.value = kMakers[static_cast<size_t>(input.kind)](reader);
  } catch (const detail::Failure& f) {
    result.error = f.error;
  } catch (const std::bad_alloc&) {
    result.error = GeneratorError{ir::kNoArg,
                                  "out of memory generating `" + std::string(ir::generator(input.kind).keyword) + "`", ""};
  }
  return result;
}

}  // namespace nomec::backend
