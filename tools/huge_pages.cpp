#include "huge_pages.hpp"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <system_error>

namespace glassmap::cli {

std::string thpMode(std::string_view enabled_file) {
  const std::size_t open = enabled_file.find('[');
  if (open == std::string_view::npos) return {};
  const std::size_t close = enabled_file.find(']', open);
  if (close == std::string_view::npos) return {};
  return std::string(enabled_file.substr(open + 1, close - open - 1));
}

std::string kernelThpMode() {
  std::ifstream file("/sys/kernel/mm/transparent_hugepage/enabled");
  return thpMode(std::string((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>()));
}

std::optional<std::string> hugePageTunables(const char* tunables, std::string_view thp_mode, const char* opt_out,
                                            const char* preload) {
  if (opt_out && std::string_view(opt_out) == "0") return std::nullopt;
  if (underValgrind(preload)) return std::nullopt;
  if (thp_mode != "madvise") return std::nullopt;
  const std::string_view current = tunables ? tunables : "";
  if (current.find("glibc.malloc.hugetlb") != std::string_view::npos) return std::nullopt;
  std::string out(current);
  if (!out.empty()) out += ':';
  out += "glibc.malloc.hugetlb=1";
  return out;
}

bool underValgrind(const char* preload) {
  return preload && std::string_view(preload).find("vgpreload") != std::string_view::npos;
}

bool mallocReadsTunables() {
#if !defined(__GLIBC__) || defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  return false;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
  return false;
#else
  return true;
#endif
#else
  return true;
#endif
}

TunablesChange requestHugePages() {
  TunablesChange change;
  if (!mallocReadsTunables()) return change;
  const char* before = std::getenv("GLIBC_TUNABLES");
  const std::optional<std::string> tunables =
      hugePageTunables(before, kernelThpMode(), std::getenv("GLASSMAP_HUGE_PAGES"), std::getenv("LD_PRELOAD"));
  if (!tunables) return change;
  if (before) change.before = std::string(before);
  change.changed = setenv("GLIBC_TUNABLES", tunables->c_str(), 1) == 0;
  return change;
}

void useHugePages(char** argv) {
  const TunablesChange change = requestHugePages();
  if (!change.changed) return;
  execv("/proc/self/exe", argv);
  // Still here: no /proc, or the binary is gone. Carry on as we are.
  if (change.before) {
    setenv("GLIBC_TUNABLES", change.before->c_str(), 1);
  } else {
    unsetenv("GLIBC_TUNABLES");
  }
}

std::string programBeside(const char* argv0, std::string_view name) {
  std::string self;
  std::error_code error;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", error);
  if (!error) {
    self = exe.string();
  } else if (argv0 && std::string_view(argv0).find('/') != std::string_view::npos) {
    self = argv0;
  } else {
    return std::string(name);
  }
  return (std::filesystem::path(self).parent_path() / name).string();
}

}  // namespace glassmap::cli
