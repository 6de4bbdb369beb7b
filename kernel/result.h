// Structured kernel errors and the `Result<T>` returned by every fallible kernel entry
// point. The kernel never throws across its public API and never formats diagnostics:
// the backend turns a `KernelError` (kind, plain message, offending element IDs) into a
// located diagnostic.
#pragma once

#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "kernel/ids.h"

namespace nomec::kernel {

/// A failure reported by the kernel, e.g. a third face on an edge in
/// `surface s (f1 f2 f3) endsurface`.
struct KernelError {
  enum class Kind {
    /// A face references a vertex index that does not exist, or an unknown name.
    UnknownVertex,
    /// A face has fewer than 3 vertices or repeats a vertex consecutively.
    DegenerateFace,
    /// An edge would be shared by three or more faces.
    NonManifoldEdge,
    /// The faces around a vertex form more than one fan.
    NonManifoldVertex,
    /// A merge was refused because it would create non-manifold edges or vertices.
    NonManifoldMerge,
    /// An option value is outside its documented range.
    InvalidArgument,
  };
  Kind kind = Kind::InvalidArgument;
  /// Lowercase, no trailing period; describes what was seen.
  std::string message;
  /// Offending elements. For builder errors `faces` holds indices of soup faces and
  /// `vertices` the soup vertex pairs of offending edges (two entries per edge).
  std::vector<EdgeId> edges;
  std::vector<FaceId> faces;
  std::vector<VertexId> vertices;
};

/// An `InvalidArgument` error with `message` and no offending elements.
inline KernelError invalid_argument(std::string message) {
  return KernelError{KernelError::Kind::InvalidArgument, std::move(message), {}, {}, {}};
}

/// Either a value or a `KernelError`.
template <typename T>
class Result {
 public:
  Result(T value) : data_(std::move(value)) {}
  Result(KernelError error) : data_(std::move(error)) {}

  bool has_value() const { return data_.index() == 0; }
  explicit operator bool() const { return has_value(); }
  /// Precondition: `has_value()`.
  T& value() { return std::get<0>(data_); }
  const T& value() const { return std::get<0>(data_); }
  T& operator*() { return value(); }
  const T& operator*() const { return value(); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  /// Precondition: `!has_value()`.
  const KernelError& error() const { return std::get<1>(data_); }

 private:
  std::variant<T, KernelError> data_;
};

}  // namespace nomec::kernel
