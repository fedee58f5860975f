#pragma once
// Pieces of the ROS 2 bag storage shared by its translation units. Private to the io module.

#include <filesystem>
#include <memory>

#include "glassmap/io/ros2_bag.hpp"

namespace glassmap::ros2 {

/// Storage of a single file told by content, or nothing when it is neither MCAP nor SQLite.
enum class FileKind { Mcap, Sqlite, Other };
FileKind sniffFile(const std::filesystem::path& path);

/// Opens one .mcap or .db3 file (told by content); throws Error naming it otherwise.
std::unique_ptr<BagReader> openBagFile(const std::filesystem::path& path);

/// Opens a rosbag2 directory through its metadata.yaml.
std::unique_ptr<BagReader> openBagDirectory(const std::filesystem::path& dir);

}  // namespace glassmap::ros2
