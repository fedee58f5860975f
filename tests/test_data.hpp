#pragma once
// The project's shared data folder (real logs, benchmark floorplans), a sibling of the clone:
// its paths, and the one way a test skips when a file of it is missing.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace glassmap::test {

/// Path of `relative` (e.g. "real/intel-corrected.log.gz") in the shared data folder.
inline std::filesystem::path sharedData(const std::string& relative) {
  return std::filesystem::path(GLASSMAP_SOURCE_DIR) / ".." / "shared" / "data" / relative;
}

/// The skip message for a missing shared data file or folder.
inline std::string missingSharedData(const std::filesystem::path& path) {
  return "shared data missing: " + path.lexically_normal().string() +
         " (the shared data folder lives beside the clone)";
}

}  // namespace glassmap::test

/// Skips the calling test (GTEST_SKIP returns from it) when `path` does not exist.
#define GLASSMAP_REQUIRE_SHARED_DATA(path) \
  if (!std::filesystem::exists(path)) GTEST_SKIP() << ::glassmap::test::missingSharedData(path)
