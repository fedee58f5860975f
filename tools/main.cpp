// glassmap: laser logs to glass-aware maps, vector floorplans and localization.
#include <iostream>
#include <new>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "cli_common.hpp"
#include "cli_config.hpp"
#include "glassmap/core/atomic_file.hpp"
#include "glassmap/core/error.hpp"
#include "huge_pages.hpp"

int main(int argc, char** argv) {
  // First of all: glibc's malloc on 2 MiB pages where the kernel gives them on request (the
  // program starts again with the tunable set; GLASSMAP_HUGE_PAGES=0 opts out). Freiburg 079 and
  // the 100 m floor map in 12-14% less time, at the same peak memory (docs/speed.md).
  glassmap::cli::useHugePages(argv);
  // SIGINT/SIGTERM remove the temporaries of writes in progress, so an interrupted run leaves
  // either the old output or the new one, never a partial file.
  glassmap::installSignalCleanup();
#if defined(__GLIBC__)
  // Buffers of 4 MiB and more (grids, per-thread counts, a log's records) are mapped on their own
  // and go back to the system when freed. glibc raises this threshold to the largest block freed
  // so far (up to 32 MiB), after which such buffers stay in the heap when freed and every later
  // stage adds to the peak: mapping the 100 m floor peaked at 305-336 MB, with this 275 MB, in the
  // same time (tools/bench/speed_table.py --only floor100).
  mallopt(M_MMAP_THRESHOLD, 4 << 20);
#endif
  CLI::App app{
      "glassmap: glass-aware laser mapping, vector floorplans and localization.\n"
      "Run 'glassmap <verb> --help' for the options of a verb."};
  app.require_subcommand(1);
  app.set_version_flag("--version", "glassmap 0.1.0");
  glassmap::cli::registerAll(app);
  glassmap::cli::addConfigOptions(app);  // -c FILE.yaml and --write-config on every verb
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const glassmap::Error& e) {
    std::cerr << "glassmap: error: " << e.what() << "\n";
    return 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "glassmap: error: out of memory (peak so far " << glassmap::cli::peakMemoryBytes() / 1000000
              << " MB): the input asks for more than this machine can give; see the verb's --max-memory or\n"
                 "check the input for coordinates far from the rest\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "glassmap: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
