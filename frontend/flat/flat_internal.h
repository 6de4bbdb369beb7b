// Helpers the flat-file readers share (frontend/flat only): strict number parsing, adding
// a face with the check every format needs (a face whose vertices repeat once welded is
// dropped with a warning), and `.sif`'s weld of nearby points.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "frontend/flat/flat.h"

namespace nomec::flat::detail {

/// A finite decimal number (`12`, `-0.5`, `+.5`, `1e-3`); nullopt otherwise.
std::optional<double> parse_number(std::string_view text);
/// A whole number with an optional sign (`-1`, `42`), saturated to ±2^40; nullopt otherwise.
std::optional<int64_t> parse_integer(std::string_view text);

/// Appends the face `vertices` (indices into `g.positions`) to `g`, unless a vertex repeats:
/// then warns at `at` (`what` names the face as written, e.g. "triangle `(t 3 4 5)`") and
/// drops it. Only the first `kShownDropped` drops of a file are reported one by one;
/// `report_dropped` sums up the rest. Returns whether the face was added.
inline constexpr int kShownDropped = 10;
bool add_face(ir::FlatGeometry& g, std::span<const int32_t> vertices, SourceRange at, std::string_view what,
              DiagnosticEngine& diags, int& dropped);
/// After a file: one warning for the dropped faces not reported one by one.
void report_dropped(int dropped, FileId file, DiagnosticEngine& diags);

/// Points welded within a distance (`.sif`, sif.cpp): `map[i]` is the survivor point `i`
/// went into, `survivors` their positions in order; `comparisons` counts the distances
/// measured (tests hold the weld to O(n log n) with it).
struct Weld {
  std::vector<int32_t> map;
  std::vector<std::array<double, 3>> survivors;
  int64_t comparisons = 0;
};
/// Each point goes into the earliest survivor at most `distance` (< 2^-9) away, or
/// survives itself; a point with `apart[i]` set (a misread vertex) or a non-finite
/// coordinate survives without being compared. O(n log n) for any coordinates.
Weld weld_points(std::span<const std::array<double, 3>> points, std::span<const uint8_t> apart, double distance);

}  // namespace nomec::flat::detail
