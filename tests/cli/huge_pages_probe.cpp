// Runs useHugePages as the glassmap command does, then checks what happened: the program started
// again exactly when the kernel gives huge pages on request (and nothing opts out), with the
// tunable set and its arguments intact. The first start marks the environment, so the second knows
// it is one. Prints "huge pages probe passed" or the failure. Usage: huge_pages_probe first "second argument"
#include <unistd.h>

#include <cstdlib>
#include <iostream>
#include <string>
#include <string_view>

#include "huge_pages.hpp"

int main(int argc, char** argv) {
  constexpr const char* kMarker = "GLASSMAP_HUGE_PAGES_PROBE_STARTED";
  const bool started_again = std::getenv(kMarker) != nullptr;
  if (!started_again) setenv(kMarker, "1", 1);
  glassmap::cli::useHugePages(argv);
  // Still here in the first start: no new start happened.
  const std::string mode = glassmap::cli::kernelThpMode();
  const char* opt_out = std::getenv("GLASSMAP_HUGE_PAGES");
  const char* now = std::getenv("GLIBC_TUNABLES");
  const bool asked = now && std::string_view(now).find("glibc.malloc.hugetlb=1") != std::string_view::npos;
  // Without /proc no new start can happen, and the program carries on as it was.
  const bool expect = mode == "madvise" && glassmap::cli::mallocReadsTunables() &&
                      !(opt_out && std::string_view(opt_out) == "0") && access("/proc/self/exe", X_OK) == 0;
  std::cout << "kernel THP mode '" << mode << "', started again: " << started_again << ", GLIBC_TUNABLES "
            << (now ? now : "(unset)") << "\n";
  if (started_again != expect) {
    std::cout << "FAIL: the program " << (started_again ? "started" : "did not start") << " again\n";
    return 1;
  }
  if (asked != expect) {
    std::cout << "FAIL: the tunable is " << (asked ? "set" : "not set") << "\n";
    return 1;
  }
  if (argc != 3 || std::string_view(argv[1]) != "first" || std::string_view(argv[2]) != "second argument") {
    std::cout << "FAIL: the arguments did not survive the new start\n";
    return 1;
  }
  std::cout << "huge pages probe passed\n";
  return 0;
}
