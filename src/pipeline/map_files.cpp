#include "glassmap/pipeline/map_files.hpp"

#include "glassmap/core/labels.hpp"
#include "glassmap/io/render_labels.hpp"
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
                                                 bool floorplan_files) {
  const glass::CellEvidence& e = result.evidence;
  std::filesystem::create_directories(dir);
  std::vector<std::filesystem::path> written;
  writeRosMap(dir / "map.yaml", toRosMap(e));
  written.push_back(dir / "map.yaml");
  written.push_back(dir / "map.pgm");
  writeLabelRaster(dir / "labels.tif", toLabelRaster(e));
  written.push_back(dir / "labels.tif");
  writeLabelsPng(dir / "map.png", e.geometry.width, e.geometry.height, e.label, e.bins);
  written.push_back(dir / "map.png");
  if (floorplan_files && result.has_floorplan) {
    const auto files = vector::writeFloorplanSet(dir / "floorplan", result.floorplan.map);
    written.insert(written.end(), files.begin(), files.end());
  }
  return written;
}

}  // namespace glassmap::pipeline
