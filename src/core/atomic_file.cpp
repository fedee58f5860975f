#include "glassmap/core/atomic_file.hpp"

#include <unistd.h>

#include <atomic>
#include <string>
#include <system_error>

#include "glassmap/core/error.hpp"

namespace glassmap {

namespace fs = std::filesystem;

fs::path temporarySibling(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  std::string name(1, '.');
  name += target.stem().string();
  name += ".tmp";
  name += std::to_string(::getpid());
  name += '-';
  name += std::to_string(counter++);
  name += target.extension().string();
  return target.parent_path() / name;
}

void writeAtomically(const fs::path& target, const std::function<void(const fs::path&)>& write) {
  const fs::path tmp = temporarySibling(target);
  try {
    write(tmp);
    std::error_code ec;
    fs::rename(tmp, target, ec);
    if (ec) throw Error("cannot rename temporary output into place: " + ec.message(), target.string());
  } catch (...) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw;
  }
}

}  // namespace glassmap
