// The glassmap command as users start it: a small program that asks glibc's malloc for huge pages
// (huge_pages.hpp) and becomes glassmap-engine, the command itself, beside it. The engine links
// GDAL and a hundred more libraries, whose loading and relocation cost about 80 ms of every start;
// setting the tunable here, before the engine starts, spares it the second start it would make
// for the tunable (which paid that cost twice). The same process (exec, not a child): its exit
// status, signals and resource use are the engine's.
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "huge_pages.hpp"

int main(int, char** argv) {
  const std::string engine = glassmap::cli::programBeside(argv[0], "glassmap-engine");
  if (glassmap::cli::underValgrind(std::getenv("LD_PRELOAD"))) {
    std::fprintf(stderr,
                 "glassmap: note: valgrind follows this launcher into %s only with --trace-children=yes; "
                 "or run that program under it directly\n",
                 engine.c_str());
  }
  glassmap::cli::requestHugePages();
  if (engine.find('/') != std::string::npos) {
    execv(engine.c_str(), argv);
  } else {
    execvp(engine.c_str(), argv);
  }
  std::fprintf(stderr, "glassmap: error: cannot start %s: %s\n", engine.c_str(), std::strerror(errno));
  return 127;
}
