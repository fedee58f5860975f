#pragma once
// Transparent huge pages for the glassmap process. The mapping passes allocate and free grids of
// tens of megabytes, per thread and per stage, and a fresh page costs a fault on first touch: on
// Freiburg 079 about 68,000 faults of 4 KiB, a tenth of the run's time on a virtual machine, where
// a fault is dear. glibc's malloc asks the kernel for 2 MiB pages (madvise) when its tunable
// glibc.malloc.hugetlb=1 is set, which glibc reads only when a process starts: the command sets
// it and starts itself again, before it does anything else.

#include <optional>
#include <string>
#include <string_view>

namespace glassmap::cli {

/// The kernel's transparent huge page mode, the bracketed word of
/// /sys/kernel/mm/transparent_hugepage/enabled ("always [madvise] never" gives "madvise"), or ""
/// when the text has none.
std::string thpMode(std::string_view enabled_file);

/// This kernel's mode: thpMode of its /sys/kernel/mm/transparent_hugepage/enabled ("" without one).
std::string kernelThpMode();

/// The GLIBC_TUNABLES value that asks glibc's malloc for huge pages, given the current value
/// (nullptr: unset), the kernel's mode, GLASSMAP_HUGE_PAGES and LD_PRELOAD (nullptr: unset);
/// nothing when there is nothing to do: huge pages only on request ("madvise") is the one mode
/// where asking helps, a glibc.malloc.hugetlb already set is the user's choice,
/// GLASSMAP_HUGE_PAGES=0 opts out, and under valgrind (its preloaded vgpreload libraries) a new
/// start would run outside the tool, whose allocator reads no tunable anyway.
std::optional<std::string> hugePageTunables(const char* tunables, std::string_view thp_mode, const char* opt_out,
                                            const char* preload = nullptr);

/// Whether LD_PRELOAD (nullptr: unset) holds valgrind's preloaded vgpreload libraries: the process
/// runs under valgrind, which follows a new program only with --trace-children=yes.
bool underValgrind(const char* preload);

/// Whether the allocator is glibc's own malloc, which reads the tunable (a sanitizer brings its
/// own allocator).
bool mallocReadsTunables();

/// What requestHugePages did: whether it set GLIBC_TUNABLES, and the value it replaced (nullopt: unset).
struct TunablesChange {
  bool changed = false;
  std::optional<std::string> before;
};

/// Sets GLIBC_TUNABLES to hugePageTunables' value for this process's environment and kernel, when
/// there is one and glibc's malloc is the allocator (not under a sanitizer, whose allocator
/// ignores it).
TunablesChange requestHugePages();

/// Starts the program again (/proc/self/exe, the same arguments) with the tunable set, when
/// requestHugePages sets it. Returns only when it did not: nothing to do, or the exec failed (the
/// environment then is as it was). A program started by the glassmap launcher (launcher.cpp) has
/// the tunable already and goes on.
void useHugePages(char** argv);

/// The program `name` in the directory of the running program (/proc/self/exe; without /proc,
/// the directory of argv0 when it names one); `name` alone (looked up in PATH) when neither does.
std::string programBeside(const char* argv0, std::string_view name);

}  // namespace glassmap::cli
