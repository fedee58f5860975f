#include "glassmap/io/ros_map.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>

#include "gdal_util.hpp"
#include "glassmap/core/atomic_file.hpp"
#include "glassmap/core/error.hpp"
#include "text_parse.hpp"

namespace glassmap {

namespace fs = std::filesystem;

namespace {

enum class MapMode { Trinary, Scale, Raw };

/// An 8-bit image as read from disk: row 0 is the top row. `shade` in [0, 1].
struct GrayImage {
  int width = 0, height = 0;
  std::vector<double> shade;      ///< brightness per pixel in [0, 1]
  std::vector<int> raw;           ///< pixel value (average of colour channels)
  std::vector<bool> transparent;  ///< alpha < 1 (only images with an alpha channel)
};

/// Largest map image read through GDAL (1 G pixels: a 50 km square at 5 cm).
constexpr std::size_t kMaxImagePixels = std::size_t{1} << 30;

/// Reads a PGM (P5 binary or P2 ASCII, maxval up to 65535).
GrayImage readPgm(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open map image", path.string());
  const std::string name = path.string();
  auto token = [&]() -> std::string {
    std::string t;
    int c;
    while ((c = in.get()) != EOF) {
      if (c == '#') {
        while ((c = in.get()) != EOF && c != '\n') {
        }
        continue;
      }
      if (std::isspace(c)) {
        if (!t.empty()) return t;
        continue;
      }
      t += static_cast<char>(c);
    }
    return t;
  };
  auto number = [&](const char* field) -> long {
    const std::string t = token();
    try {
      std::size_t used = 0;
      const long v = std::stol(t, &used);
      if (used != t.size() || v < 0) throw std::invalid_argument(t);
      return v;
    } catch (const std::exception&) {
      throw Error("bad PGM header: expected a non-negative integer, got '" + t + "'", name, 0, field);
    }
  };
  const std::string magic = token();
  if (magic != "P5" && magic != "P2") throw Error("not a PGM image (magic '" + magic + "', expected P5 or P2)", name);
  GrayImage img;
  const long w = number("width"), h = number("height"), maxval = number("maxval");
  if (w <= 0 || h <= 0 || w > 100000 || h > 100000) throw Error("implausible PGM size", name, 0, "width");
  if (maxval <= 0 || maxval > 65535) throw Error("PGM maxval must be 1..65535", name, 0, "maxval");
  img.width = static_cast<int>(w);
  img.height = static_cast<int>(h);
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  // The header's size must fit the data that follows before anything is allocated: a forged
  // header must not make us reserve gigabytes (P5: 1 or 2 bytes per pixel, P2: >= 2 characters).
  const std::streamoff here = in.tellg();
  in.seekg(0, std::ios::end);
  const std::streamoff end = in.tellg();
  in.seekg(here);
  const std::size_t avail = here >= 0 && end >= here ? static_cast<std::size_t>(end - here) : 0;
  const std::size_t need = magic == "P5" ? n * (maxval > 255 ? 2 : 1) : 2 * n - 1;
  if (need > avail)
    throw Error("PGM pixel data is truncated: " + std::to_string(w) + " x " + std::to_string(h) + " pixels need " +
                    std::to_string(need) + " bytes, the file has " + std::to_string(avail),
                name);
  img.raw.resize(n);
  if (magic == "P5") {
    const std::size_t bytes = maxval > 255 ? 2 : 1;
    std::vector<unsigned char> buf(n * bytes);
    in.read(reinterpret_cast<char*>(buf.data()), static_cast<std::streamsize>(buf.size()));
    if (static_cast<std::size_t>(in.gcount()) != buf.size())
      throw Error("PGM pixel data is truncated (" + std::to_string(in.gcount()) + " of " + std::to_string(buf.size()) +
                      " bytes)",
                  name);
    for (std::size_t i = 0; i < n; ++i) img.raw[i] = bytes == 2 ? (buf[2 * i] << 8) | buf[2 * i + 1] : buf[i];
  } else {
    for (std::size_t i = 0; i < n; ++i) {
      const std::string t = token();
      if (t.empty()) throw Error("PGM pixel data is truncated at pixel " + std::to_string(i), name);
      try {
        img.raw[i] = std::stoi(t);
      } catch (const std::exception&) {
        throw Error("bad PGM pixel '" + t + "' at pixel " + std::to_string(i), name);
      }
    }
  }
  img.shade.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (img.raw[i] > maxval) throw Error("PGM pixel exceeds maxval at pixel " + std::to_string(i), name);
    img.shade[i] = static_cast<double>(img.raw[i]) / static_cast<double>(maxval);
  }
  return img;
}

/// Reads any raster GDAL can open (PNG, BMP, TIFF, ...): grey, grey+alpha, RGB or RGBA.
GrayImage readRasterWithGdal(const fs::path& path) {
  io_detail::GdalErrorCollector errors;
  io_detail::ensureGdalRegistered();
  GDALDatasetH ds = GDALOpenEx(path.string().c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr);
  if (!ds) throw Error("cannot read map image" + errors.suffix(), path.string());
  struct Closer {
    GDALDatasetH ds;
    ~Closer() { GDALClose(ds); }
  } closer{ds};
  GrayImage img;
  img.width = GDALGetRasterXSize(ds);
  img.height = GDALGetRasterYSize(ds);
  const int bands = GDALGetRasterCount(ds);
  if (bands < 1) throw Error("map image has no bands", path.string());
  const std::size_t n = static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height);
  if (img.width <= 0 || img.height <= 0 || n > kMaxImagePixels)
    throw Error("implausible map image size " + std::to_string(img.width) + " x " + std::to_string(img.height) +
                    " (at most " + std::to_string(kMaxImagePixels) + " pixels)",
                path.string());
  // Each band scaled to [0, 255] the way map_server's image loader expands it: a 1-, 2- or 4-bit
  // image (NBITS) by its own maximum, a 16-bit one by 65535; a paletted image through its colours.
  const GDALRasterBandH first = GDALGetRasterBand(ds, 1);
  const GDALColorTableH palette = bands == 1 && GDALGetRasterColorInterpretation(first) == GCI_PaletteIndex
                                      ? GDALGetRasterColorTable(first)
                                      : nullptr;
  std::vector<std::vector<double>> px;
  for (int b = 0; b < bands; ++b) {
    const GDALRasterBandH band = GDALGetRasterBand(ds, b + 1);
    std::vector<std::uint16_t> v(n);
    if (GDALRasterIO(band, GF_Read, 0, 0, img.width, img.height, v.data(), img.width, img.height, GDT_UInt16, 0, 0) !=
        CE_None)
      throw Error("cannot read map image pixels" + errors.suffix(), path.string());
    double top = GDALGetRasterDataType(band) == GDT_Byte ? 255.0 : 65535.0;
    if (const char* nbits = GDALGetMetadataItem(band, "NBITS", "IMAGE_STRUCTURE")) {
      const int bits = std::atoi(nbits);
      if (bits >= 1 && bits <= 16) top = static_cast<double>((1 << bits) - 1);
    }
    if (palette) {  // indices -> red, green, blue, alpha
      const int entries = GDALGetColorEntryCount(palette);
      px.assign(4, std::vector<double>(n, 0.0));
      for (std::size_t i = 0; i < n; ++i) {
        if (v[i] >= entries)
          throw Error("palette index " + std::to_string(v[i]) + " past the colour table", path.string(), 0,
                      "pixel " + std::to_string(i));
        const GDALColorEntry* e = GDALGetColorEntry(palette, v[i]);
        px[0][i] = e->c1, px[1][i] = e->c2, px[2][i] = e->c3, px[3][i] = e->c4;
      }
      break;
    }
    px.emplace_back(n);
    for (std::size_t i = 0; i < n; ++i) px.back()[i] = std::min(255.0, v[i] * 255.0 / top);
  }
  const int channels = static_cast<int>(px.size());
  const int colour_bands = channels >= 3 ? 3 : 1;
  const bool has_alpha = channels == 2 || channels == 4;
  img.raw.resize(n);
  img.shade.resize(n);
  if (has_alpha) img.transparent.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    double sum = 0;
    for (int b = 0; b < colour_bands; ++b) sum += px[static_cast<std::size_t>(b)][i];
    img.raw[i] = static_cast<int>(std::lround(sum / colour_bands));
    img.shade[i] = sum / (255.0 * colour_bands);
    if (has_alpha) img.transparent[i] = px[static_cast<std::size_t>(channels - 1)][i] < 255.0;
  }
  return img;
}

bool isPgm(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  char m[2] = {0, 0};
  in.read(m, 2);
  return in.gcount() == 2 && m[0] == 'P' && (m[1] == '5' || m[1] == '2');
}

}  // namespace

OccupancyGridMap readRosMap(const fs::path& yaml_path) {
  const std::string yname = yaml_path.string();
  std::error_code ec;
  if (!fs::exists(yaml_path, ec)) throw Error("map YAML file does not exist" + io_detail::reason(ec), yname);
  YAML::Node doc;
  try {
    doc = YAML::LoadFile(yname);
  } catch (const YAML::Exception& e) {
    throw Error("bad YAML: " + e.msg, yname, e.mark.is_null() ? 0 : static_cast<std::size_t>(e.mark.line + 1));
  }
  if (!doc.IsMap()) throw Error("map YAML must be a mapping of keys", yname);
  auto need = [&](const char* key) {
    const YAML::Node node = doc[key];
    if (!node) throw Error("missing key", yname, 0, key);
    return node;
  };
  auto line = [](const YAML::Node& n) { return n.Mark().is_null() ? 0 : static_cast<std::size_t>(n.Mark().line + 1); };
  auto asDouble = [&](const YAML::Node& n, const char* key) {
    try {
      return n.as<double>();
    } catch (const YAML::Exception&) {
      throw Error("expected a number", yname, line(n), key);
    }
  };
  auto asString = [&](const YAML::Node& n, const char* key) {
    try {
      return n.as<std::string>();
    } catch (const YAML::Exception&) {  // a sequence or a map where a scalar belongs
      throw Error("expected a string", yname, line(n), key);
    }
  };
  OccupancyGridMap map;
  const YAML::Node image_node = need("image");
  const std::string image_name = asString(image_node, "image");
  if (image_name.empty()) throw Error("empty image name", yname, line(image_node), "image");
  map.resolution = asDouble(need("resolution"), "resolution");
  if (!(map.resolution > 0.0)) throw Error("must be positive", yname, line(doc["resolution"]), "resolution");
  const YAML::Node origin = need("origin");
  if (!origin.IsSequence() || origin.size() != 3) throw Error("expected [x, y, yaw]", yname, line(origin), "origin");
  map.origin = Pose2(asDouble(origin[0], "origin"), asDouble(origin[1], "origin"), asDouble(origin[2], "origin"));
  bool negate = false;
  if (const YAML::Node n = doc["negate"]) {
    try {
      negate = n.as<int>() != 0;
    } catch (const YAML::Exception&) {
      try {
        negate = n.as<bool>();
      } catch (const YAML::Exception&) {
        throw Error("expected 0, 1, true or false", yname, line(n), "negate");
      }
    }
  }
  const double occupied_thresh = doc["occupied_thresh"] ? asDouble(doc["occupied_thresh"], "occupied_thresh") : 0.65;
  const double free_thresh = doc["free_thresh"] ? asDouble(doc["free_thresh"], "free_thresh") : 0.196;
  MapMode mode = MapMode::Trinary;
  if (const YAML::Node n = doc["mode"]) {
    const std::string m = asString(n, "mode");
    if (m == "trinary")
      mode = MapMode::Trinary;
    else if (m == "scale")
      mode = MapMode::Scale;
    else if (m == "raw")
      mode = MapMode::Raw;
    else
      throw Error("expected trinary, scale or raw, got '" + m + "'", yname, line(n), "mode");
  }
  fs::path image_path = image_name;
  if (image_path.is_relative()) image_path = yaml_path.parent_path() / image_path;
  if (!fs::exists(image_path, ec))
    throw Error("image '" + image_path.string() + "' does not exist" + io_detail::reason(ec), yname, line(image_node),
                "image");
  const GrayImage img = isPgm(image_path) ? readPgm(image_path) : readRasterWithGdal(image_path);

  map.width = img.width;
  map.height = img.height;
  map.data.assign(static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height), -1);
  if (mode != MapMode::Raw) map.occupancy.assign(map.data.size(), 0.0f);
  map.occupied_thresh = occupied_thresh;
  map.free_thresh = free_thresh;
  for (int r = 0; r < img.height; ++r) {
    for (int c = 0; c < img.width; ++c) {
      const std::size_t src = static_cast<std::size_t>(r) * img.width + c;
      const std::size_t dst = static_cast<std::size_t>(img.height - 1 - r) * img.width + c;  // row flip
      std::int8_t value = -1;
      if (mode == MapMode::Raw) {
        value = static_cast<std::int8_t>(img.raw[src]);
      } else {
        const double occ = negate ? img.shade[src] : 1.0 - img.shade[src];
        map.occupancy[dst] = static_cast<float>(occ);
        if (mode == MapMode::Scale && !img.transparent.empty() && img.transparent[src]) {
          value = -1;
        } else if (occ > occupied_thresh) {
          value = 100;
        } else if (occ < free_thresh) {
          value = 0;
        } else if (mode == MapMode::Trinary) {
          value = -1;
        } else {
          value = static_cast<std::int8_t>(std::lround(99.0 * (occ - free_thresh) / (occupied_thresh - free_thresh)));
        }
      }
      map.data[dst] = value;
    }
  }
  return map;
}

void writeRosMap(const fs::path& yaml_path_in, const OccupancyGridMap& map) {
  if (map.width <= 0 || map.height <= 0 ||
      map.data.size() != static_cast<std::size_t>(map.width) * static_cast<std::size_t>(map.height))
    throw Error("occupancy grid has inconsistent size (" + std::to_string(map.width) + " x " +
                std::to_string(map.height) + ", " + std::to_string(map.data.size()) + " cells)");
  if (!(map.resolution > 0.0)) throw Error("occupancy grid resolution must be positive");
  fs::path yaml_path = yaml_path_in;
  if (yaml_path.extension() != ".yaml" && yaml_path.extension() != ".yml") yaml_path += ".yaml";
  fs::path pgm_path = yaml_path;
  pgm_path.replace_extension(".pgm");

  writeAtomically(pgm_path, [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw Error("cannot create", tmp.string());
    out << "P5\n# CREATOR: glassmap " << map.resolution << " m/pix\n" << map.width << ' ' << map.height << "\n255\n";
    std::vector<unsigned char> row(static_cast<std::size_t>(map.width));
    for (int r = map.height - 1; r >= 0; --r) {  // image top row = grid top row
      for (int c = 0; c < map.width; ++c) {
        const int v = map.at(c, r);
        row[static_cast<std::size_t>(c)] = v < 0 || v > 100 ? 205 : v >= 65 ? 0 : v <= 19 ? 254 : 205;
      }
      out.write(reinterpret_cast<const char*>(row.data()), static_cast<std::streamsize>(row.size()));
    }
    out.flush();
    if (!out) throw Error("write failed (disk full?)", pgm_path.string());
  });
  writeAtomically(yaml_path, [&](const fs::path& tmp) {
    YAML::Emitter e;
    e.SetDoublePrecision(17);
    e << YAML::BeginMap;
    e << YAML::Key << "image" << YAML::Value << pgm_path.filename().string();
    e << YAML::Key << "mode" << YAML::Value << "trinary";
    e << YAML::Key << "resolution" << YAML::Value << map.resolution;
    e << YAML::Key << "origin" << YAML::Value << YAML::Flow << YAML::BeginSeq << map.origin.x() << map.origin.y()
      << map.origin.theta << YAML::EndSeq;
    e << YAML::Key << "negate" << YAML::Value << 0;
    e << YAML::Key << "occupied_thresh" << YAML::Value << 0.65;
    e << YAML::Key << "free_thresh" << YAML::Value << 0.196;
    e << YAML::EndMap;
    std::ofstream out(tmp);
    if (!out) throw Error("cannot create", tmp.string());
    out << e.c_str() << "\n";
    out.flush();
    if (!out) throw Error("write failed (disk full?)", yaml_path.string());
  });
}

}  // namespace glassmap
