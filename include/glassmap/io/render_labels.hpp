#pragma once
/// Picture of a label grid (Cairo PNG): unknown grey, empty white, occupied black, glass in a
/// colour wheel by pane angle (hue = 2 x angle, so 0 and 180 deg meet).

#include <cstdint>
#include <filesystem>
#include <vector>

namespace glassmap {

/// How to draw.
struct LabelRenderOptions {
  int scale = 0;  ///< pixels per cell; 0 picks 1..4 so the picture is about 1000+ px wide
};

/// RGB colour of a label (glass by its bin among `bins`).
struct Rgb {
  std::uint8_t r, g, b;
};
Rgb labelColour(int label, int bins);

/// Writes a PNG of labels (row 0 = bottom, drawn at the bottom), atomically.
void writeLabelsPng(const std::filesystem::path& png, int width, int height, const std::vector<std::uint8_t>& labels,
                    int bins, const LabelRenderOptions& options = {});

}  // namespace glassmap
