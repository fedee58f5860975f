#include "glassmap/core/atomic_file.hpp"

#include <fcntl.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <string>
#include <system_error>

#include "glassmap/core/error.hpp"

namespace glassmap {

namespace fs = std::filesystem;

namespace {

// The registry the signal handler reads: fixed storage, no allocation, lock-free slot states.
// state: 0 free, 1 being filled or emptied by its owner, 2 live (the handler may read it).
constexpr int kSlots = 64;
constexpr std::size_t kPathMax = 4096;
struct Slot {
  std::atomic<int> state{0};
  bool is_directory = false;
  char path[kPathMax] = {};
};
std::array<Slot, kSlots> g_slots;

// Writes "<path><suffix>" into buf (capacity kPathMax) without the C library's formatting.
bool joinPath(char* buf, const char* path, const char* suffix) {
  const std::size_t a = std::strlen(path), b = std::strlen(suffix);
  if (a + b + 1 > kPathMax) return false;
  std::memcpy(buf, path, a);
  std::memcpy(buf + a, suffix, b + 1);
  return true;
}

// Empties a folder one level deep (getdents64 + unlinkat: raw system calls, signal-safe) and
// removes it.
void removeFolder(const char* path) noexcept {
  const int fd = ::open(path, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd >= 0) {
    alignas(8) char buf[4096];
    for (;;) {
      const long n = ::syscall(SYS_getdents64, fd, buf, sizeof buf);
      if (n <= 0) break;
      for (long off = 0; off < n;) {
        // struct linux_dirent64 { u64 d_ino; s64 d_off; u16 d_reclen; u8 d_type; char d_name[]; }
        unsigned short reclen = 0;
        std::memcpy(&reclen, buf + off + 16, sizeof reclen);
        const char* name = buf + off + 19;
        if (std::strcmp(name, ".") != 0 && std::strcmp(name, "..") != 0) ::unlinkat(fd, name, 0);
        off += reclen;
      }
    }
    ::close(fd);
  }
  ::rmdir(path);
}

void removeSlot(const Slot& s) noexcept {
  if (s.is_directory) {
    removeFolder(s.path);
    return;
  }
  ::unlink(s.path);
  char side[kPathMax];
  // Sidecars the writers make beside a file: SQLite's (GeoPackage) and the entity spool GDAL's
  // DXF writer keeps as "<file>.tmp" until it closes.
  for (const char* suffix : {"-journal", "-wal", "-shm", ".tmp"}) {
    if (joinPath(side, s.path, suffix)) ::unlink(side);
  }
}

void onTerminatingSignal(int sig) {
  const int saved_errno = errno;
  removeLiveTemporaries();
  errno = saved_errno;
  // SA_RESETHAND restored the default action; the signal is blocked while this handler runs,
  // so the re-raised one is delivered (and ends the process) as the handler returns.
  ::raise(sig);
}

}  // namespace

LiveTemporary::LiveTemporary(const fs::path& path, bool is_directory) {
  const std::string& p = path.native();
  if (p.size() + 1 > kPathMax) return;
  for (int i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (g_slots[i].state.compare_exchange_strong(expected, 1, std::memory_order_acquire)) {
      std::memcpy(g_slots[i].path, p.c_str(), p.size() + 1);
      g_slots[i].is_directory = is_directory;
      g_slots[i].state.store(2, std::memory_order_release);
      slot_ = i;
      return;
    }
  }
}

LiveTemporary::~LiveTemporary() {
  if (slot_ >= 0) g_slots[slot_].state.store(0, std::memory_order_release);
}

void removeLiveTemporaries() noexcept {
  for (const Slot& s : g_slots) {
    if (s.state.load(std::memory_order_acquire) == 2) removeSlot(s);
  }
}

void installSignalCleanup() {
  static std::atomic<bool> installed{false};
  if (installed.exchange(true)) return;
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction old {};
    if (::sigaction(sig, nullptr, &old) != 0 || old.sa_handler == SIG_IGN) continue;
    struct sigaction sa {};
    sa.sa_handler = onTerminatingSignal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESETHAND;
    ::sigaction(sig, &sa, nullptr);
  }
}

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

void checkWritableDirectory(const fs::path& dir) {
  // The deepest folder that exists must take a new file; nothing is created for good (a run
  // refused later leaves no empty folder behind).
  std::error_code ec;
  fs::path existing = fs::absolute(dir, ec);
  if (ec) throw Error("cannot resolve the output folder: " + ec.message(), dir.string());
  while (!fs::exists(existing, ec) && existing.has_parent_path() && existing != existing.parent_path())
    existing = existing.parent_path();
  if (!fs::is_directory(existing, ec))
    throw Error("cannot create the output folder: " + existing.string() + " is not a folder", dir.string());
  const fs::path probe = temporarySibling(existing / "write-test");
  const LiveTemporary live(probe);
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0) {
    const int err = errno;
    throw Error(std::string(existing == fs::absolute(dir) ? "cannot write into the output folder: "
                                                          : "cannot create the output folder: ") +
                    std::strerror(err),
                dir.string());
  }
  ::close(fd);
  ::unlink(probe.c_str());
}

void syncToDisk(const fs::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw Error(std::string("cannot open to flush: ") + std::strerror(errno), path.string());
  const int rc = ::fsync(fd);
  const int err = errno;
  ::close(fd);
  // EINVAL: the file system (a pipe, some special files) cannot sync; nothing to flush there.
  if (rc != 0 && err != EINVAL) throw Error(std::string("cannot flush to disk: ") + std::strerror(err), path.string());
}

void writeAtomically(const fs::path& target, const std::function<void(const fs::path&)>& write) {
  const fs::path tmp = temporarySibling(target);
  const LiveTemporary live(tmp);
  try {
    try {
      write(tmp);
      if (fs::is_regular_file(tmp)) syncToDisk(tmp);  // the write errors a full disk delays surface here
    } catch (const Error& e) {
      // Name the user's file, not our hidden temporary.
      if (e.file() == tmp.string()) throw Error(e.message(), target.string(), e.line(), e.field());
      throw;
    }
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
