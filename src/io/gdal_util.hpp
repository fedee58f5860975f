#pragma once
// Private GDAL plumbing of the io module: one-time driver registration and error capture.

#include <cpl_error.h>
#include <gdal.h>
#include <ogr_api.h>

#include <string>
#include <vector>

namespace glassmap::io_detail {

/// Registers all GDAL/OGR drivers once per process (thread-safe).
void ensureGdalRegistered();

/// While alive, GDAL's messages on this thread go here instead of stderr.
class GdalErrorCollector {
 public:
  GdalErrorCollector();
  ~GdalErrorCollector();
  GdalErrorCollector(const GdalErrorCollector&) = delete;
  GdalErrorCollector& operator=(const GdalErrorCollector&) = delete;

  /// ": msg1; msg2" for appending to an error message, or "" when GDAL said nothing.
  std::string suffix() const;
  const std::vector<std::string>& messages() const { return messages_; }
  /// Number of CE_Failure / CE_Fatal messages so far.
  std::size_t failures() const { return failures_; }

 private:
  static void CPL_STDCALL handler(CPLErr level, CPLErrorNum num, const char* msg);
  std::vector<std::string> messages_;
  std::size_t failures_ = 0;
};

}  // namespace glassmap::io_detail
