// Reading floorplans through GDAL/OGR: any line source, materials from fields or layers, units
// and CRSs to local metres.
#include "glassmap/io/floorplan.hpp"

#include <cpl_vsi.h>
#include <gdal_priv.h>
#include <ogr_geometry.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <system_error>

#include "dxf_text.hpp"
#include "floorplan_detail.hpp"
#include "gdal_util.hpp"
#include "glassmap/core/angles.hpp"
#include "glassmap/core/atomic_file.hpp"
#include "glassmap/core/error.hpp"
#include "text_parse.hpp"

namespace glassmap {

namespace fs = std::filesystem;
using io_detail::GdalErrorCollector;
using io_detail::lower;

namespace {

constexpr double kDefaultThickness = 0.1;  // [m]

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

/// A file in GDAL's /vsimem/ over a buffer the caller keeps alive; unlinked at scope exit.
class MemFile {
 public:
  MemFile() = default;
  MemFile(const MemFile&) = delete;
  MemFile& operator=(const MemFile&) = delete;
  ~MemFile() {
    if (!file_) return;
    VSIFCloseL(file_);
    VSIUnlink(path_.c_str());
  }
  bool open(const std::string& path, std::string& buffer) {
    path_ = path;
    file_ = VSIFileFromMemBuffer(path.c_str(), reinterpret_cast<GByte*>(buffer.data()),
                                 static_cast<vsi_l_offset>(buffer.size()), FALSE);
    return file_ != nullptr;
  }

 private:
  std::string path_;
  VSILFILE* file_ = nullptr;
};

struct FeatureAttrs {
  Material material = Material::Wall;
  bool material_set = false;  // by a field or XDATA, not by the layer name
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
    if (key == "material") {
      try {
        a.material = parseMaterial(std::string(val));
        a.material_set = true;
      } catch (const Error& e) {
        throw Error(e.message(), file, 0, where);
      }
    } else if (key == "thickness") {
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

/// Rows of the read report by (layer, outcome, why), in order of first appearance.
class Tally {
 public:
  explicit Tally(FloorplanReadReport& r) : r_(r) {}
  void add(const std::string& layer, const std::string& outcome, const std::string& why, std::size_t segments) {
    const std::string key = layer + '\n' + outcome + '\n' + why;
    auto [it, added] = index_.try_emplace(key, r_.rows.size());
    if (added) r_.rows.push_back({layer, outcome, why, 0, 0});
    ++r_.rows[it->second].features;
    r_.rows[it->second].segments += segments;
  }

 private:
  FloorplanReadReport& r_;
  std::map<std::string, std::size_t> index_;
};

/// Why a DXF feature is not geometry of the building ("" when it is); see io_detail::dxfIgnoreReason.
std::string dxfIgnoreReason(OGRFeature& f, const io_detail::DxfScan& scan, const std::string& cad_layer) {
  auto text = [&](const char* name) {
    const int i = f.GetFieldIndex(name);
    return i >= 0 && f.IsFieldSetAndNotNull(i) ? std::string(f.GetFieldAsString(i)) : std::string();
  };
  const std::string paper = text("PaperSpace");
  return io_detail::dxfIgnoreReason(scan, !paper.empty() && paper != "0", text("EntityHandle"), text("SubClasses"),
                                    cad_layer);
}

}  // namespace

VectorMap readFloorplan(const fs::path& path, const FloorplanReadOptions& options) {
  io_detail::ensureGdalRegistered();
  GdalErrorCollector errors;
  const std::string file = path.string();
  std::error_code ec;
  if (!fs::exists(path, ec)) throw Error("floorplan file does not exist" + io_detail::reason(ec), file);
  FloorplanReadReport local_report;
  FloorplanReadReport& report = options.report ? *options.report : local_report;
  report = {};
  io_detail::DxfScan scan;
  std::string open_path = file;
  MemFile patched;
  if (lower(path.extension().string()) == ".dxf") {
    io_detail::checkDxfGroupCodes(path);
    scan = io_detail::scanDxf(path);
    if (!scan.patched.empty()) {  // GDAL reads the copy whose fit-point splines are polylines
      open_path = "/vsimem/glassmap_" + std::to_string(reinterpret_cast<std::uintptr_t>(&scan)) + "/" +
                  path.filename().string();
      if (!patched.open(open_path, scan.patched)) throw Error("cannot stage the DXF in memory", file);
      report.notes.push_back(std::to_string(scan.fit_splines) +
                             " spline(s) given only by fit points read as polylines through their fit points");
    }
  }
  ScopedConfig raw_codes("DXF_INCLUDE_RAW_CODE_VALUES", "TRUE");
  // Blocks are exploded entity by entity, so each keeps its own layer (or the INSERT's, for
  // entities on layer 0) and the handle of the INSERT or DIMENSION that drew it.
  ScopedConfig inline_blocks("DXF_INLINE_BLOCKS", "TRUE");
  ScopedConfig merge_blocks("DXF_MERGE_BLOCK_GEOMETRIES", "FALSE");
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
      GDALDataset::Open(open_path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, driver.empty() ? nullptr : allowed));
  if (!ds) throw Error("cannot open as a vector floorplan" + errors.suffix(), file);
  VectorMap map;
  map.name = path.stem().string();
  std::size_t skipped = 0;
  if (options.unit_in_metres < 0.0 || !std::isfinite(options.unit_in_metres))
    throw Error("unit_in_metres must be positive (or 0 for the file's own units)", file);
  const bool is_dxf = EQUAL(ds->GetDriverName(), "DXF");
  const double dxf_unit = is_dxf ? io_detail::dxfUnitInMetres(path) : 0.0;
  bool first_layer = true;
  const bool ours = io_detail::hasFloorplanLayer(*ds);
  Tally tally(report);
  std::map<std::string, std::size_t> unknown_layers;  // CAD layers read as wall by default: features
  std::size_t ignored = 0;
  const std::size_t gdal_failures = errors.failures();
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
      const io_detail::GeoJsonHead head = io_detail::geoJsonHead(path);
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
        to_local = io_detail::toLocalMetres(*srs, lon, lat, file);
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
    // A georeferenced plan of ours: read back in the map frame its origin says.
    std::optional<Pose2> frame = io_detail::mapFrameOrigin(*layer, file);
    if (frame && options.building_frame) frame.reset();
    if (frame) {
      char note[200];
      std::snprintf(note, sizeof note,
                    "layer %s: read back in the map frame (its origin at E %.3f N %.3f, x axis %.6f rad from east)",
                    layer->GetName(), frame->x(), frame->y(), frame->theta);
      report.notes.push_back(note);
    }
    OGRFeatureDefn* defn = layer->GetLayerDefn();
    const int material_idx = defn->GetFieldIndex("material");
    const int thickness_idx = defn->GetFieldIndex("thickness");
    const int angle_idx = defn->GetFieldIndex("pane_angle");
    const int support_idx = defn->GetFieldIndex("support");
    const int evidence_idx = defn->GetFieldIndex("evidence");
    const int dxf_layer_idx = defn->GetFieldIndex("Layer");
    const int raw_idx = defn->GetFieldIndex("RawCodeValues");
    layer->ResetReading();
    for (auto& f : *layer) {
      FeatureAttrs a;
      const std::string where = "feature " + std::to_string(f->GetFID());
      const bool has_cad = dxf_layer_idx >= 0 && f->IsFieldSetAndNotNull(dxf_layer_idx);
      const io_detail::ExtraLayer extra =
          io_detail::extraLayerOf(ours, layer->GetName(), *f, has_cad ? f->GetFieldAsString(dxf_layer_idx) : "");
      if (extra != io_detail::ExtraLayer::None && !(extra == io_detail::ExtraLayer::Clutter && options.clutter)) {
        tally.add(has_cad ? f->GetFieldAsString(dxf_layer_idx) : layer->GetName(), "ignored",
                  extra == io_detail::ExtraLayer::Clutter ? "glassmap's clutter layer (the building only)"
                                                          : "glassmap's door and room layers are not surfaces",
                  0);
        continue;
      }
      if (extra == io_detail::ExtraLayer::Clutter) {  // material "clutter": a surface, read as wall
        a.material = Material::Wall;
        a.material_set = true;
      } else if (material_idx >= 0 && f->IsFieldSetAndNotNull(material_idx)) {
        try {
          a.material = parseMaterial(f->GetFieldAsString(material_idx));
          a.material_set = true;
        } catch (const Error& e) {
          throw Error(e.message(), file, 0, where + " material");
        }
      }
      const bool has_cad_layer = dxf_layer_idx >= 0 && f->IsFieldSetAndNotNull(dxf_layer_idx);
      const std::string source_layer = has_cad_layer ? f->GetFieldAsString(dxf_layer_idx) : layer->GetName();
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
      std::string why = "material field";
      if (!a.material_set) {
        report.by_layer_names = true;
        why = is_dxf ? dxfIgnoreReason(*f, scan, source_layer) : std::string();
        if (why.empty()) {
          const LayerDecision d = classifyLayer(source_layer, options.layer_rules, has_cad_layer);
          why = d.why;
          if (d.role == LayerRole::Ignore) {
            ++ignored;
            tally.add(source_layer, "ignored", why, 0);
            continue;
          }
          a.material = d.role == LayerRole::Glass ? Material::Glass : Material::Wall;
          if (!d.known && has_cad_layer) ++unknown_layers[source_layer];
        } else {
          ++ignored;
          tally.add(source_layer, "ignored", why, 0);
          continue;
        }
      }
      const std::size_t first = map.segments.size();
      if (to_local) {
        std::unique_ptr<OGRGeometry> g(f->GetGeometryRef() ? f->GetGeometryRef()->clone() : nullptr);
        if (g && g->transform(to_local.get()) != OGRERR_NONE)
          throw Error("cannot transform to local metres", file, 0, where + " geometry");
        addSegments(g.get(), 1.0, a, map, skipped);
      } else {
        addSegments(f->GetGeometryRef(), to_m, a, map, skipped);
      }
      if (frame)
        for (std::size_t i = first; i < map.segments.size(); ++i) {
          MapSegment& s = map.segments[i];
          s.a = frame->inverse() * s.a;
          s.b = frame->inverse() * s.b;
          s.pane_angle = std::fmod(std::fmod(s.pane_angle - frame->theta, kPi) + kPi, kPi);
        }
      for (std::size_t i = first; i < map.segments.size(); ++i) {  // e.g. 1e400 in GeoJSON reads as inf
        if (!map.segments[i].a.allFinite() || !map.segments[i].b.allFinite())
          throw Error("non-finite coordinate (after scaling to metres)", file, 0, where + " geometry");
      }
      tally.add(source_layer, std::string(toString(a.material)), why, map.segments.size() - first);
    }
  }
  if (errors.failures() > gdal_failures)
    report.warnings.push_back("GDAL could not read " + std::to_string(errors.failures() - gdal_failures) +
                              " entities, missing from the plan (first: " + errors.messages().back() + ")");
  if (ignored > 0 && map.segments.empty())
    throw Error("every line of the floorplan was ignored (" + std::to_string(ignored) +
                    " features: annotation, doors, paper space, frozen or off layers, ...); say which layers are "
                    "walls and glass with --layers, e.g. \"wall=MYWALLS*;glass=MYGLASS*\"",
                file);
  if (!unknown_layers.empty()) {
    std::string names;
    for (const auto& [name, n] : unknown_layers)
      names += (names.empty() ? "" : ", ") + name + " (" + std::to_string(n) + ")";
    report.warnings.push_back("layer(s) with no known name read as wall: " + names +
                              "; map them with --layers \"wall=...;glass=...;ignore=...\"");
  }
  if (report.by_layer_names && !map.segments.empty() && map.count(Material::Wall) == 0)
    report.warnings.push_back("no line was read as wall: every line is glass");
  return map;
}

}  // namespace glassmap
