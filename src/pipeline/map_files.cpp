#include "glassmap/pipeline/map_files.hpp"

#include <algorithm>
#include <string>
#include <system_error>

#include "glassmap/core/atomic_file.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/core/labels.hpp"
#include "glassmap/io/render_labels.hpp"
#include "glassmap/io/sensor_profile.hpp"
#include "glassmap/vector/export.hpp"

namespace glassmap::pipeline {

OccupancyGridMap toRosMap(const glass::CellEvidence& e) {
  OccupancyGridMap m;
  m.width = e.geometry.width;
  m.height = e.geometry.height;
  m.resolution = e.geometry.resolution;
  m.origin = Pose2(e.geometry.origin, 0.0);
  m.data.resize(e.label.size());
  for (std::size_t i = 0; i < e.label.size(); ++i) {
    const int l = e.label[i];
    m.data[i] = l == kUnknown ? std::int8_t{-1} : l == kEmpty ? std::int8_t{0} : std::int8_t{100};
  }
  return m;
}

LabelRaster toLabelRaster(const glass::CellEvidence& e) {
  LabelRaster r;
  r.width = e.geometry.width;
  r.height = e.geometry.height;
  r.resolution = e.geometry.resolution;
  r.origin = e.geometry.origin;
  r.codes.resize(e.label.size());
  for (std::size_t i = 0; i < e.label.size(); ++i) r.codes[i] = labelToCode(e.label[i]);
  return r;
}

std::vector<std::filesystem::path> writeMapFiles(const std::filesystem::path& dir, const MapResult& result,
                                                 bool floorplan_files, const FloorplanGeoref* georef) {
  namespace fs = std::filesystem;
  const glass::CellEvidence& e = result.evidence;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw Error("cannot create the output folder: " + ec.message(), dir.string());
  const fs::path staging = temporarySibling(dir / "map-files");
  const LiveTemporary live(staging, /*is_directory=*/true);  // a signal removes it too
  fs::create_directory(staging, ec);
  if (ec) throw Error("cannot create a staging folder: " + ec.message(), dir.string());
  std::vector<fs::path> names;
  try {
    writeRosMap(staging / "map.yaml", toRosMap(e));
    writeLabelRaster(staging / "labels.tif", toLabelRaster(e));
    writeLabelsPng(staging / "map.png", e.geometry.width, e.geometry.height, e.label, e.bins);
    writeSensorProfile(staging / "sensor.yaml", result.profile);
    if (floorplan_files && result.has_floorplan)
      vector::writeFloorplanSet(staging / "floorplan", result.floorplan.map, vector::defaultFloorplanSet(),
                                result.floorplan.extras, georef);
    for (const auto& entry : fs::directory_iterator(staging)) names.push_back(entry.path().filename());
  } catch (const Error& err) {
    fs::remove_all(staging, ec);
    // Name the user's folder, not the staging one.
    throw Error(err.message(), (dir / fs::path(err.file()).filename()).string(), err.line(), err.field());
  } catch (...) {
    fs::remove_all(staging, ec);
    throw;
  }
  std::sort(names.begin(), names.end());

  // Swap in: the old manifest goes first, so an interrupted swap leaves a folder without one.
  fs::remove(dir / kMapManifest, ec);
  if (!(floorplan_files && result.has_floorplan))
    for (const char* ext : {".gpkg", ".geojson", ".dxf", ".svg", ".png"})
      fs::remove(dir / ("floorplan" + std::string(ext)), ec);
  std::vector<fs::path> written;
  for (const fs::path& name : names) {
    fs::rename(staging / name, dir / name, ec);
    if (ec) {
      const std::string why = ec.message();
      fs::remove_all(staging, ec);
      throw Error("cannot move the output into place: " + why, (dir / name).string());
    }
    written.push_back(dir / name);
  }
  fs::remove(staging, ec);
  return written;
}

}  // namespace glassmap::pipeline
