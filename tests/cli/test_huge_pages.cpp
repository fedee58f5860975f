// The process's huge-page request (tools/huge_pages.hpp): when the command asks glibc for huge
// pages, and the tunable it sets.
#include <gtest/gtest.h>

#include "huge_pages.hpp"

namespace glassmap::cli {
namespace {

TEST(HugePages, ModeIsTheBracketedWord) {
  EXPECT_EQ(thpMode("always [madvise] never\n"), "madvise");
  EXPECT_EQ(thpMode("[always] madvise never\n"), "always");
  EXPECT_EQ(thpMode("always madvise [never]"), "never");
  EXPECT_EQ(thpMode(""), "");          // no such file (no THP in the kernel)
  EXPECT_EQ(thpMode("always ["), "");  // torn text
}

TEST(HugePages, AsksOnlyWhereTheKernelGivesThemOnRequest) {
  EXPECT_EQ(hugePageTunables(nullptr, "madvise", nullptr), "glibc.malloc.hugetlb=1");
  // Every mapping gets them anyway, or none does: nothing to ask.
  EXPECT_FALSE(hugePageTunables(nullptr, "always", nullptr));
  EXPECT_FALSE(hugePageTunables(nullptr, "never", nullptr));
  EXPECT_FALSE(hugePageTunables(nullptr, "", nullptr));
}

TEST(HugePages, KeepsTheUsersTunablesAndChoice) {
  // Other tunables stay; the request is added.
  EXPECT_EQ(hugePageTunables("glibc.malloc.arena_max=2", "madvise", nullptr),
            "glibc.malloc.arena_max=2:glibc.malloc.hugetlb=1");
  EXPECT_EQ(hugePageTunables("", "madvise", nullptr), "glibc.malloc.hugetlb=1");
  // A hugetlb the user set (0 included) stands; and once set, a second start changes nothing.
  EXPECT_FALSE(hugePageTunables("glibc.malloc.hugetlb=0", "madvise", nullptr));
  EXPECT_FALSE(hugePageTunables("glibc.malloc.hugetlb=1", "madvise", nullptr));
  // GLASSMAP_HUGE_PAGES=0 opts out; any other value does not.
  EXPECT_FALSE(hugePageTunables(nullptr, "madvise", "0"));
  EXPECT_EQ(hugePageTunables(nullptr, "madvise", "1"), "glibc.malloc.hugetlb=1");
}

TEST(HugePages, NotUnderValgrind) {
  // A new start would leave the tool; another preloaded library changes nothing.
  EXPECT_FALSE(hugePageTunables(nullptr, "madvise", nullptr,
                                "/usr/libexec/valgrind/vgpreload_core-amd64-linux.so:"
                                "/usr/libexec/valgrind/vgpreload_memcheck-amd64-linux.so"));
  EXPECT_EQ(hugePageTunables(nullptr, "madvise", nullptr, "/usr/lib/x86_64-linux-gnu/libjemalloc.so.2"),
            "glibc.malloc.hugetlb=1");
}

}  // namespace
}  // namespace glassmap::cli
