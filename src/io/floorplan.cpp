// Floorplan formats and units: which driver writes what, unit names, the plausibility check.
#include "glassmap/io/floorplan.hpp"

#include <gdal_priv.h>
#include <ogr_geometry.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>
#include <system_error>

#include "dxf_text.hpp"
#include "floorplan_detail.hpp"
#include "gdal_util.hpp"
#include "glassmap/core/atomic_file.hpp"
#include "glassmap/core/error.hpp"
#include "text_parse.hpp"

namespace glassmap {

namespace fs = std::filesystem;
using io_detail::GdalErrorCollector;
using io_detail::lower;

std::string_view localMetricCrsWkt() { return io_detail::kLocalWkt; }

namespace {

struct NamedUnit {
  const char* name;
  double metres;
  const char* label;
};
constexpr NamedUnit kUnits[] = {{"m", 1.0, "metres"},         {"dm", 0.1, "decimetres"},
                                {"cm", 0.01, "centimetres"},  {"mm", 0.001, "millimetres"},
                                {"km", 1000.0, "kilometres"}, {"in", 0.0254, "inches"},
                                {"ft", 0.3048, "feet"},       {"us-ft", 1200.0 / 3937.0, "US survey feet"},
                                {"yd", 0.9144, "yards"}};

}  // namespace

std::string io_detail::unitName(double metres) {
  for (const NamedUnit& u : kUnits)
    if (std::abs(u.metres - metres) <= 1e-9 * metres) return u.label;
  return std::to_string(metres) + " m per unit";
}

double parseLengthUnit(const std::string& text, const std::string& field) {
  for (const NamedUnit& u : kUnits)
    if (lower(text) == u.name) return u.metres;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() && *end == '\0' && std::isfinite(v) && v > 0.0) return v;
  throw Error("unknown unit '" + text + "' (expected m, dm, cm, mm, km, in, ft, us-ft, yd or metres per unit)", {}, 0,
              field);
}

std::string implausibleExtentWarning(const VectorMap& map, const FloorplanUnits& units, const fs::path& path) {
  // The bulk of the drawing: 1st to 99th percentile of the segment midpoints weighted by length,
  // so that a stray segment far away (CAD files have them) does not make a building implausible.
  std::vector<std::pair<double, double>> xs, ys;  // (coordinate, length)
  double total = 0.0;
  for (const MapSegment& s : map.segments) {
    if (!s.a.allFinite() || !s.b.allFinite()) continue;
    const double len = std::max(s.length(), 1e-9);
    for (const Vec2& p : {s.a, s.b}) {
      xs.emplace_back(p.x(), len / 2);
      ys.emplace_back(p.y(), len / 2);
    }
    total += len;
  }
  if (xs.empty()) return {};
  auto span = [&](std::vector<std::pair<double, double>>& v) {
    std::sort(v.begin(), v.end());
    double acc = 0.0, lo = v.front().first, hi = v.back().first;
    bool have_lo = false;
    for (const auto& [c, w] : v) {
      acc += w;
      if (!have_lo && acc >= 0.01 * total) lo = c, have_lo = true;
      if (acc >= 0.99 * total) {
        hi = c;
        break;
      }
    }
    return hi - lo;
  };
  const Vec2 size(span(xs), span(ys));
  const double side = size.maxCoeff();
  if (side >= 2.0 && side <= 5000.0) return {};
  char buf[160];
  std::snprintf(buf, sizeof buf, "the plan spans %.3g x %.3g m", size.x(), size.y());
  return path.string() + ": " + buf + ", implausible for a building floor, with its units read as " + units.source +
         "; if that is wrong, pass --units (m, cm, mm, in, ft, ...)";
}

FloorplanFormat floorplanFormatFromPath(const fs::path& path) {
  const std::string ext = lower(path.extension().string());
  if (ext == ".gpkg") return FloorplanFormat::Gpkg;
  if (ext == ".geojson" || ext == ".json") return FloorplanFormat::GeoJson;
  if (ext == ".shp") return FloorplanFormat::Shapefile;
  if (ext == ".fgb") return FloorplanFormat::FlatGeobuf;
  if (ext == ".dxf") return FloorplanFormat::Dxf;
  throw Error("unknown floorplan format '" + ext + "': expected .gpkg, .geojson, .json, .shp, .fgb or .dxf",
              path.string());
}

std::string_view gdalDriverName(FloorplanFormat format) {
  switch (format) {
    case FloorplanFormat::Gpkg: return "GPKG";
    case FloorplanFormat::GeoJson: return "GeoJSON";
    case FloorplanFormat::Shapefile: return "ESRI Shapefile";
    case FloorplanFormat::FlatGeobuf: return "FlatGeobuf";
    case FloorplanFormat::Dxf: return "DXF";
  }
  return "";
}

}  // namespace glassmap
