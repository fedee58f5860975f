// Reliability (issue 9), the glassmap command end to end: map ends cleanly on hostile logs and
// refuses absurd grids; the same inputs and seed give byte-identical outputs with one thread and
// with several.
#include <sys/wait.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "reliability/reliability_util.hpp"

namespace glassmap {
namespace {

using namespace reliability;

#ifdef GLASSMAP_CLI

// `glassmap map` on a log full of hostile records: a clean run or a clear error, never a crash.
TEST(HostileCli, MapOnAHostileLogEndsCleanly) {
  TempDir dir;
  std::string text;
  for (int k = 0; k < 40; ++k) {
    std::vector<std::string> r(181, "3.0");
    r[3] = "nan";
    r[4] = "-1";
    r[5] = "1e30";
    r[6] = "inf";
    text += flaser(k % 7 == 0 ? std::vector<std::string>{} : r, k % 5 == 0 ? 1.0 : 1.0 + k);
  }
  const auto log = dir.write("hostile.clf", text);
  const RunResult res = runCli({"map", log.string(), "-o", (dir / "out").string(), "-q"});
  ASSERT_FALSE(WIFSIGNALED(res.status)) << "killed by signal " << WTERMSIG(res.status) << "\n" << res.output;
  if (!res.exited(0)) {
    EXPECT_NE(res.output.find("error"), std::string::npos) << res.output;
  }
}

// A pose a million kilometres away: the grid would need absurd memory; it must be refused up
// front (or mapped in memory that grows with what was observed), never exhaust the machine.
TEST(HostileCli, MapWithAPoseFarOutsideTheMapDoesNotExhaustMemory) {
  TempDir dir;
  const std::vector<std::string> r(181, "3.0");
  std::string text = flaser(r, 1.0) + flaser(r, 2.0);
  text += "FLASER 181";
  for (const auto& v : r) text += " " + v;
  text += " 1e9 1e9 0 1 2 0 3 host 3\n";
  const auto log = dir.write("far.clf", text);
  TempDir logdir;
  const pid_t pid = spawnCli({"map", log.string(), "-o", (dir / "out").string(), "-q"}, logdir / "o.txt");
  int status = 0;
  ::waitpid(pid, &status, 0);
  const std::string out = readBytes(logdir / "o.txt");
  ASSERT_FALSE(WIFSIGNALED(status)) << "killed by signal " << WTERMSIG(status) << "\n" << out;
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 1) << out;
  EXPECT_NE(out.find("grid"), std::string::npos) << out;
  EXPECT_NE(out.find("error"), std::string::npos) << out;
}

// A grid whose dense layers would need more memory than allowed is refused before anything is
// allocated, with the figure; --max-memory raises the limit. Scans 60 m apart make a grid of about
// 1300 x 1300 cells (~27 MB at 16 bytes per cell).
TEST(HostileCli, MapRefusesAGridOverTheMemoryLimitUnlessRaised) {
  TempDir dir;
  const std::vector<std::string> r(181, "3.0");
  std::string text;
  for (int k = 0; k < 4; ++k) {
    const double x = k < 2 ? 0.1 * k : 60.0 + 0.1 * k;
    text += "FLASER 181";
    for (const auto& v : r) text += " " + v;
    text += " " + std::to_string(x) + " " + std::to_string(x) + " 0 " + std::to_string(x) + " " + std::to_string(x) +
            " 0 " + std::to_string(k + 1) + " host " + std::to_string(k + 1) + "\n";
  }
  const auto log = dir.write("wide.clf", text);
  const RunResult refused = runCli({"map", log.string(), "-o", (dir / "small").string(), "-q", "--max-memory", "10"});
  ASSERT_TRUE(refused.exited(1)) << refused.output;
  EXPECT_NE(refused.output.find("would need about"), std::string::npos) << refused.output;
  EXPECT_NE(refused.output.find("over the limit of 10 MB"), std::string::npos) << refused.output;
  EXPECT_NE(refused.output.find("--max-memory"), std::string::npos) << refused.output;
  EXPECT_FALSE(fs::exists(dir / "small")) << "nothing may be written after a refusal";
  const RunResult raised = runCli({"map", log.string(), "-o", (dir / "big").string(), "-q", "--max-memory", "100"});
  ASSERT_TRUE(raised.exited(0)) << raised.output;
  EXPECT_TRUE(fs::exists(dir / "big" / "labels.tif"));
}

// ---------------------------------------------------------------------------------------------
// Determinism

void expectSameFiles(const fs::path& a, const fs::path& b, const std::vector<std::string>& names) {
  for (const auto& n : names) {
    ASSERT_TRUE(fs::exists(a / n)) << a / n;
    ASSERT_TRUE(fs::exists(b / n)) << b / n;
    EXPECT_TRUE(readBytes(a / n) == readBytes(b / n)) << n << " differs between " << a << " and " << b;
  }
}

TEST(Determinism, SimulateAndMapAreByteIdenticalAcrossRunsAndThreadCounts) {
  TempDir dir;
  const std::string scene = std::string(GLASSMAP_SOURCE_DIR) + "/maps/glass-corridor/scene.yaml";
  const int cpus = std::min(usableCpus(), 4);
  const std::vector<std::pair<std::string, int>> runs = {{"a1", 1}, {"b1", 1}, {"cN", cpus}};
  for (const auto& [name, n] : runs) {
    const RunResult sim = runCli({"simulate", scene, "-o", (dir / ("sim-" + name)).string(), "--seed", "42",
                                  "--duration", kSanitized ? "4" : "12", "-q"},
                                 n);
    ASSERT_TRUE(sim.exited(0)) << sim.output;
    const RunResult map =
        runCli({"map", (dir / ("sim-" + name) / "log.clf").string(), "-o", (dir / ("map-" + name)).string(), "-q"}, n);
    ASSERT_TRUE(map.exited(0)) << map.output;
  }
  const std::vector<std::string> sim_files = {"log.clf", "groundtruth.tum", "outcomes.bin"};
  const std::vector<std::string> map_files = {"labels.tif", "map.pgm", "map.yaml"};
  expectSameFiles(dir / "sim-a1", dir / "sim-b1", sim_files);
  expectSameFiles(dir / "sim-a1", dir / "sim-cN", sim_files);
  expectSameFiles(dir / "map-a1", dir / "map-b1", map_files);
  expectSameFiles(dir / "map-a1", dir / "map-cN", map_files);
  if (cpus < 2) GTEST_SKIP() << "one usable CPU: compared two single-thread runs only";
}

#endif  // GLASSMAP_CLI

}  // namespace
}  // namespace glassmap
