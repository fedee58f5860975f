#include "cli_common.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <vector>

namespace glassmap::cli {
namespace {

std::vector<std::pair<int, Register>>& registry() {
  static std::vector<std::pair<int, Register>> verbs;
  return verbs;
}

}  // namespace

Registrar::Registrar(int order, Register fn) { registry().emplace_back(order, std::move(fn)); }

void registerAll(CLI::App& app) {
  auto& verbs = registry();
  std::stable_sort(verbs.begin(), verbs.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  for (auto& [order, fn] : verbs) fn(app);
}

bool stderrIsTerminal() { return ::isatty(STDERR_FILENO) == 1; }

std::size_t peakMemoryBytes() {
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  return static_cast<std::size_t>(usage.ru_maxrss) * 1024;  // Linux reports KiB
}

}  // namespace glassmap::cli
