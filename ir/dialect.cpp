// Dialect names (see dialect.h).
#include "ir/dialect.h"

namespace nomec {

std::string_view dialect_name(Dialect d) {
  switch (d) {
    case Dialect::Nome: return "nome";
    case Dialect::Nome2: return "nome2";
    case Dialect::Nome3: return "nome3";
    case Dialect::Slide: return "slide";
  }
  return "nome";
}

std::optional<Dialect> dialect_by_name(std::string_view name) {
  if (name == "nome") return Dialect::Nome;
  if (name == "nome2") return Dialect::Nome2;
  if (name == "nome3") return Dialect::Nome3;
  if (name == "slide") return Dialect::Slide;
  return std::nullopt;
}

}  // namespace nomec
