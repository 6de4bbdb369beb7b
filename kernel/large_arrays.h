// Allocation helpers for the kernel's large flat arrays (a subdivision level of a big
// mesh writes hundreds of megabytes). Most of the time spent filling fresh memory goes to
// the operating system mapping it in one 4 KiB page at a time; asking for transparent
// huge pages on the large buffers cuts that per-page cost by a factor of up to 512.
#pragma once

#include <cstddef>
#include <vector>

namespace nomec::kernel {

/// Buffers below this size are left alone (the advice only pays off for whole 2 MiB
/// pages, and small buffers usually come from reused heap memory anyway).
inline constexpr size_t kHugePageAdviceBytes = size_t{4} << 20;

/// Advises the operating system that the 2 MiB-aligned pages inside [data, data + bytes)
/// may be backed by huge pages. Only a hint: a no-op below `kHugePageAdviceBytes`, on
/// systems without transparent huge pages, or when the advice is refused.
void advise_huge_pages(const void* data, size_t bytes);

/// Reserves room for exactly `n` elements (when `v` has less) and advises huge pages for
/// the buffer before it is first written.
template <typename T>
void reserve_large(std::vector<T>& v, size_t n) {
  if (v.capacity() >= n) return;
  v.reserve(n);
  advise_huge_pages(v.data(), n * sizeof(T));
}

/// `reserve_large` followed by `resize(n)` (value-initialising the new elements).
template <typename T>
void resize_large(std::vector<T>& v, size_t n) {
  reserve_large(v, n);
  v.resize(n);
}

}  // namespace nomec::kernel
