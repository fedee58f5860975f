#include "glassmap/geometry/vector_map.hpp"

#include <algorithm>
#include <cctype>
#include <string>

#include "glassmap/core/error.hpp"

namespace glassmap {

std::string_view toString(Material m) { return m == Material::Glass ? "glass" : "wall"; }

Material parseMaterial(std::string_view s) {
  std::string lower(s);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (lower == "glass") return Material::Glass;
  if (lower == "wall") return Material::Wall;
  throw Error("unknown material '" + std::string(s) + "' (expected wall or glass)", {}, 0, "material");
}

Eigen::AlignedBox2d VectorMap::bounds() const {
  Eigen::AlignedBox2d box;
  for (const auto& s : segments) {
    box.extend(s.a);
    box.extend(s.b);
  }
  return box;
}

std::size_t VectorMap::count(Material m) const {
  return static_cast<std::size_t>(
      std::count_if(segments.begin(), segments.end(), [m](const MapSegment& s) { return s.material == m; }));
}

}  // namespace glassmap
