#pragma once
// Compression of MCAP chunks and rosbag2 files/messages: zstd (libzstd) and lz4 frames (liblz4).
// Private to the io module.

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "glassmap/io/ros2_bag.hpp"

namespace glassmap::ros2 {

/// MCAP's name of a compression ("", "zstd", "lz4").
std::string compressionName(BagCompression c);

/// Compresses `in` as one zstd or lz4 frame (None: a copy).
std::vector<std::uint8_t> compressBytes(BagCompression c, std::span<const std::uint8_t> in);

/// Decompresses `in` compressed with MCAP compression `name` into `out`, which must come out at
/// exactly `expected` bytes. Output grows with what the decoder produces, never beyond
/// `expected`, and `expected` itself is refused above max(64 MiB, 256 × input size), so a hostile
/// length field cannot allocate more than the data can justify. Throws Error naming `where`
/// (file and byte offset) on an unknown compression, a corrupt stream or a size mismatch.
void decompressBytes(const std::string& name, std::span<const std::uint8_t> in, std::uint64_t expected,
                     std::vector<std::uint8_t>& out, const std::string& file, const std::string& where);

/// Decompresses one zstd frame of unknown size (a rosbag2 MESSAGE-mode message), limited as above.
void zstdDecompressAny(std::span<const std::uint8_t> in, std::vector<std::uint8_t>& out, const std::string& file,
                       const std::string& where);

/// Decompresses the zstd file `in` (rosbag2 FILE mode) into `out`, streaming. Throws Error naming `in`.
void zstdDecompressFile(const std::filesystem::path& in, const std::filesystem::path& out);

/// Compresses the file `in` into the zstd file `out`, streaming. Throws Error naming the failing file.
void zstdCompressFile(const std::filesystem::path& in, const std::filesystem::path& out);

}  // namespace glassmap::ros2
