// The extra layers of our floorplans (clutter, doors, rooms) and the map frame a georeferenced
// GPKG records: what readFloorplan skips or undoes, and readFloorplanExtras.
#include "glassmap/io/floorplan_extras.hpp"

#include <gdal_priv.h>
#include <ogr_geometry.h>
#include <ogrsf_frmts.h>

#include <cmath>
#include <cstdio>
#include <sstream>

#include "floorplan_detail.hpp"
#include "gdal_util.hpp"
#include "glassmap/core/error.hpp"

namespace glassmap {

namespace io_detail {

ExtraLayer extraLayerOf(bool ours, const char* ogr_layer, OGRFeature& f, const std::string& cad_layer) {
  const std::string l = lower(ogr_layer ? ogr_layer : "");
  if (ours) {  // a GPKG of ours: its layers by name
    if (l == "clutter") return ExtraLayer::Clutter;
    if (l == "doors") return ExtraLayer::Door;
    if (l == "rooms") return ExtraLayer::Room;
  }
  const int i = f.GetFieldIndex("layer");  // GeoJSON of ours: a member per feature
  const std::string tag = i >= 0 && f.IsFieldSetAndNotNull(i) ? lower(f.GetFieldAsString(i)) : lower(cad_layer);
  if (tag == "clutter") return ExtraLayer::Clutter;
  if (tag == "door") return ExtraLayer::Door;
  if (tag == "room" || tag == "rooms") return ExtraLayer::Room;
  return ExtraLayer::None;
}

std::optional<Pose2> mapFrameOrigin(OGRLayer& layer, const std::string& file) {
  const char* text = layer.GetMetadataItem(kMapFrameOriginKey);
  if (!text) {  // a GeoJSON of ours: in its description
    const char* d = layer.GetMetadataItem("DESCRIPTION");
    const std::string prefix = kGeoJsonOriginPrefix;
    if (!d || std::string(d).rfind(prefix, 0) != 0) return std::nullopt;
    text = d + prefix.size();
  }
  std::istringstream in(text);
  double e = 0, n = 0, rot = 0;
  std::string rest;
  if (!(in >> e >> n >> rot) || (in >> rest) || !std::isfinite(e) || !std::isfinite(n) || !std::isfinite(rot))
    throw Error("expected \"E N ROT_RAD\", got \"" + std::string(text) + "\"", file, 0,
                std::string("layer ") + layer.GetName() + " metadata " + kMapFrameOriginKey);
  return Pose2(e, n, rot);
}

bool hasFloorplanLayer(GDALDataset& ds) { return ds.GetLayerByName(kFloorplanLayerName) != nullptr; }

}  // namespace io_detail

FloorplanExtras readFloorplanExtras(const std::filesystem::path& path) {
  io_detail::ensureGdalRegistered();
  io_detail::GdalErrorCollector errors;
  const std::string ext = io_detail::lower(path.extension().string());
  if (ext != ".gpkg" && ext != ".geojson" && ext != ".json" && ext != ".dxf") return {};
  GDALDatasetUniquePtr ds(GDALDataset::Open(path.string().c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY));
  if (!ds) throw Error("cannot open as a vector floorplan" + errors.suffix(), path.string());
  const bool ours = io_detail::hasFloorplanLayer(*ds);
  // A georeferenced GPKG: every layer back into the map frame by the origin its floorplan records.
  std::optional<Pose2> origin;
  if (OGRLayer* main = ds->GetLayerByName(io_detail::kFloorplanLayerName))
    origin = io_detail::mapFrameOrigin(*main, path.string());
  const auto back = [&](double x, double y) {
    const Vec2 p(x, y);
    return origin ? Vec2(origin->inverse() * p) : p;
  };
  FloorplanExtras out;
  for (OGRLayer* layer : ds->GetLayers()) {
    const int cad = layer->GetLayerDefn()->GetFieldIndex("Layer");
    layer->ResetReading();
    for (auto& f : *layer) {
      const std::string cad_layer = cad >= 0 && f->IsFieldSetAndNotNull(cad) ? f->GetFieldAsString(cad) : "";
      const io_detail::ExtraLayer kind = io_detail::extraLayerOf(ours, layer->GetName(), *f, cad_layer);
      const OGRGeometry* g = f->GetGeometryRef();
      if (kind == io_detail::ExtraLayer::None || !g) continue;
      const OGRwkbGeometryType type = wkbFlatten(g->getGeometryType());
      if (kind == io_detail::ExtraLayer::Room) {
        const OGRLineString* ring = type == wkbPolygon      ? g->toPolygon()->getExteriorRing()
                                    : type == wkbLineString ? g->toLineString()
                                                            : nullptr;
        if (!ring) continue;
        RoomPolygon r;
        for (int i = 0; i + 1 < ring->getNumPoints(); ++i) r.ring.push_back(back(ring->getX(i), ring->getY(i)));
        const int id = f->GetFieldIndex("id"), area = f->GetFieldIndex("area");
        r.id = id >= 0 ? f->GetFieldAsInteger(id) : static_cast<int>(out.rooms.size()) + 1;
        r.area = area >= 0 ? f->GetFieldAsDouble(area) : 0.0;
        if (area < 0) {  // shoelace
          for (std::size_t i = 0; i < r.ring.size(); ++i) {
            const Vec2& a = r.ring[i];
            const Vec2& b = r.ring[(i + 1) % r.ring.size()];
            r.area += 0.5 * (a.x() * b.y() - b.x() * a.y());
          }
          r.area = std::abs(r.area);
        }
        out.rooms.push_back(std::move(r));
        continue;
      }
      if (type != wkbLineString) continue;
      const OGRLineString* l = g->toLineString();
      if (l->getNumPoints() < 2) continue;
      const Vec2 a = back(l->getX(0), l->getY(0)), b = back(l->getX(1), l->getY(1));
      if (kind == io_detail::ExtraLayer::Door) {
        out.doors.push_back({a, b});
      } else {
        MapSegment& s = out.clutter.add(a, b, Material::Wall);
        const int t = f->GetFieldIndex("thickness");
        if (t >= 0 && f->IsFieldSetAndNotNull(t)) s.thickness = f->GetFieldAsDouble(t);
      }
    }
  }
  return out;
}

}  // namespace glassmap
