// Allocation helpers for the kernel's large flat arrays (a subdivision level of a big
// mesh writes hundreds of megabytes). Most of the time spent filling fresh memory goes to
// the operating system mapping it in one 4 KiB page at a time; asking for transparent
// huge pages on the large buffers cuts that per-page cost by a factor of up to 512.
#pragma once

#include <cstddef>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

namespace nomec::kernel {

/// Buffers below this size are left alone (the advice only pays off for whole 2 MiB
/// pages, and small buffers usually come from reused heap memory anyway).
inline constexpr size_t kHugePageAdviceBytes = size_t{4} << 20;

/// Advises the operating system that the 2 MiB-aligned pages inside [data, data + bytes)
/// may be backed by huge pages. Only a hint: a no-op below `kHugePageAdviceBytes`, on
/// systems without transparent huge pages, or when the advice is refused.
void advise_huge_pages(const void* data, size_t bytes);

/// A `std::allocator` whose value-initialisation leaves the element as it is, so that
/// `resize(n)` of an `OverwriteVector` only allocates: no pass that fills the memory with
/// a value every element then loses (for a subdivision level, a fifth of the time).
/// Rationale: the element types are trivially copyable and destructible, i.e. implicit-
/// lifetime types, whose objects the allocation itself creates; every other `construct`
/// (copies, `resize(n, value)`, `assign`, `push_back`) is the usual one. Only for arrays
/// whose every element is written before it is read (see `resize_for_overwrite`).
template <typename T>
struct OverwriteAllocator : std::allocator<T> {
  static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>);
  template <typename U>
  struct rebind {
    using other = OverwriteAllocator<U>;
  };
  OverwriteAllocator() = default;
  template <typename U>
  OverwriteAllocator(const OverwriteAllocator<U>&) noexcept {}
  template <typename U>
  void construct(U*) noexcept {}
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

/// A vector whose `resize(n)` leaves the new elements for the caller to write.
template <typename T>
using OverwriteVector = std::vector<T, OverwriteAllocator<T>>;

/// Reserves room for exactly `n` elements (when `v` has less) and advises huge pages for
/// the buffer before it is first written.
template <typename T, typename A>
void reserve_large(std::vector<T, A>& v, size_t n) {
  if (v.capacity() >= n) return;
  v.reserve(n);
  advise_huge_pages(v.data(), n * sizeof(T));
}

/// `reserve_large` followed by `resize(n)`, value-initialising the new elements (for an
/// `OverwriteVector` too).
template <typename T, typename A>
void resize_large(std::vector<T, A>& v, size_t n) {
  reserve_large(v, n);
  if constexpr (std::is_same_v<A, OverwriteAllocator<T>>) {
    v.resize(n, T());
  } else {
    v.resize(n);
  }
}

/// `reserve_large` followed by a `resize(n)` that leaves the new elements unwritten: the
/// caller writes every one of them before anything reads it.
template <typename T>
void resize_for_overwrite(OverwriteVector<T>& v, size_t n) {
  reserve_large(v, n);
  v.resize(n);
}

}  // namespace nomec::kernel
