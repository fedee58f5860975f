// glassmap: laser logs to glass-aware maps, vector floorplans and localization.
#include <iostream>
#include <new>

#include "cli_common.hpp"
#include "cli_config.hpp"
#include "glassmap/core/atomic_file.hpp"
#include "glassmap/core/error.hpp"

int main(int argc, char** argv) {
  // SIGINT/SIGTERM remove the temporaries of writes in progress, so an interrupted run leaves
  // either the old output or the new one, never a partial file.
  glassmap::installSignalCleanup();
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
