// Id<Tag>: the one typed index of the project. A file of the SourceManager, a statement of
// the syntax tree, a node or expression of the IR and a vertex of a kernel mesh are each an
// int32 index into their owner's arrays, passed by value, with an explicit `None()` (-1);
// the tag type keeps an index of one kind from being used as another.
#pragma once

#include <compare>
#include <cstddef>
#include <cstdint>
#include <functional>

namespace nomec {

/// A typed int32 index. `Tag` only distinguishes the kinds; `None()` is -1.
template <typename Tag>
struct Id {
  int32_t index = -1;

  constexpr Id() = default;
  constexpr explicit Id(int32_t i) : index(i) {}
  static constexpr Id None() { return Id(); }
  constexpr bool is_valid() const { return index >= 0; }
  constexpr explicit operator bool() const { return is_valid(); }
  friend constexpr bool operator==(Id a, Id b) = default;
  friend constexpr auto operator<=>(Id a, Id b) = default;
};

}  // namespace nomec

template <typename Tag>
struct std::hash<nomec::Id<Tag>> {
  size_t operator()(nomec::Id<Tag> id) const noexcept { return std::hash<int32_t>()(id.index); }
};
