// SmallVec: a vector of trivially copyable elements that keeps its first N elements inside
// the object. The syntax tree's per-node lists (a statement's items, a list's elements, a
// call's arguments) are short, and a large document has tens of thousands of them: with
// std::vector each was a heap allocation when parsed, again each time the language server's
// parse cache assembled a document from its pieces, and a free when the tree was dropped.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <new>
#include <stdexcept>
#include <type_traits>
#include <utility>

namespace nomec {

template <typename T, uint32_t N>
class SmallVec {
  static_assert(std::is_trivially_copyable_v<T>, "SmallVec copies its elements bytewise");
  static_assert(N > 0);

 public:
  using value_type = T;
  using iterator = T*;
  using const_iterator = const T*;

  SmallVec() = default;
  SmallVec(std::initializer_list<T> init) { assign(init.begin(), init.size()); }
  SmallVec(const SmallVec& o) {
    if (o.is_inline()) {
      copy_inline_room(o);
      size_ = o.size_;
    } else {
      assign(o.data(), o.size_);
    }
  }
  SmallVec(SmallVec&& o) noexcept { take(o); }
  SmallVec& operator=(const SmallVec& o) {
    if (this != &o) {
      size_ = 0;
      assign(o.data(), o.size_);
    }
    return *this;
  }
  SmallVec& operator=(SmallVec&& o) noexcept {
    if (this != &o) {
      release();
      take(o);
    }
    return *this;
  }
  ~SmallVec() { release(); }

  uint32_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  T* data() { return is_inline() ? inline_data() : heap(); }
  const T* data() const { return is_inline() ? inline_data() : heap(); }
  T& operator[](size_t i) { return data()[i]; }
  const T& operator[](size_t i) const { return data()[i]; }
  const T& at(size_t i) const {
    if (i >= size_) throw std::out_of_range("SmallVec::at");
    return data()[i];
  }
  T& front() { return data()[0]; }
  const T& front() const { return data()[0]; }
  T& back() { return data()[size_ - 1]; }
  const T& back() const { return data()[size_ - 1]; }
  T* begin() { return data(); }
  T* end() { return data() + size_; }
  const T* begin() const { return data(); }
  const T* end() const { return data() + size_; }

  void clear() { size_ = 0; }
  void reserve(uint32_t n) {
    if (n > capacity()) grow(n);
  }
  void push_back(const T& v) {
    if (size_ == capacity()) {
      T copy = v;  // `v` may live in this vector
      grow(capacity() * 2);
      data()[size_++] = copy;
      return;
    }
    data()[size_++] = v;
  }
  template <typename... Args>
  T& emplace_back(Args&&... args) {
    push_back(T{std::forward<Args>(args)...});
    return back();
  }
  void pop_back() { --size_; }
  /// Drops elements from the end until `n` remain (no-op when there are fewer).
  void truncate(uint32_t n) {
    if (n < size_) size_ = n;
  }

  friend bool operator==(const SmallVec& a, const SmallVec& b) {
    if (a.size_ != b.size_) return false;
    for (uint32_t i = 0; i < a.size_; ++i) {
      if (!(a[i] == b[i])) return false;
    }
    return true;
  }

 private:
  bool is_inline() const { return cap_ == 0; }
  uint32_t capacity() const { return is_inline() ? N : cap_; }
  T* heap() const { return room_.heap; }
  void assign(const T* from, uint32_t n) {
    reserve(n);
    if (n > 0) std::memcpy(static_cast<void*>(data()), from, sizeof(T) * n);
    size_ = n;
  }
  void grow(uint32_t n) {
    T* fresh = static_cast<T*>(std::malloc(sizeof(T) * n));
    if (fresh == nullptr) throw std::bad_alloc();
    if (size_ > 0) std::memcpy(static_cast<void*>(fresh), data(), sizeof(T) * size_);
    if (!is_inline()) std::free(heap());
    room_.heap = fresh;  // the inline elements, if any, were copied out above
    cap_ = n;
  }
  void take(SmallVec& o) {
    size_ = o.size_;
    if (!o.is_inline()) {
      room_.heap = o.heap();
      cap_ = o.cap_;
      o.cap_ = 0;
    } else {
      copy_inline_room(o);
    }
    o.size_ = 0;
  }
  void release() {
    // Most vectors never leave their inline room: skip the allocator's call for them (a
    // free of null still costs one, on every expression and list of a large file).
    if (!is_inline()) {
      std::free(heap());
      cap_ = 0;
    }
    size_ = 0;
  }

  uint32_t size_ = 0;
  uint32_t cap_ = 0;  // of the heap block; 0 while the elements are inline
  // The elements while they fit, else the heap block's address: a vector on the heap does
  // not use its inline room, so the pointer shares it (a statement's items, a list's
  // elements: tens of thousands per large document, 8 bytes each saved).
  // Raw room rather than `T inline_[N]`: an element type with a default constructor (an
  // `Id` is -1 until set) would otherwise be constructed N times for every vector made,
  // though only the first `size_` elements are ever read. The elements are trivially
  // copyable, so they begin to exist where they are copied in.
  union Room {
    T* heap;
    alignas(T) unsigned char bytes[sizeof(T) * N];
  } room_;
  // The whole inline room, a fixed size the compiler copies in a few moves, rather than a
  // call to memcpy for `size_` elements (copying a syntax tree copies many of these). The
  // bytes past `size_` may never have been written: copying them as bytes is allowed, and
  // nothing reads them as elements.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
  void copy_inline_room(const SmallVec& o) { std::memcpy(&room_, &o.room_, sizeof room_); }
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
  T* inline_data() { return std::launder(reinterpret_cast<T*>(room_.bytes)); }
  const T* inline_data() const { return std::launder(reinterpret_cast<const T*>(room_.bytes)); }
};

}  // namespace nomec
