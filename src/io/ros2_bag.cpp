#include "glassmap/io/ros2_bag.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <fstream>

#include "glassmap/core/error.hpp"
#include "mcap_format.hpp"
#include "mcap_reader.hpp"
#include "ros2_bag_detail.hpp"
#include "sqlite_bag.hpp"

namespace glassmap::ros2 {

FileKind sniffFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  // The SQLite header is 100 bytes; its application id (bytes 68-71) says "GPKG" in a GeoPackage,
  // an SQLite file that is a floorplan, not a bag.
  std::array<char, 72> head{};
  in.read(head.data(), head.size());
  const std::streamsize got = in.gcount();
  if (got < static_cast<std::streamsize>(mcap::kMagic.size())) return FileKind::Other;
  if (std::equal(mcap::kMagic.begin(), mcap::kMagic.end(), reinterpret_cast<const std::uint8_t*>(head.data())))
    return FileKind::Mcap;
  if (got >= 16 && std::memcmp(head.data(), "SQLite format 3\0", 16) == 0)
    return got == 72 && std::memcmp(head.data() + 68, "GPKG", 4) == 0 ? FileKind::Other : FileKind::Sqlite;
  return FileKind::Other;
}

std::unique_ptr<BagReader> openBagFile(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw Error("no such bag file", path.string());
  switch (sniffFile(path)) {
    case FileKind::Mcap: return std::make_unique<McapFileReader>(path);
    case FileKind::Sqlite: return std::make_unique<SqliteFileReader>(path);
    case FileKind::Other: break;
  }
  throw Error("not a ROS 2 bag: neither the MCAP magic nor an SQLite header at byte 0", path.string());
}

bool isBag(const std::filesystem::path& path) {
  try {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) return std::filesystem::is_regular_file(path / "metadata.yaml", ec);
    return std::filesystem::is_regular_file(path, ec) && sniffFile(path) != FileKind::Other;
  } catch (...) {
    return false;
  }
}

std::unique_ptr<BagReader> openBag(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return openBagDirectory(path);
  if (!std::filesystem::exists(path, ec)) throw Error("no such bag (file or folder)", path.string());
  return openBagFile(path);
}

}  // namespace glassmap::ros2
