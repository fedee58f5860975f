#pragma once
/// Floorplans as vector PDF (Cairo's PDF surface), drawn to a metric scale for printing.

#include <filesystem>

#include "glassmap/geometry/vector_map.hpp"

namespace glassmap {

/// Page layout of a PDF floorplan.
struct PdfLayout {
  double scale = 100.0;         ///< drawing scale 1:scale (1:100 -> 1 m is 10 mm); raised to fit max_side
  double max_side_mm = 1189.0;  ///< longest page side (A0) [mm]
  double margin_mm = 10.0;      ///< page margin [mm]
  bool legend = true;           ///< scale text and the colour key under the drawing
};

/// Writes the floorplan as a one-page PDF, atomically: walls dark, glass blue, line widths the
/// segments' thickness at scale (at least 0.25 pt). Throws Error for an empty map.
void renderFloorplanPdf(const std::filesystem::path& out, const VectorMap& map, const PdfLayout& layout = {});

}  // namespace glassmap
