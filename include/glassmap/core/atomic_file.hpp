#pragma once
/// Writing outputs so that a failure or an interruption never leaves a half-written file.

#include <filesystem>
#include <functional>

namespace glassmap {

/// Calls write(tmp) with a temporary path next to `target`, flushes tmp to disk (fsync), then
/// renames tmp over target. If write or the flush fails, the temporary is removed, target is left
/// as it was, and the error rethrown (an Error naming tmp is rethrown naming target).
/// The temporary keeps target's extension so that format-sniffing writers (GDAL) still work.
/// While it exists the temporary is registered as a LiveTemporary (see installSignalCleanup).
void writeAtomically(const std::filesystem::path& target,
                     const std::function<void(const std::filesystem::path& tmp)>& write);

/// Checks that `dir` can be written (it, or the deepest of its ancestors that exists, takes a new
/// file), so that a long run fails before it starts rather than at its end; creates nothing.
/// Throws Error naming dir with the system's reason.
void checkWritableDirectory(const std::filesystem::path& dir);

/// Flushes a written file to disk (fsync); throws Error with the system's reason on failure.
void syncToDisk(const std::filesystem::path& path);

/// Temporary sibling path for target: "<dir>/.<stem>.tmp<pid>-<n><ext>".
std::filesystem::path temporarySibling(const std::filesystem::path& target);

/// Registers a temporary file (or a folder of temporaries) for removal by the signal handler of
/// installSignalCleanup() for as long as this object lives; the owner still removes it normally.
/// At most 64 live registrations are tracked at once (more are not protected: the count is small
/// because a command writes few files at a time). A folder is emptied (one level) and removed.
class LiveTemporary {
 public:
  explicit LiveTemporary(const std::filesystem::path& path, bool is_directory = false);
  ~LiveTemporary();
  LiveTemporary(const LiveTemporary&) = delete;
  LiveTemporary& operator=(const LiveTemporary&) = delete;

 private:
  int slot_ = -1;
};

/// Installs SIGINT, SIGTERM and SIGHUP handlers (not over a signal the process ignores) that
/// remove every live temporary (files, SQLite's -journal/-wal/-shm sidecars, the ".tmp" entity
/// spool of GDAL's DXF writer, registered folders) with async-signal-safe calls, then re-raise the signal with its default action, so
/// the process still dies of it and an interrupted write leaves the old target or none. Call
/// once from main(); idempotent.
void installSignalCleanup();

/// Removes every live temporary now, as the signal handler does (async-signal-safe).
void removeLiveTemporaries() noexcept;

}  // namespace glassmap
