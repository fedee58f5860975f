#include "glassmap/io/render_floorplan.hpp"

#include <cairo-svg.h>
#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "glassmap/core/atomic_file.hpp"
#include "glassmap/core/error.hpp"

namespace glassmap {
namespace {

void setRgb(cairo_t* cr, std::uint32_t rgb, double alpha = 1.0) {
  cairo_set_source_rgba(cr, ((rgb >> 16) & 0xff) / 255.0, ((rgb >> 8) & 0xff) / 255.0, (rgb & 0xff) / 255.0, alpha);
}

constexpr std::uint32_t kWallColour = 0x202020;
constexpr std::uint32_t kGlassColour = 0x1e90ff;
constexpr std::uint32_t kTrajectoryColour = 0xd62728;

}  // namespace

void renderFloorplan(const std::filesystem::path& out, const VectorMap& map, const FloorplanPicture& pic) {
  Eigen::AlignedBox2d box = map.bounds();
  for (const Vec2& p : pic.trajectory) box.extend(p);
  for (const ColoredPoint& p : pic.points) box.extend(p.p);
  if (box.isEmpty()) throw Error("nothing to draw: the floorplan is empty", out.string());
  box.min() -= Vec2::Constant(pic.margin);
  box.max() += Vec2::Constant(pic.margin);
  const Vec2 size = box.max() - box.min();
  const double scale = std::min(pic.pixels_per_metre, pic.max_pixels / std::max(size.x(), size.y()));
  const int legend_h = pic.legend ? 28 : 0;
  const int w = std::max(1, static_cast<int>(std::ceil(size.x() * scale)));
  const int h = std::max(1, static_cast<int>(std::ceil(size.y() * scale))) + legend_h;

  std::string ext = out.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext != ".png" && ext != ".svg") throw Error("expected a .png or .svg output", out.string());

  writeAtomically(out, [&](const std::filesystem::path& tmp) {
    cairo_surface_t* surface = ext == ".svg" ? cairo_svg_surface_create(tmp.c_str(), w, h)
                                             : cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
    std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> surface_guard(surface, cairo_surface_destroy);
    if (cairo_surface_status(surface) != CAIRO_STATUS_SUCCESS)
      throw Error("cannot create a drawing surface", out.string());
    cairo_t* cr = cairo_create(surface);
    std::unique_ptr<cairo_t, decltype(&cairo_destroy)> cr_guard(cr, cairo_destroy);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    // Map frame -> image: x right, y up.
    const auto px = [&](const Vec2& p) {
      return std::pair<double, double>((p.x() - box.min().x()) * scale, (box.max().y() - p.y()) * scale);
    };
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
    for (const ColoredPoint& p : pic.points) {
      const auto [x, y] = px(p.p);
      setRgb(cr, p.rgb, 0.8);
      cairo_arc(cr, x, y, pic.point_radius, 0, 2 * kPi);
      cairo_fill(cr);
    }
    for (const MapSegment& s : map.segments) {
      const bool glass = s.material == Material::Glass;
      setRgb(cr, glass ? kGlassColour : kWallColour);
      cairo_set_line_width(cr, std::max(glass ? 2.5 : 1.5, s.thickness * scale));
      const auto [ax, ay] = px(s.a);
      const auto [bx, by] = px(s.b);
      cairo_move_to(cr, ax, ay);
      cairo_line_to(cr, bx, by);
      cairo_stroke(cr);
    }
    if (pic.trajectory.size() > 1) {
      setRgb(cr, kTrajectoryColour);
      cairo_set_line_width(cr, 1.5);
      const auto [x0, y0] = px(pic.trajectory.front());
      cairo_move_to(cr, x0, y0);
      for (const Vec2& p : pic.trajectory) {
        const auto [x, y] = px(p);
        cairo_line_to(cr, x, y);
      }
      cairo_stroke(cr);
    }
    if (pic.legend) {
      // Scale bar of a round length near a fifth of the width, and the material key.
      const double target = size.x() / 5.0;
      const double step = std::pow(10.0, std::floor(std::log10(target)));
      const double bar = target >= 5 * step ? 5 * step : (target >= 2 * step ? 2 * step : step);
      const double y = h - 10.0;
      cairo_set_source_rgb(cr, 0, 0, 0);
      cairo_set_line_width(cr, 2);
      cairo_move_to(cr, 10, y);
      cairo_line_to(cr, 10 + bar * scale, y);
      cairo_stroke(cr);
      cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
      cairo_set_font_size(cr, 12);
      const std::string label = (bar >= 1 ? std::to_string(static_cast<int>(bar)) : std::to_string(bar)) + " m";
      cairo_move_to(cr, 16 + bar * scale, y + 4);
      cairo_show_text(cr, label.c_str());
      double x = 80 + bar * scale;
      for (auto [name, rgb] : {std::pair<const char*, std::uint32_t>{"wall", kWallColour}, {"glass", kGlassColour}}) {
        setRgb(cr, rgb);
        cairo_rectangle(cr, x, y - 8, 16, 8);
        cairo_fill(cr);
        cairo_set_source_rgb(cr, 0, 0, 0);
        cairo_move_to(cr, x + 20, y);
        cairo_show_text(cr, name);
        x += 70;
      }
    }
    cairo_destroy(cr_guard.release());
    if (ext == ".png") {
      if (cairo_surface_write_to_png(surface, tmp.c_str()) != CAIRO_STATUS_SUCCESS)
        throw Error("cannot write PNG", out.string());
    } else {
      cairo_surface_finish(surface);
      if (cairo_surface_status(surface) != CAIRO_STATUS_SUCCESS) throw Error("cannot write SVG", out.string());
    }
  });
}

}  // namespace glassmap
