#include "glassmap/core/error.hpp"

namespace glassmap {
namespace {

std::string compose(const std::string& message, const std::string& file, std::size_t line, const std::string& field) {
  std::string out;
  if (!file.empty()) {
    out += file;
    if (line > 0) out += ":" + std::to_string(line);
    out += ": ";
  }
  if (!field.empty()) out += field + ": ";
  return out + message;
}

}  // namespace

Error::Error(std::string message, std::string file, std::size_t line, std::string field)
    : std::runtime_error(compose(message, file, line, field)),
      message_(std::move(message)),
      file_(std::move(file)),
      line_(line),
      field_(std::move(field)) {}

}  // namespace glassmap
