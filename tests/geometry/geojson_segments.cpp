#include "geojson_segments.hpp"

#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace glassmap::test {

VectorMap readGeoJsonSegments(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  const nlohmann::json doc = nlohmann::json::parse(in);
  VectorMap map;
  for (const auto& feature : doc.at("features")) {
    const auto& props = feature.at("properties");
    const auto& geometry = feature.at("geometry");
    if (geometry.at("type") != "LineString") continue;
    const auto& coords = geometry.at("coordinates");
    MapSegment proto;
    proto.material = parseMaterial(props.value("material", std::string("wall")));
    proto.thickness = props.value("thickness", 0.1);
    for (std::size_t i = 1; i < coords.size(); ++i) {
      MapSegment s = proto;
      s.a = Vec2(coords[i - 1][0].get<double>(), coords[i - 1][1].get<double>());
      s.b = Vec2(coords[i][0].get<double>(), coords[i][1].get<double>());
      map.segments.push_back(s);
    }
  }
  return map;
}

}  // namespace glassmap::test
