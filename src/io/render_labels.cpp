#include "glassmap/io/render_labels.hpp"

#include <cairo.h>

#include <algorithm>
#include <cmath>

#include "glassmap/core/atomic_file.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/core/labels.hpp"

namespace glassmap {

Rgb labelColour(int label, int bins) {
  if (label == kUnknown) return {205, 205, 205};
  if (label == kEmpty) return {255, 255, 255};
  if (label == kOccupied) return {0, 0, 0};
  // Hue from the pane angle (two turns of hue per half turn of angle would repeat; one is enough
  // since 0 and 180 deg are the same pane), full saturation, value 0.85.
  const double h = 6.0 * glassBin(label) / std::max(1, bins);
  const int sector = static_cast<int>(h) % 6;
  const double f = h - std::floor(h), v = 0.85;
  const double p = 0.0, q = v * (1.0 - f), t = v * f;
  double r = v, g = t, b = p;
  switch (sector) {
    case 0:
      r = v;
      g = t;
      b = p;
      break;
    case 1:
      r = q;
      g = v;
      b = p;
      break;
    case 2:
      r = p;
      g = v;
      b = t;
      break;
    case 3:
      r = p;
      g = q;
      b = v;
      break;
    case 4:
      r = t;
      g = p;
      b = v;
      break;
    default:
      r = v;
      g = p;
      b = q;
      break;
  }
  auto c = [](double x) { return static_cast<std::uint8_t>(std::lround(255.0 * x)); };
  return {c(r), c(g), c(b)};
}

void writeLabelsPng(const std::filesystem::path& png, int width, int height, const std::vector<std::uint8_t>& labels,
                    int bins, const LabelRenderOptions& options) {
  if (width <= 0 || height <= 0 || labels.size() != static_cast<std::size_t>(width) * height) {
    throw Error("label grid size does not match its width and height", png.string());
  }
  int scale = options.scale;
  if (scale <= 0) scale = std::clamp(1000 / std::max(width, height), 1, 4);
  const int pw = width * scale, ph = height * scale;
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, pw, ph);
  if (cairo_surface_status(surface) != CAIRO_STATUS_SUCCESS) {
    cairo_surface_destroy(surface);
    throw Error("cannot create a " + std::to_string(pw) + " x " + std::to_string(ph) + " picture", png.string());
  }
  cairo_surface_flush(surface);
  unsigned char* data = cairo_image_surface_get_data(surface);
  const int stride = cairo_image_surface_get_stride(surface);
  for (int py = 0; py < ph; ++py) {
    const int y = height - 1 - py / scale;  // row 0 of the grid at the bottom of the picture
    auto* row = reinterpret_cast<std::uint32_t*>(data + static_cast<std::ptrdiff_t>(py) * stride);
    for (int px = 0; px < pw; ++px) {
      const Rgb c = labelColour(labels[static_cast<std::size_t>(y) * width + px / scale], bins);
      row[px] = (std::uint32_t{c.r} << 16) | (std::uint32_t{c.g} << 8) | c.b;
    }
  }
  cairo_surface_mark_dirty(surface);
  try {
    writeAtomically(png, [&](const std::filesystem::path& tmp) {
      if (cairo_surface_write_to_png(surface, tmp.c_str()) != CAIRO_STATUS_SUCCESS) {
        throw Error("cannot write PNG", tmp.string());
      }
    });
  } catch (...) {
    cairo_surface_destroy(surface);
    throw;
  }
  cairo_surface_destroy(surface);
}

}  // namespace glassmap
