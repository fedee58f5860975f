#pragma once
// Helpers of the reliability tests (issue 9): temporary folders, error expectations, hostile
// inputs, and running the glassmap command as a subprocess.

#include <fcntl.h>
#include <sched.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "glassmap/core/error.hpp"

namespace glassmap::reliability {

namespace fs = std::filesystem;

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif
#else
inline constexpr bool kSanitized = false;
#endif

/// A fresh folder under the temp dir, removed at scope exit.
class TempDir {
 public:
  TempDir() {
    static std::atomic<int> counter{0};
    path_ = fs::temp_directory_path() /
            ("glassmap-reliability-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  fs::path operator/(const std::string& name) const { return path_ / name; }
  const fs::path& path() const { return path_; }
  fs::path write(const std::string& name, const std::string& text) const {
    const fs::path p = path_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }

 private:
  fs::path path_;
};

inline std::string readBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Names in `dir` that look like writeAtomically's temporaries (".<stem>.tmp<pid>-<n><ext>").
inline std::vector<std::string> temporariesIn(const fs::path& dir) {
  std::vector<std::string> found;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.starts_with(".") && name.find(".tmp") != std::string::npos) found.push_back(name);
  }
  return found;
}

/// Expects `f` to throw an Error whose text holds `part`.
template <class F>
void expectErrorWith(F&& f, const std::string& part) {
  try {
    f();
    ADD_FAILURE() << "no Error; expected one mentioning '" << part << "'";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

/// Expects `f` to throw an Error naming `field` (and `line`, when not 0).
template <class F>
void expectErrorAt(F&& f, const std::string& field, std::size_t line = 0) {
  try {
    f();
    ADD_FAILURE() << "no Error; expected one naming field '" << field << "'";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), field) << e.what();
    if (line != 0) {
      EXPECT_EQ(e.line(), line) << e.what();
    }
  }
}

/// A FLASER line with the given range tokens (count as declared), pose (1, 2, 0), time t.
inline std::string flaser(const std::vector<std::string>& ranges, double t, long declared = -1) {
  std::string line = "FLASER " + std::to_string(declared < 0 ? static_cast<long>(ranges.size()) : declared);
  for (const auto& r : ranges) line += " " + r;
  char tail[128];
  std::snprintf(tail, sizeof tail, " 1 2 0 1 2 0 %.6f host %.6f\n", t, t);
  return line + tail;
}

/// A GeoJSON FeatureCollection with one LineString per segment (x0, y0, x1, y1), alternately wall
/// and glass.
inline std::string geojsonLines(const std::vector<std::array<double, 4>>& segs) {
  std::string s = R"({"type":"FeatureCollection","features":[)";
  char buf[256];
  for (std::size_t i = 0; i < segs.size(); ++i) {
    std::snprintf(
        buf, sizeof buf,
        R"(%s{"type":"Feature","properties":{"material":"%s"},"geometry":{"type":"LineString","coordinates":[[%.17g,%.17g],[%.17g,%.17g]]}})",
        i ? "," : "", i % 2 ? "glass" : "wall", segs[i][0], segs[i][1], segs[i][2], segs[i][3]);
    s += buf;
  }
  return s + "]}";
}

#ifdef GLASSMAP_CLI

struct RunResult {
  int status = 0;
  std::string output;  ///< stdout and stderr
  bool exited(int code) const { return WIFEXITED(status) && WEXITSTATUS(status) == code; }
};

/// Starts the glassmap command with `args`, output to `log`; `cpus` > 0 pins it to that many of
/// this process's CPUs (TBB sizes its thread pool from the affinity mask); `max_file_bytes` caps
/// every file it writes (the log included), as a full disk would.
inline pid_t spawnCli(const std::vector<std::string>& args, const fs::path& log, int cpus = 0,
                      rlim_t max_file_bytes = RLIM_INFINITY) {
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    ::dup2(fd, 1);
    ::dup2(fd, 2);
    if (!kSanitized) {  // a runaway allocation fails in the child instead of swapping the machine
      const rlimit as{std::size_t{6} << 30, std::size_t{6} << 30};
      ::setrlimit(RLIMIT_AS, &as);
    }
    if (cpus > 0) {
      cpu_set_t have, want;
      CPU_ZERO(&want);
      sched_getaffinity(0, sizeof have, &have);
      for (int c = 0, taken = 0; c < CPU_SETSIZE && taken < cpus; ++c) {
        if (CPU_ISSET(c, &have)) {
          CPU_SET(c, &want);
          ++taken;
        }
      }
      sched_setaffinity(0, sizeof want, &want);
    }
    if (max_file_bytes != RLIM_INFINITY) {  // writes past the cap fail with EFBIG, no SIGXFSZ
      std::signal(SIGXFSZ, SIG_IGN);
      const rlimit fsize{max_file_bytes, max_file_bytes};
      ::setrlimit(RLIMIT_FSIZE, &fsize);
    }
    std::vector<char*> argv;
    std::string exe = GLASSMAP_CLI;
    argv.push_back(exe.data());
    std::vector<std::string> copy = args;
    for (auto& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(exe.c_str(), argv.data());
    ::_exit(127);
  }
  return pid;
}

inline RunResult runCli(const std::vector<std::string>& args, int cpus = 0) {
  TempDir logdir;
  const fs::path log = logdir / "out.txt";
  const pid_t pid = spawnCli(args, log, cpus);
  RunResult r;
  ::waitpid(pid, &r.status, 0);
  r.output = readBytes(log);
  return r;
}

inline int usableCpus() {
  cpu_set_t have;
  sched_getaffinity(0, sizeof have, &have);
  return CPU_COUNT(&have);
}

#endif  // GLASSMAP_CLI

}  // namespace glassmap::reliability
