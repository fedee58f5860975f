// The process's huge-page request (tools/huge_pages.hpp): when the command asks glibc for huge
// pages, and the tunable it sets.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

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
  EXPECT_TRUE(underValgrind("/usr/libexec/valgrind/vgpreload_core-amd64-linux.so"));
  EXPECT_FALSE(underValgrind("/usr/lib/x86_64-linux-gnu/libjemalloc.so.2"));
  EXPECT_FALSE(underValgrind(nullptr));
}

// Runs a shell command; its output (stdout and stderr) and exit status.
struct Outcome {
  std::string output;
  int status = -1;
};
Outcome run(const std::string& command) {
  Outcome r;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return r;
  char buffer[4096];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) r.output.append(buffer, n);
  const int raw = pclose(pipe);
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return r;
}

// A folder of its own for a copy of the launcher, removed at the end.
struct LauncherCopy {
  std::filesystem::path dir, launcher;
  explicit LauncherCopy(const std::string& name) {
    dir = std::filesystem::temp_directory_path() / ("glassmap_" + name + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    launcher = dir / "glassmap";
    std::filesystem::copy_file(GLASSMAP_LAUNCHER, launcher);
  }
  ~LauncherCopy() { std::filesystem::remove_all(dir); }
};

TEST(Launcher, RunsTheEngineBesideIt) {
  const std::string launcher = GLASSMAP_LAUNCHER;
  const std::string engine = (std::filesystem::path(launcher).parent_path() / "glassmap-engine").string();
  EXPECT_EQ(programBeside(nullptr, "glassmap-engine"),
            (std::filesystem::read_symlink("/proc/self/exe").parent_path() / "glassmap-engine").string());
  const Outcome version = run("'" + launcher + "' --version");
  EXPECT_EQ(version.status, 0);
  EXPECT_EQ(version.output, "glassmap 0.1.0\n");
  // A usage error: the engine's message and exit status, as if it had been started directly.
  const Outcome bad = run("'" + launcher + "' map --no-such-option");
  const Outcome direct = run("'" + engine + "' map --no-such-option");
  EXPECT_NE(bad.status, 0);
  EXPECT_EQ(bad.status, direct.status);
  EXPECT_EQ(bad.output, direct.output);
}

TEST(Launcher, GivesTheEngineItsArgumentsAndTheTunable) {
  // A stand-in engine that prints what it was given.
  LauncherCopy copy("launcher_args");
  {
    std::ofstream script(copy.dir / "glassmap-engine");
    script << "#!/bin/sh\nprintf '%s|' \"$@\" \"${GLIBC_TUNABLES-unset}\"\n";
  }
  std::filesystem::permissions(copy.dir / "glassmap-engine", std::filesystem::perms::owner_all);
  const char* before = std::getenv("GLIBC_TUNABLES");
  std::string expected = before ? before : "unset";
  if (mallocReadsTunables()) {
    if (const auto t =
            hugePageTunables(before, kernelThpMode(), std::getenv("GLASSMAP_HUGE_PAGES"), std::getenv("LD_PRELOAD")))
      expected = *t;
  }
  const Outcome r = run("'" + copy.launcher.string() + "' first 'second argument'");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(r.output, "first|second argument|" + expected + "|");
  // The engine's exit status comes through.
  {
    std::ofstream script(copy.dir / "glassmap-engine");
    script << "#!/bin/sh\nexit 3\n";
  }
  EXPECT_EQ(run("'" + copy.launcher.string() + "'").status, 3);
}

TEST(Launcher, SaysWhenTheEngineIsMissing) {
  LauncherCopy copy("launcher_alone");
  const Outcome r = run("'" + copy.launcher.string() + "' --version");
  EXPECT_EQ(r.status, 127);
  EXPECT_NE(r.output.find("cannot start " + (copy.dir / "glassmap-engine").string()), std::string::npos) << r.output;
}

}  // namespace
}  // namespace glassmap::cli
