#pragma once
/// Shared part of the libFuzzer targets: the readers take paths, so each input is written to a
/// temporary file (in /dev/shm when present) with the extension the reader sniffs, then read.
/// A glassmap::Error is an accepted outcome; a crash, hang, leak or sanitizer report is not.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

namespace glassmap::fuzz {

/// Folder for the per-process scratch files.
inline std::filesystem::path scratchDir() {
  static const std::filesystem::path dir = [] {
    std::filesystem::path base = std::filesystem::exists("/dev/shm") ? std::filesystem::path("/dev/shm")
                                                                     : std::filesystem::temp_directory_path();
    auto d = base / ("glassmap-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

/// Writes bytes to <scratch>/<name> and returns the path.
inline std::filesystem::path writeScratch(std::string_view name, const std::uint8_t* data, std::size_t size) {
  auto path = scratchDir() / std::string(name);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  out.close();
  if (!out) std::abort();  // scratch space full: not a finding, but must not pass silently
  return path;
}

}  // namespace glassmap::fuzz
