// Writing floorplans: GDAL vector formats (read back and counted before the rename), shapefile
// sets, DXF with our header and XDATA.
#include "glassmap/io/floorplan.hpp"
#include "glassmap/io/floorplan_extras.hpp"

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
#include "glassmap/core/angles.hpp"
#include "glassmap/core/atomic_file.hpp"
#include "glassmap/core/error.hpp"
#include "text_parse.hpp"

namespace glassmap {

namespace fs = std::filesystem;
using io_detail::GdalErrorCollector;
using io_detail::lower;

namespace {

void checkSegments(const VectorMap& map) {
  for (std::size_t i = 0; i < map.segments.size(); ++i) {
    const MapSegment& s = map.segments[i];
    if (!s.a.allFinite() || !s.b.allFinite() || !std::isfinite(s.thickness))
      throw Error("segment " + std::to_string(i) + " has a non-finite coordinate or thickness");
  }
}

/// Reads `path` back with the one driver that wrote it and checks that every segment reached the
/// disk. Some GDAL drivers (GeoJSON, FlatGeobuf) do not check their writes: on a full disk or
/// past a file-size limit they leave a truncated file and report success.
void verifyWritten(const fs::path& path, FloorplanFormat format, std::size_t expected) {
  syncToDisk(path);
  GdalErrorCollector errors;
  const std::string driver_name(gdalDriverName(format));
  const char* drivers[] = {driver_name.c_str(), nullptr};
  GDALDatasetUniquePtr ds(GDALDataset::Open(path.string().c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, drivers));
  const std::string why = " (disk full, or a file-size limit?)";
  if (!ds) throw Error("the file written does not read back" + why + errors.suffix(), path.string());
  // Counted one by one: a truncated file's header may still promise every feature.
  std::size_t count = 0;
  for (OGRLayer* layer : ds->GetLayers()) {
    layer->ResetReading();
    while (OGRFeatureUniquePtr f{layer->GetNextFeature()}) ++count;
  }
  if (count != expected)
    throw Error("only " + std::to_string(count) + " of " + std::to_string(expected) + " segments reached the file" +
                    why + errors.suffix(),
                path.string());
}

/// Writes the extra layers: GPKG as layers of their own (clutter, doors, rooms), GeoJSON and DXF
/// into the one layer of the file (GeoJSON: member `layer` CLUTTER, DOOR, ROOM; DXF: layers
/// CLUTTER, DOOR, ROOMS, rooms as closed polylines).
void writeExtras(GDALDataset& ds, OGRLayer* main, FloorplanFormat format, OGRSpatialReference* srs,
                 const FloorplanExtras& x, const fs::path& target) {
  GdalErrorCollector errors;
  const auto fail = [&](const std::string& what) { throw Error(what + errors.suffix(), target.string()); };
  const auto line = [](const Vec2& a, const Vec2& b) {
    auto l = std::make_unique<OGRLineString>();
    l->addPoint(a.x(), a.y());
    l->addPoint(b.x(), b.y());
    return l;
  };
  const auto outline = [](const RoomPolygon& r) {
    auto l = std::make_unique<OGRLinearRing>();
    for (const Vec2& p : r.ring) l->addPoint(p.x(), p.y());
    l->closeRings();
    return l;
  };
  const auto put = [&](OGRLayer* layer, OGRFeature& f, std::unique_ptr<OGRGeometry> g) {
    f.SetGeometryDirectly(g.release());
    if (layer->CreateFeature(&f) != OGRERR_NONE) fail("cannot write feature (disk full, or a file-size limit?)");
  };
  const auto field = [&](OGRLayer* layer, const char* name, OGRFieldType type) {
    OGRFieldDefn def(name, type);
    if (layer->CreateField(&def) != OGRERR_NONE) fail(std::string("cannot create field ") + name);
  };
  OGRLayer* clutter = main;
  OGRLayer* doors = main;
  OGRLayer* rooms = main;
  if (format == FloorplanFormat::Gpkg) {
    clutter = ds.CreateLayer("clutter", srs, wkbLineString, nullptr);
    doors = ds.CreateLayer("doors", srs, wkbLineString, nullptr);
    rooms = ds.CreateLayer("rooms", srs, wkbPolygon, nullptr);
    if (!clutter || !doors || !rooms) fail("cannot create the clutter, doors and rooms layers");
    for (const char* f : {"material", "thickness", "support", "evidence"})
      field(clutter, f,
            f == std::string("material")  ? OFTString
            : f == std::string("support") ? OFTInteger64
                                          : OFTReal);
    field(doors, "width", OFTReal);
    field(rooms, "id", OFTInteger);
    field(rooms, "area", OFTReal);
  }
  const bool dxf = format == FloorplanFormat::Dxf;
  const auto tag = [&](OGRFeature& f, const char* json_layer, const char* dxf_layer) {
    if (dxf) f.SetField("Layer", dxf_layer);
    if (format == FloorplanFormat::GeoJson) f.SetField("layer", json_layer);
  };
  const bool in_transaction = ds.StartTransaction(FALSE) == OGRERR_NONE;
  for (const MapSegment& s : x.clutter.segments) {
    OGRFeature f(clutter->GetLayerDefn());
    tag(f, "CLUTTER", "CLUTTER");
    if (!dxf) {
      f.SetField("material", "clutter");  // not a wall to a GIS filtering on it
      f.SetField("thickness", s.thickness);
      f.SetField("support", static_cast<GIntBig>(s.support));
      f.SetField("evidence", s.evidence);
    }
    put(clutter, f, line(s.a, s.b));
  }
  for (const DoorOpening& d : x.doors) {
    OGRFeature f(doors->GetLayerDefn());
    tag(f, "DOOR", "DOOR");
    if (!dxf) f.SetField("width", d.width());
    put(doors, f, line(d.a, d.b));
  }
  for (const RoomPolygon& r : x.rooms) {
    OGRFeature f(rooms->GetLayerDefn());
    tag(f, "ROOM", "ROOMS");
    if (dxf) {  // a closed polyline (GDAL would write a polygon as a HATCH)
      auto ring = outline(r);
      auto l = std::make_unique<OGRLineString>();
      l->addSubLineString(ring.get());
      put(rooms, f, std::move(l));
      continue;
    }
    f.SetField("id", r.id);
    f.SetField("area", r.area);
    auto poly = std::make_unique<OGRPolygon>();
    poly->addRingDirectly(outline(r).release());
    put(rooms, f, std::move(poly));
  }
  if (in_transaction && ds.CommitTransaction() != OGRERR_NONE) fail("cannot commit the features");
}

/// Writes the features of `map` (and of `extras`, in the formats that hold them) into a new
/// dataset at `target` with GDAL.
void writeWithGdal(const fs::path& target, const VectorMap& map, FloorplanFormat format, const fs::path& dxf_header,
                   const FloorplanGeoref* georef, const FloorplanExtras* extras) {
  GdalErrorCollector errors;
  const std::string driver_name(gdalDriverName(format));
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName(driver_name.c_str());
  if (!driver) throw Error("GDAL has no " + driver_name + " driver", target.string());
  CPLStringList ds_options;
  if (format == FloorplanFormat::Dxf) ds_options.SetNameValue("HEADER", dxf_header.string().c_str());
  GDALDatasetUniquePtr ds(driver->Create(target.string().c_str(), 0, 0, 0, GDT_Unknown, ds_options.List()));
  if (!ds) throw Error("cannot create " + driver_name + " file" + errors.suffix(), target.string());

  OGRSpatialReference srs;
  srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);  // easting, northing
  const bool with_crs = format == FloorplanFormat::Gpkg || format == FloorplanFormat::Shapefile ||
                        format == FloorplanFormat::FlatGeobuf || (georef && format == FloorplanFormat::GeoJson);
  if (georef) {
    if (srs.SetFromUserInput(georef->crs.c_str()) != OGRERR_NONE)
      throw Error("unknown CRS '" + georef->crs + "'" + errors.suffix(), {}, 0, "crs");
    if (!srs.IsProjected() || std::abs(srs.GetLinearUnits() - 1.0) > 1e-9)
      throw Error("'" + georef->crs + "' is not a projected CRS in metres (a floorplan needs metric easting/northing)",
                  {}, 0, "crs");
  } else if (with_crs && srs.importFromWkt(std::string(io_detail::kLocalWkt).c_str()) != OGRERR_NONE) {
    throw Error("cannot build the local metric CRS" + errors.suffix());
  }
  CPLStringList layer_options;
  if (format == FloorplanFormat::FlatGeobuf) layer_options.SetNameValue("SPATIAL_INDEX", "NO");
  if (format == FloorplanFormat::GeoJson) {
    layer_options.SetNameValue("RFC7946", "NO");
    // Read back as local metres; a georeferenced file names its CRS and records its map frame.
    if (!georef) {
      layer_options.SetNameValue("DESCRIPTION", io_detail::kGeoJsonMarker);
    } else {
      char text[200];
      std::snprintf(text, sizeof text, "%s%.6f %.6f %.12f", io_detail::kGeoJsonOriginPrefix, georef->origin.x(),
                    georef->origin.y(), georef->origin.theta);
      layer_options.SetNameValue("DESCRIPTION", text);
    }
  }
  if (format == FloorplanFormat::Shapefile) layer_options.SetNameValue("ENCODING", "UTF-8");
  const bool mixed = extras && format == FloorplanFormat::GeoJson;  // one layer: lines and room polygons
  OGRLayer* layer = ds->CreateLayer(io_detail::kFloorplanLayerName, with_crs ? &srs : nullptr,
                                    mixed ? wkbUnknown : wkbLineString, layer_options.List());
  if (!layer) throw Error("cannot create layer" + errors.suffix(), target.string());
  if (georef && format == FloorplanFormat::Gpkg) {
    char origin[128];
    std::snprintf(origin, sizeof origin, "%.6f %.6f %.12f", georef->origin.x(), georef->origin.y(),
                  georef->origin.theta);
    layer->SetMetadataItem(io_detail::kMapFrameOriginKey, origin);
  }

  if (format != FloorplanFormat::Dxf) {
    auto field = [&](const char* name, OGRFieldType type, int width = 0) {
      OGRFieldDefn def(name, type);
      if (width) def.SetWidth(width);
      if (layer->CreateField(&def) != OGRERR_NONE)
        throw Error(std::string("cannot create field ") + name + errors.suffix(), target.string());
    };
    field("material", OFTString, 8);
    field("thickness", OFTReal);
    field("pane_angle", OFTReal);
    field("support", OFTInteger64);
    field("evidence", OFTReal);
    if (mixed) {
      field("layer", OFTString, 8);
      field("width", OFTReal);
      field("id", OFTInteger);
      field("area", OFTReal);
    }
  }
  OGRFeatureDefn* defn = layer->GetLayerDefn();
  // One transaction where the driver has them (GeoPackage): one commit instead of one per feature.
  const bool in_transaction = ds->StartTransaction(FALSE) == OGRERR_NONE;
  for (const MapSegment& s : map.segments) {
    OGRFeatureUniquePtr f(OGRFeature::CreateFeature(defn));
    if (format == FloorplanFormat::Dxf) {
      f->SetField("Layer", s.material == Material::Glass ? "GLASS" : "WALL");
    } else {
      if (mixed) f->SetField("layer", s.material == Material::Glass ? "GLASS" : "WALL");
      f->SetField("material", std::string(toString(s.material)).c_str());
      f->SetField("thickness", s.thickness);
      f->SetField("pane_angle", s.pane_angle);
      f->SetField("support", static_cast<GIntBig>(s.support));
      f->SetField("evidence", s.evidence);
    }
    OGRLineString line;
    line.addPoint(s.a.x(), s.a.y());
    line.addPoint(s.b.x(), s.b.y());
    f->SetGeometry(&line);
    if (layer->CreateFeature(f.get()) != OGRERR_NONE)
      throw Error("cannot write feature (disk full, or a file-size limit?)" + errors.suffix(), target.string());
  }
  if (in_transaction && ds->CommitTransaction() != OGRERR_NONE)
    throw Error("cannot commit the features" + errors.suffix(), target.string());
  if (extras) writeExtras(*ds, layer, format, with_crs ? &srs : nullptr, *extras, target);
  const std::size_t failures_before_close = errors.failures();
  ds.reset();  // closes the file: GDAL writes indexes and trailers here
  if (errors.failures() > failures_before_close)
    throw Error("cannot finish writing" + errors.suffix(), target.string());
  if (format != FloorplanFormat::Dxf)
    verifyWritten(target, format, map.segments.size() + (extras ? extras->features() : 0));
}

void writeShapefile(const fs::path& target, const VectorMap& map, const FloorplanGeoref* georef) {
  // A shapefile is several files: build them in a temporary folder, then move each into place,
  // the .shp last so that a reader never sees a .shp without its sidecars.
  const fs::path dir = temporarySibling(target.parent_path() / (target.stem().string() + ".dir"));
  // Registered before it exists: a signal between creating and registering would leave it behind.
  const LiveTemporary live_dir(dir, /*is_directory=*/true);  // removed by a SIGINT/SIGTERM handler too
  std::error_code ec;
  fs::create_directory(dir, ec);
  if (ec) throw Error("cannot create temporary folder: " + ec.message(), dir.string());
  try {
    try {
      writeWithGdal(dir / target.filename(), map, FloorplanFormat::Shapefile, {}, georef, nullptr);
    } catch (const Error& e) {
      throw Error(e.message(), target.string(), e.line(), e.field());  // the user's path, not ours
    }
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(dir)) files.push_back(entry.path());
    std::sort(files.begin(), files.end(), [](const fs::path& a, const fs::path& b) {
      return (lower(a.extension().string()) == ".shp") < (lower(b.extension().string()) == ".shp");
    });
    for (const fs::path& f : files) {
      fs::path dest = target.parent_path() / f.filename();
      fs::rename(f, dest, ec);
      if (ec) throw Error("cannot move shapefile part into place: " + ec.message(), dest.string());
    }
    fs::remove(dir, ec);
  } catch (...) {
    fs::remove_all(dir, ec);
    throw;
  }
}

}  // namespace

namespace {

void writeIn(const fs::path& path, const VectorMap& map, const FloorplanGeoref* georef, const FloorplanExtras* extras) {
  const FloorplanFormat format = floorplanFormatFromPath(path);
  checkSegments(map);
  // Shapefile and FlatGeobuf hold one layer of one geometry type: the walls and glass only.
  if (extras && (extras->empty() || format == FloorplanFormat::Shapefile || format == FloorplanFormat::FlatGeobuf))
    extras = nullptr;
  if (extras) checkSegments(extras->clutter);
  io_detail::ensureGdalRegistered();
  switch (format) {
    case FloorplanFormat::Shapefile: writeShapefile(path, map, georef); return;
    case FloorplanFormat::Dxf: {
      // The header template (metres, layers WALL and GLASS) lives in a temporary file beside the
      // output; the entities get their attributes as XDATA after GDAL has written them.
      const fs::path header = temporarySibling(path.parent_path() / (path.stem().string() + "-header.dxf"));
      struct Remove {
        fs::path p;
        ~Remove() {
          std::error_code ec;
          fs::remove(p, ec);
        }
      } remove_header{header};
      const LiveTemporary live_header(header);
      io_detail::writeDxfHeaderTemplate(header);
      writeAtomically(path, [&](const fs::path& tmp) {
        writeWithGdal(tmp, map, format, header, georef, extras);
        io_detail::addDxfXData(tmp, map, extras ? extras->features() : 0);
        verifyWritten(tmp, format, map.segments.size() + (extras ? extras->features() : 0));
      });
      return;
    }
    default: writeAtomically(path, [&](const fs::path& tmp) { writeWithGdal(tmp, map, format, {}, georef, extras); });
  }
}

// The map frame moved into the building's CRS.
Vec2 place(const FloorplanGeoref& g, const Vec2& p) { return g.origin * p; }

VectorMap placed(const VectorMap& map, const FloorplanGeoref& georef) {
  VectorMap out = map;
  for (MapSegment& s : out.segments) {
    s.a = place(georef, s.a);
    s.b = place(georef, s.b);
    s.pane_angle = std::fmod(std::fmod(s.pane_angle + georef.origin.theta, kPi) + kPi, kPi);  // [0, pi)
  }
  return out;
}

}  // namespace

void writeFloorplan(const fs::path& path, const VectorMap& map) { writeIn(path, map, nullptr, nullptr); }

void writeFloorplan(const fs::path& path, const VectorMap& map, const FloorplanGeoref& georef) {
  writeIn(path, placed(map, georef), &georef, nullptr);
}

void writeFloorplan(const fs::path& path, const VectorMap& map, const FloorplanExtras& extras,
                    const FloorplanGeoref* georef) {
  if (!georef) return writeIn(path, map, nullptr, &extras);
  FloorplanExtras moved = extras;
  moved.clutter = placed(extras.clutter, *georef);
  for (DoorOpening& d : moved.doors) d.a = place(*georef, d.a), d.b = place(*georef, d.b);
  for (RoomPolygon& r : moved.rooms)
    for (Vec2& p : r.ring) p = place(*georef, p);
  writeIn(path, placed(map, *georef), georef, &moved);
}

}  // namespace glassmap
