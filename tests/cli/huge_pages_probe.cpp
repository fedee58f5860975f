// Runs useHugePages as the glassmap command does, then checks what the process started with:
// the tunable set exactly when the kernel gives huge pages on request, and its arguments intact.
// Prints "huge pages probe passed" or the failure. Usage: huge_pages_probe ARG...
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <string_view>

#include "huge_pages.hpp"

int main(int argc, char** argv) {
  const char* before = std::getenv("GLIBC_TUNABLES");
  const bool asked_before = before && std::string_view(before).find("glibc.malloc.hugetlb") != std::string_view::npos;
  glassmap::cli::useHugePages(argv);
  std::ifstream file("/sys/kernel/mm/transparent_hugepage/enabled");
  const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const std::string mode = glassmap::cli::thpMode(text);
  const char* now = std::getenv("GLIBC_TUNABLES");
  const bool asked = now && std::string_view(now).find("glibc.malloc.hugetlb=1") != std::string_view::npos;
  const char* opt_out = std::getenv("GLASSMAP_HUGE_PAGES");
  // Without /proc no new start can happen, and the program carries on as it was.
  const bool expect = mode == "madvise" && glassmap::cli::mallocReadsTunables() &&
                      !(opt_out && std::string_view(opt_out) == "0") && access("/proc/self/exe", X_OK) == 0;
  std::cout << "kernel THP mode '" << mode << "', GLIBC_TUNABLES " << (now ? now : "(unset)") << "\n";
  // The first start: still here means no new start happened, right only where none is expected
  // (the new start finds the tunable already set and checks the arguments only).
  if (!asked_before && asked != expect) {
    std::cout << "FAIL: the tunable is " << (asked ? "set" : "not set") << ", expected the opposite\n";
    return 1;
  }
  if (argc != 3 || std::string_view(argv[1]) != "first" || std::string_view(argv[2]) != "second argument") {
    std::cout << "FAIL: the arguments did not survive the new start\n";
    return 1;
  }
  std::cout << "huge pages probe passed\n";
  return 0;
}
