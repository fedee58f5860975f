// Reliability (issue 9), writes: an interrupted or failing write leaves the old file or none,
// never a partial one or a temporary.
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "glassmap/core/atomic_file.hpp"
#include "glassmap/io/floorplan.hpp"
#include "reliability/reliability_util.hpp"

namespace glassmap {
namespace {

using namespace reliability;

// ---------------------------------------------------------------------------------------------
// Nothing half-written

/// Runs `body` in a forked child and returns its wait status.
template <class F>
int inChild(F&& body) {
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    body();
    ::_exit(0);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return status;
}

TEST(Interrupted, SignalDuringAnAtomicWriteLeavesTheOldFileAndNoTemporary) {
  for (const int sig : {SIGTERM, SIGINT, SIGHUP}) {
    SCOPED_TRACE(sig);
    TempDir dir;
    const fs::path target = dir / "out.clf";
    std::ofstream(target) << "old contents\n";
    const int status = inChild([&] {
      installSignalCleanup();
      writeAtomically(target, [&](const fs::path& tmp) {
        std::ofstream out(tmp);
        out << "half of the new contents";
        out.flush();
        std::ofstream(dir / "tmp-name") << tmp.string();
        ::raise(sig);  // delivered now: the handler removes tmp, then the process dies of sig
        out << " and the rest\n";
      });
    });
    ASSERT_TRUE(WIFSIGNALED(status)) << "child exited normally: the signal was swallowed";
    EXPECT_EQ(WTERMSIG(status), sig);
    EXPECT_EQ(readBytes(target), "old contents\n");
    EXPECT_FALSE(fs::exists(readBytes(dir / "tmp-name")));
    EXPECT_TRUE(temporariesIn(dir.path()).empty());
  }
}

TEST(Interrupted, SignalRemovesARegisteredTemporaryFolderAndSqliteSidecars) {
  TempDir dir;
  const fs::path folder = dir / ".parts.tmp1-0.dir";
  const fs::path gpkg = dir / ".out.tmp1-1.gpkg";
  const fs::path dxf = dir / ".plan.tmp1-2.dxf";
  const int status = inChild([&] {
    installSignalCleanup();
    fs::create_directory(folder);
    const LiveTemporary live_folder(folder, true);
    const LiveTemporary live_gpkg(gpkg);
    for (const char* f : {"a.shp", "a.shx", "a.dbf", "a.prj"}) std::ofstream(folder / f) << "x";
    std::ofstream(gpkg) << "x";
    std::ofstream(gpkg.string() + "-journal") << "x";
    const LiveTemporary live_dxf(dxf);
    std::ofstream(dxf) << "x";
    std::ofstream(dxf.string() + ".tmp") << "x";  // GDAL's DXF writer spools entities there
    ::raise(SIGTERM);
  });
  ASSERT_TRUE(WIFSIGNALED(status));
  EXPECT_FALSE(fs::exists(folder));
  EXPECT_FALSE(fs::exists(gpkg));
  EXPECT_FALSE(fs::exists(gpkg.string() + "-journal"));
  EXPECT_FALSE(fs::exists(dxf));
  EXPECT_FALSE(fs::exists(dxf.string() + ".tmp"));
}

TEST(Interrupted, AnIgnoredSignalStaysIgnoredAndAFinishedWriteIsKept) {
  TempDir dir;
  const fs::path target = dir / "out.txt";
  const int status = inChild([&] {
    std::signal(SIGHUP, SIG_IGN);  // nohup: the handler must not take SIGHUP over
    installSignalCleanup();
    writeAtomically(target, [&](const fs::path& tmp) {
      std::ofstream(tmp) << "new\n";
      ::raise(SIGHUP);
    });
  });
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  EXPECT_EQ(readBytes(target), "new\n");
  EXPECT_TRUE(temporariesIn(dir.path()).empty());
}

#ifdef GLASSMAP_CLI

bool mainInstallsSignalCleanup() {
  const std::string main_cpp = readBytes(fs::path(GLASSMAP_SOURCE_DIR) / "tools" / "main.cpp");
  return main_cpp.find("installSignalCleanup") != std::string::npos;
}

// Kills `glassmap convert` of a large floorplan while it writes: the target is then absent (or
// complete), and no temporary is left behind. The kill is sent when the temporary appears.
TEST(InterruptedCli, ConvertKilledMidWriteLeavesNoPartialOutput) {
  if (!mainInstallsSignalCleanup()) GTEST_SKIP() << "tools/main.cpp does not call installSignalCleanup() yet";
  TempDir dir;
  std::vector<std::array<double, 4>> segs;
  for (int i = 0; i < 60000; ++i) segs.push_back({0.01 * i, 0.0, 0.01 * i, 1.0 + 0.001 * (i % 100)});
  const auto in = dir.write("big.geojson", geojsonLines(segs));
  int interrupted = 0, finished = 0;
  for (const int sig : {SIGTERM, SIGINT}) {
    for (const std::string ext : {".gpkg", ".dxf", ".shp", ".geojson"}) {
      SCOPED_TRACE(std::to_string(sig) + ext);
      const fs::path outdir = dir / ("out" + std::to_string(sig) + ext.substr(1));
      fs::create_directories(outdir);
      const fs::path target = outdir / ("floor" + ext);
      const pid_t pid = spawnCli({"convert", in.string(), target.string(), "-q"}, dir / "log.txt");
      // Wait for a temporary (file or folder) to appear, then signal.
      bool seen = false;
      int status = 0;
      for (;;) {
        if (::waitpid(pid, &status, WNOHANG) == pid) break;
        if (!temporariesIn(outdir).empty()) {
          seen = true;
          ::kill(pid, sig);
          ::waitpid(pid, &status, 0);
          break;
        }
        std::this_thread::sleep_for(std::chrono::microseconds(200));
      }
      if (seen && WIFSIGNALED(status)) {
        ++interrupted;
        EXPECT_EQ(WTERMSIG(status), sig);
      } else {
        ++finished;
        EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << readBytes(dir / "log.txt");
      }
      EXPECT_TRUE(temporariesIn(outdir).empty()) << temporariesIn(outdir).front();
      if (fs::exists(target)) {
        // A target present must be complete: it reads back with every segment.
        EXPECT_EQ(readFloorplan(target).segments.size(), segs.size());
      }
    }
  }
  std::printf("[ %d runs interrupted mid-write, %d finished before the signal ]\n", interrupted, finished);
  EXPECT_GT(interrupted, 0) << "no run was caught mid-write: the test did not test anything";
}

// A JSON report that cannot be written out (here: a file size cap standing in for a full disk)
// is an error, and neither a truncated report nor a temporary is left behind.
TEST(InterruptedCli, JsonReportThatCannotBeWrittenIsAnErrorAndLeavesNoFile) {
  TempDir dir;
  std::string tum;
  for (int k = 0; k < 5; ++k) tum += std::to_string(k) + " " + std::to_string(k) + " 0 0 0 0 0 1\n";
  const auto truth = dir.write("truth.tum", tum);
  const fs::path json = dir / "stats.json";
  const pid_t pid = spawnCli({"eval", "traj", "-q", "--truth", truth.string(), truth.string(), "--json", json.string()},
                             dir / "log.txt", 0, 200);  // the report is longer, the error message shorter
  int status = 0;
  ::waitpid(pid, &status, 0);
  const std::string out = readBytes(dir / "log.txt");
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 1) << out;
  EXPECT_NE(out.find("cannot write"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(json));
  EXPECT_TRUE(temporariesIn(dir.path()).empty());
  // Without the cap the same command writes the report.
  ASSERT_TRUE(
      runCli({"eval", "traj", "-q", "--truth", truth.string(), truth.string(), "--json", json.string()}).exited(0));
  EXPECT_NE(readBytes(json).find("\"rmse\": 0.0"), std::string::npos) << readBytes(json);
}

#endif  // GLASSMAP_CLI

}  // namespace
}  // namespace glassmap
