#include "gdal_util.hpp"

#include <mutex>

namespace glassmap::io_detail {

void ensureGdalRegistered() {
  static std::once_flag once;
  std::call_once(once, [] { GDALAllRegister(); });
}

GdalErrorCollector::GdalErrorCollector() { CPLPushErrorHandlerEx(&GdalErrorCollector::handler, this); }

GdalErrorCollector::~GdalErrorCollector() { CPLPopErrorHandler(); }

void CPL_STDCALL GdalErrorCollector::handler(CPLErr level, CPLErrorNum, const char* msg) {
  if (level == CE_Debug || msg == nullptr) return;
  auto* self = static_cast<GdalErrorCollector*>(CPLGetErrorHandlerUserData());
  if (!self) return;
  self->messages_.emplace_back(msg);
  if (level == CE_Failure || level == CE_Fatal) ++self->failures_;
}

std::string GdalErrorCollector::suffix() const {
  std::string out;
  for (const std::string& m : messages_) out += (out.empty() ? ": GDAL: " : "; ") + m;
  return out;
}

}  // namespace glassmap::io_detail
