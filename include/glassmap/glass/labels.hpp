#pragma once
/// Cell labels of glass mapping and their GeoTIFF codes.
///
/// Labels (shared with mrf/): 0 EMP, 1 OCC, 2 + k GLS_k (pane normal at k * bin width, k < bins).
/// GeoTIFF codes (DESIGN.md): 0 unknown, 1 empty, 2 occupied, 10 + k glass at k * bin width.

#include <cstdint>

namespace glassmap::glass {

inline constexpr int kEmpty = 0;          ///< label EMP
inline constexpr int kOccupied = 1;       ///< label OCC
inline constexpr int kFirstGlass = 2;     ///< label GLS_0
inline constexpr int kDefaultBins = 36;   ///< 5 deg bins over [0, 180)
inline constexpr std::uint8_t kUnknown = 255;  ///< label of a cell no beam touched

/// Labels for `bins` angle bins: 2 + bins (38 by default).
inline constexpr int numLabels(int bins = kDefaultBins) { return kFirstGlass + bins; }
/// Label of glass with pane normal in bin k.
inline constexpr int glassLabel(int k) { return kFirstGlass + k; }
/// True for GLS_k labels (not kUnknown).
inline constexpr bool isGlass(int label) { return label >= kFirstGlass && label != kUnknown; }
/// Bin k of a glass label.
inline constexpr int glassBin(int label) { return label - kFirstGlass; }

/// GeoTIFF code of a label: 0 unknown, 1 empty, 2 occupied, 10 + k glass.
inline constexpr std::uint8_t labelToCode(int label) {
  if (label == kUnknown) return 0;
  if (label == kEmpty) return 1;
  if (label == kOccupied) return 2;
  return static_cast<std::uint8_t>(10 + glassBin(label));
}
/// Label of a GeoTIFF code (codes 3..9 read as occupied, the ROS reading of "not free").
inline constexpr int codeToLabel(std::uint8_t code) {
  if (code == 0) return kUnknown;
  if (code == 1) return kEmpty;
  if (code < 10) return kOccupied;
  return glassLabel(code - 10);
}

}  // namespace glassmap::glass
