// Reading floorplans through GDAL/OGR: any line source, materials from fields or layers, units
// and CRSs to local metres.
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

namespace {

constexpr double kDefaultThickness = 0.1;  // [m]

bool containsGlass(std::string_view s) { return lower(s).find("glass") != std::string::npos; }

/// Scoped thread-local GDAL configuration option.
class ScopedConfig {
 public:
  ScopedConfig(const char* key, const char* value) : key_(key) {
    const char* old = CPLGetThreadLocalConfigOption(key, nullptr);
    if (old) old_ = old, had_ = true;
    CPLSetThreadLocalConfigOption(key, value);
  }
  ~ScopedConfig() { CPLSetThreadLocalConfigOption(key_, had_ ? old_.c_str() : nullptr); }
  ScopedConfig(const ScopedConfig&) = delete;
  ScopedConfig& operator=(const ScopedConfig&) = delete;

 private:
  const char* key_;
  std::string old_;
  bool had_ = false;
};

struct FeatureAttrs {
  Material material = Material::Wall;
  double thickness = kDefaultThickness;
  double pane_angle = 0.0;
  std::uint32_t support = 0;
  double evidence = 0.0;
};

/// Collects the segments of a geometry (lines, polygon rings, collections) in metres.
void addSegments(const OGRGeometry* g, double to_m, const FeatureAttrs& a, VectorMap& out, std::size_t& skipped) {
  if (!g || g->IsEmpty()) return;
  const OGRwkbGeometryType type = wkbFlatten(g->getGeometryType());
  if (type == wkbLineString || type == wkbLinearRing || type == wkbCircularString || type == wkbCompoundCurve) {
    std::unique_ptr<OGRLineString> owned;
    const OGRLineString* ls = nullptr;
    if (type == wkbLineString || type == wkbLinearRing) {
      ls = g->toLineString();
    } else {
      owned.reset(g->toCurve()->CurveToLine());
      ls = owned.get();
    }
    for (int i = 0; i + 1 < ls->getNumPoints(); ++i) {
      MapSegment s;
      s.a = Vec2(ls->getX(i), ls->getY(i)) * to_m;
      s.b = Vec2(ls->getX(i + 1), ls->getY(i + 1)) * to_m;
      if (s.a == s.b) continue;  // repeated vertex
      s.material = a.material;
      s.thickness = a.thickness;
      s.pane_angle = a.pane_angle;
      s.support = a.support;
      s.evidence = a.evidence;
      out.segments.push_back(s);
    }
  } else if (type == wkbPolygon || type == wkbCurvePolygon) {
    const OGRCurvePolygon* poly = g->toCurvePolygon();
    addSegments(poly->getExteriorRingCurve(), to_m, a, out, skipped);
    for (int i = 0; i < poly->getNumInteriorRings(); ++i)
      addSegments(poly->getInteriorRingCurve(i), to_m, a, out, skipped);
  } else if (OGR_GT_IsSubClassOf(type, wkbGeometryCollection)) {
    const OGRGeometryCollection* c = g->toGeometryCollection();
    for (int i = 0; i < c->getNumGeometries(); ++i) addSegments(c->getGeometryRef(i), to_m, a, out, skipped);
  } else {
    ++skipped;  // points, text, ...
  }
}

/// Reads "key=value" pairs from DXF XDATA of application GLASSMAP (RawCodeValues field).
void readXData(OGRFeature& f, int raw_idx, FeatureAttrs& a, bool& has_thickness, const std::string& file) {
  if (raw_idx < 0 || !f.IsFieldSetAndNotNull(raw_idx)) return;
  char** values = f.GetFieldAsStringList(raw_idx);
  bool ours = false;
  for (char** v = values; v && *v; ++v) {
    const std::string_view item(*v);
    if (item.starts_with("1001 ")) {
      ours = item.substr(5) == "GLASSMAP";
      continue;
    }
    if (!ours || !item.starts_with("1000 ")) continue;
    const std::string_view kv = item.substr(5);
    const auto eq = kv.find('=');
    if (eq == std::string_view::npos) continue;
    const std::string_view key = kv.substr(0, eq), val = kv.substr(eq + 1);
    double num = 0.0;
    const bool is_num = io_detail::tryParseDouble(val, num);
    const std::string where = "feature " + std::to_string(f.GetFID()) + " XDATA " + std::string(key);
    if (key == "thickness") {
      if (!is_num) throw Error("expected a number, got '" + std::string(val) + "'", file, 0, where);
      a.thickness = num;
      has_thickness = true;
    } else if (key == "pane_angle" && is_num) {
      a.pane_angle = num;
    } else if (key == "support" && is_num && num >= 0) {
      a.support = static_cast<std::uint32_t>(num);
    } else if (key == "evidence" && is_num) {
      a.evidence = num;
    }
  }
}

}  // namespace

namespace {

// What the text of a GeoJSON file says before its features: an old-style "crs" member, and
// glassmap's marker.
struct GeoJsonHead {
  bool has_crs = false;
  bool glassmap = false;
};
GeoJsonHead geoJsonHead(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string head(64 * 1024, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  const std::size_t features = head.find("\"features\"");
  const std::string before = head.substr(0, features);
  return {before.find("\"crs\"") != std::string::npos, before.find(io_detail::kGeoJsonMarker) != std::string::npos};
}

// A transformation from a geographic CRS to metres of a transverse Mercator centred on (lon, lat):
// a local metric frame in which a building's plan keeps its shape to well under a millimetre.
std::unique_ptr<OGRCoordinateTransformation> toLocalMetres(const OGRSpatialReference& geographic, double lon,
                                                           double lat, const std::string& file) {
  OGRSpatialReference local;
  local.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  if (local.SetWellKnownGeogCS("WGS84") != OGRERR_NONE || local.SetTM(lat, lon, 1.0, 0.0, 0.0) != OGRERR_NONE)
    throw Error("cannot build a local transverse Mercator frame", file);
  OGRSpatialReference src(geographic);
  src.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  std::unique_ptr<OGRCoordinateTransformation> ct(OGRCreateCoordinateTransformation(&src, &local));
  if (!ct) throw Error("cannot transform the plan's geographic coordinates to metres (PROJ)", file);
  return ct;
}

}  // namespace

VectorMap readFloorplan(const fs::path& path, const FloorplanReadOptions& options) {
  io_detail::ensureGdalRegistered();
  GdalErrorCollector errors;
  const std::string file = path.string();
  std::error_code ec;
  if (!fs::exists(path, ec)) throw Error("floorplan file does not exist" + io_detail::reason(ec), file);
  if (lower(path.extension().string()) == ".dxf") io_detail::checkDxfGroupCodes(path);
  ScopedConfig raw_codes("DXF_INCLUDE_RAW_CODE_VALUES", "TRUE");
  // A known extension opens with its own driver only: no probing of every other driver's parser
  // on a file that is not theirs (faster, and a smaller surface for malformed input). Any other
  // OGR source is left to GDAL's probing.
  std::string driver;
  try {
    driver = std::string(gdalDriverName(floorplanFormatFromPath(path)));
  } catch (const Error&) {
  }
  const char* const allowed[] = {driver.c_str(), nullptr};
  GDALDatasetUniquePtr ds(
      GDALDataset::Open(file.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, driver.empty() ? nullptr : allowed));
  if (!ds) throw Error("cannot open as a vector floorplan" + errors.suffix(), file);
  VectorMap map;
  map.name = path.stem().string();
  std::size_t skipped = 0;
  if (options.unit_in_metres < 0.0 || !std::isfinite(options.unit_in_metres))
    throw Error("unit_in_metres must be positive (or 0 for the file's own units)", file);
  const bool is_dxf = EQUAL(ds->GetDriverName(), "DXF");
  const double dxf_unit = is_dxf ? io_detail::dxfUnitInMetres(path) : 0.0;
  bool first_layer = true;
  for (OGRLayer* layer : ds->GetLayers()) {
    double to_m = dxf_unit > 0.0 ? dxf_unit : 1.0;
    std::string source = dxf_unit > 0.0 ? "DXF $INSUNITS (" + io_detail::unitName(dxf_unit) + ")"
                         : is_dxf       ? "no DXF $INSUNITS: metres"
                                        : "none declared: metres";
    // GDAL reports every GeoJSON layer as WGS 84 (RFC 7946: longitude/latitude). A GeoJSON that
    // declares a CRS ("crs" member) is read in it; glassmap's own GeoJSON (marked) is local metres;
    // an unmarked one without a CRS is longitude/latitude when read as metres it would be an
    // implausibly small plan (under 2 m), else local metres (said in the units note).
    const bool is_geojson = EQUAL(ds->GetDriverName(), "GeoJSON") || EQUAL(ds->GetDriverName(), "GeoJSONSeq");
    const OGRSpatialReference* srs = layer->GetSpatialRef();
    std::unique_ptr<OGRCoordinateTransformation> to_local;
    if (is_geojson) {
      const GeoJsonHead head = geoJsonHead(path);
      OGREnvelope env;
      const bool have_extent = layer->GetExtent(&env, TRUE) == OGRERR_NONE;
      const bool lonlat_range = have_extent && env.MinX >= -180 && env.MaxX <= 180 && env.MinY >= -90 && env.MaxY <= 90;
      const bool tiny = have_extent && std::max(env.MaxX - env.MinX, env.MaxY - env.MinY) < 2.0;
      if (head.has_crs) {
        // srs as declared
      } else if (options.unit_in_metres > 0.0 || head.glassmap || !lonlat_range || !tiny) {
        srs = nullptr;
        source = head.glassmap ? "glassmap GeoJSON: local metres"
                               : "no crs member: local metres assumed (RFC 7946 would read degrees; the plan's "
                                 "size says metres)";
      }
      if (srs != nullptr && srs->IsGeographic() && !have_extent) srs = nullptr;
    }
    if (srs) {
      if (srs->IsGeographic()) {
        if (options.unit_in_metres > 0.0)
          throw Error(
              "layer '" + std::string(layer->GetName()) + "' is in geographic coordinates: --units does not apply",
              file);
        OGREnvelope env;
        if (layer->GetExtent(&env, TRUE) != OGRERR_NONE)
          throw Error("layer '" + std::string(layer->GetName()) + "' has no extent to centre a local frame on", file);
        const double lon = 0.5 * (env.MinX + env.MaxX), lat = 0.5 * (env.MinY + env.MaxY);
        to_local = toLocalMetres(*srs, lon, lat, file);
        char buf[200];
        std::snprintf(buf, sizeof buf,
                      "longitude/latitude (%s), projected to metres about %.6f, %.6f (transverse Mercator)",
                      srs->GetName() ? srs->GetName() : "geographic", lon, lat);
        source = buf;
        to_m = 1.0;
        srs = nullptr;
      }
    }
    if (srs) {
      const char* unit_name = nullptr;
      to_m = srs->GetLinearUnits(&unit_name);
      if (!(to_m > 0.0)) to_m = 1.0;
      source = std::string("CRS linear unit (") + (unit_name ? unit_name : "?") + ")";
    }
    if (options.unit_in_metres > 0.0) {
      to_m = options.unit_in_metres;
      source = "option (" + io_detail::unitName(to_m) + ")";
    }
    if (first_layer && options.units != nullptr) *options.units = {to_m, source};
    first_layer = false;
    OGRFeatureDefn* defn = layer->GetLayerDefn();
    const int material_idx = defn->GetFieldIndex("material");
    const int thickness_idx = defn->GetFieldIndex("thickness");
    const int angle_idx = defn->GetFieldIndex("pane_angle");
    const int support_idx = defn->GetFieldIndex("support");
    const int evidence_idx = defn->GetFieldIndex("evidence");
    const int dxf_layer_idx = defn->GetFieldIndex("Layer");
    const int raw_idx = defn->GetFieldIndex("RawCodeValues");
    const bool layer_is_glass = containsGlass(layer->GetName());
    layer->ResetReading();
    for (auto& f : *layer) {
      FeatureAttrs a;
      const std::string where = "feature " + std::to_string(f->GetFID());
      if (material_idx >= 0 && f->IsFieldSetAndNotNull(material_idx)) {
        try {
          a.material = parseMaterial(f->GetFieldAsString(material_idx));
        } catch (const Error& e) {
          throw Error(e.message(), file, 0, where + " material");
        }
      } else if (dxf_layer_idx >= 0 && f->IsFieldSetAndNotNull(dxf_layer_idx)) {
        a.material = containsGlass(f->GetFieldAsString(dxf_layer_idx)) ? Material::Glass : Material::Wall;
      } else {
        a.material = layer_is_glass ? Material::Glass : Material::Wall;
      }
      bool has_thickness = false;
      if (thickness_idx >= 0 && f->IsFieldSetAndNotNull(thickness_idx)) {
        a.thickness = f->GetFieldAsDouble(thickness_idx) * to_m;
        has_thickness = true;
      }
      readXData(*f, raw_idx, a, has_thickness, file);
      if (!std::isfinite(a.thickness) || a.thickness <= 0.0)
        throw Error("thickness must be a positive number of metres", file, 0, where + " thickness");
      if (angle_idx >= 0 && f->IsFieldSetAndNotNull(angle_idx)) a.pane_angle = f->GetFieldAsDouble(angle_idx);
      if (support_idx >= 0 && f->IsFieldSetAndNotNull(support_idx))
        a.support = static_cast<std::uint32_t>(std::max<GIntBig>(0, f->GetFieldAsInteger64(support_idx)));
      if (evidence_idx >= 0 && f->IsFieldSetAndNotNull(evidence_idx)) a.evidence = f->GetFieldAsDouble(evidence_idx);
      const std::size_t first = map.segments.size();
      if (to_local) {
        std::unique_ptr<OGRGeometry> g(f->GetGeometryRef() ? f->GetGeometryRef()->clone() : nullptr);
        if (g && g->transform(to_local.get()) != OGRERR_NONE)
          throw Error("cannot transform to local metres", file, 0, where + " geometry");
        addSegments(g.get(), 1.0, a, map, skipped);
      } else {
        addSegments(f->GetGeometryRef(), to_m, a, map, skipped);
      }
      for (std::size_t i = first; i < map.segments.size(); ++i) {  // e.g. 1e400 in GeoJSON reads as inf
        if (!map.segments[i].a.allFinite() || !map.segments[i].b.allFinite())
          throw Error("non-finite coordinate (after scaling to metres)", file, 0, where + " geometry");
      }
    }
  }
  return map;
}

}  // namespace glassmap
