#pragma once
/// Cell labels of glass mapping and their file codes: the one definition every stage uses.
///
/// Labels (in memory; grid, glass, mrf): 0 EMP, 1 OCC, 2 + k GLS_k (pane normal in angle bin k,
/// k < bins), kUnknown for a cell no beam touched (never a label of the MRF).
/// Codes (files and the vector stage; DESIGN.md's GeoTIFF): 0 unknown, 1 empty, 2 occupied,
/// 3..9 read as occupied (the ROS reading of "not free"), 10 + k glass with pane normal in bin k.

#include <cstdint>

namespace glassmap {

inline constexpr int kEmpty = 0;               ///< label EMP
inline constexpr int kOccupied = 1;            ///< label OCC
inline constexpr int kFirstGlass = 2;          ///< label GLS_0
inline constexpr int kDefaultBins = 36;        ///< 5 deg bins over [0, 180)
inline constexpr std::uint8_t kUnknown = 255;  ///< label of a cell no beam touched

/// Labels for `bins` angle bins: 2 + bins (38 by default).
inline constexpr int numLabels(int bins = kDefaultBins) { return kFirstGlass + bins; }
/// Label of glass with pane normal in bin k.
inline constexpr int glassLabel(int k) { return kFirstGlass + k; }
/// True for GLS_k labels (not kUnknown).
inline constexpr bool isGlass(int label) { return label >= kFirstGlass && label != kUnknown; }
/// Bin k of a glass label.
inline constexpr int glassBin(int label) { return label - kFirstGlass; }

inline constexpr std::uint8_t kCodeUnknown = 0;      ///< code: no beam touched the cell
inline constexpr std::uint8_t kCodeEmpty = 1;        ///< code: free space
inline constexpr std::uint8_t kCodeOccupied = 2;     ///< code: wall (anything opaque)
inline constexpr std::uint8_t kCodeFirstGlass = 10;  ///< code: glass with pane normal in bin 0

/// True for glass codes (10 + k).
inline constexpr bool isGlassCode(std::uint8_t code) { return code >= kCodeFirstGlass; }
/// True for wall codes (2..9).
inline constexpr bool isWallCode(std::uint8_t code) { return code >= kCodeOccupied && code < kCodeFirstGlass; }

/// Code of a label: 0 unknown, 1 empty, 2 occupied, 10 + k glass.
inline constexpr std::uint8_t labelToCode(int label) {
  if (label == kUnknown) return kCodeUnknown;
  if (label == kEmpty) return kCodeEmpty;
  if (label == kOccupied) return kCodeOccupied;
  return static_cast<std::uint8_t>(kCodeFirstGlass + glassBin(label));
}
/// Label of a code (codes 3..9 read as occupied).
inline constexpr int codeToLabel(std::uint8_t code) {
  if (code == kCodeUnknown) return kUnknown;
  if (code == kCodeEmpty) return kEmpty;
  if (code < kCodeFirstGlass) return kOccupied;
  return glassLabel(code - kCodeFirstGlass);
}

}  // namespace glassmap
