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
  // The first messages and the last (the one nearest the failure); drivers repeat themselves.
  constexpr std::size_t kShown = 3;
  std::string out;
  for (std::size_t i = 0; i < messages_.size(); ++i) {
    if (i >= kShown && i + 1 < messages_.size()) {
      if (i == kShown) out += "; ... (" + std::to_string(messages_.size() - kShown - 1) + " more)";
      continue;
    }
    out += (out.empty() ? ": GDAL: " : "; ") + messages_[i];
  }
  return out;
}

}  // namespace glassmap::io_detail
