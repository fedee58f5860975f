#include "glassmap/io/render_pdf.hpp"

#include <cairo-pdf.h>
#include <cairo.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

#include "glassmap/core/atomic_file.hpp"
#include "glassmap/core/error.hpp"

namespace glassmap {
namespace {

// Cairo's own PDF file output does not report a short write (a full disk leaves a truncated PDF
// and CAIRO_STATUS_SUCCESS): write through a stream whose every write is checked.
struct CheckedFile {
  std::FILE* f = nullptr;
  int error = 0;  // errno of the first failed write
};

cairo_status_t writeChecked(void* closure, const unsigned char* data, unsigned int length) {
  auto* out = static_cast<CheckedFile*>(closure);
  if (std::fwrite(data, 1, length, out->f) != length) {
    if (out->error == 0) out->error = errno != 0 ? errno : EIO;
    return CAIRO_STATUS_WRITE_ERROR;
  }
  return CAIRO_STATUS_SUCCESS;
}

}  // namespace

void renderFloorplanPdf(const std::filesystem::path& out, const VectorMap& map, const PdfLayout& layout) {
  const Eigen::AlignedBox2d box = map.bounds();
  if (box.isEmpty()) throw Error("nothing to draw: the floorplan is empty", out.string());
  if (!(layout.scale > 0) || !(layout.max_side_mm > 2 * layout.margin_mm))
    throw Error("bad PDF layout (scale and page size must be positive)", out.string());
  constexpr double kPtPerMm = 72.0 / 25.4;
  const Vec2 size = (box.max() - box.min()).cwiseMax(Vec2::Constant(1e-3));
  // Paper millimetres per metre at 1:scale, lowered to a round scale when the drawing is too big.
  double scale = layout.scale;
  const double usable = layout.max_side_mm - 2 * layout.margin_mm;
  while (1000.0 * std::max(size.x(), size.y()) / scale > usable) scale *= scale < 200 ? 2.0 : 2.5;
  const double pt_per_m = 1000.0 / scale * kPtPerMm;
  const double margin = layout.margin_mm * kPtPerMm;
  const double legend_h = layout.legend ? 14.0 : 0.0;
  const double w = size.x() * pt_per_m + 2 * margin, h = size.y() * pt_per_m + 2 * margin + legend_h;

  writeAtomically(out, [&](const std::filesystem::path& tmp) {
    CheckedFile file;
    file.f = std::fopen(tmp.c_str(), "wb");
    if (file.f == nullptr) throw Error(std::string("cannot create: ") + std::strerror(errno), out.string());
    std::unique_ptr<std::FILE, decltype(&std::fclose)> fg(file.f, std::fclose);
    cairo_surface_t* surface = cairo_pdf_surface_create_for_stream(writeChecked, &file, w, h);
    std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> sg(surface, cairo_surface_destroy);
    if (cairo_surface_status(surface) != CAIRO_STATUS_SUCCESS) throw Error("cannot create a PDF surface", out.string());
    cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_TITLE,
                                   map.name.empty() ? "glassmap floorplan" : map.name.c_str());
    cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_CREATOR, "glassmap");
    cairo_t* cr = cairo_create(surface);
    std::unique_ptr<cairo_t, decltype(&cairo_destroy)> cg(cr, cairo_destroy);
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
    for (const MapSegment& s : map.segments) {
      const bool glass = s.material == Material::Glass;
      if (glass)
        cairo_set_source_rgb(cr, 0x1e / 255.0, 0x90 / 255.0, 1.0);
      else
        cairo_set_source_rgb(cr, 0.125, 0.125, 0.125);
      cairo_set_line_width(cr, std::max(0.25, s.thickness * pt_per_m));
      const auto px = [&](const Vec2& p) {
        return std::pair<double, double>(margin + (p.x() - box.min().x()) * pt_per_m,
                                         margin + (box.max().y() - p.y()) * pt_per_m);
      };
      const auto [ax, ay] = px(s.a);
      const auto [bx, by] = px(s.b);
      cairo_move_to(cr, ax, ay);
      cairo_line_to(cr, bx, by);
      cairo_stroke(cr);
    }
    if (layout.legend) {
      const std::string text = "1:" + std::to_string(static_cast<long>(std::lround(scale))) +
                               "   walls dark, glass blue   " + (map.name.empty() ? "" : map.name);
      cairo_set_source_rgb(cr, 0, 0, 0);
      cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
      cairo_set_font_size(cr, 8);
      cairo_move_to(cr, margin, h - margin * 0.5 - 2);
      cairo_show_text(cr, text.c_str());
    }
    cairo_show_page(cr);
    cairo_destroy(cg.release());
    cairo_surface_finish(surface);
    const bool flushed = std::fflush(file.f) == 0;
    if (!flushed && file.error == 0) file.error = errno;
    if (file.error != 0) throw Error(std::string("cannot write PDF: ") + std::strerror(file.error), out.string());
    if (cairo_surface_status(surface) != CAIRO_STATUS_SUCCESS) throw Error("cannot write PDF", out.string());
  });
}

}  // namespace glassmap
