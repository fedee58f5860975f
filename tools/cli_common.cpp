#include "cli_common.hpp"

#include "glassmap/core/atomic_file.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/io/floorplan.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <iostream>
#include <sstream>
#include <vector>

namespace glassmap::cli {
namespace {

std::vector<std::pair<int, Register>>& registry() {
  static std::vector<std::pair<int, Register>> verbs;
  return verbs;
}

}  // namespace

Registrar::Registrar(int order, Register fn) { registry().emplace_back(order, std::move(fn)); }

void registerAll(CLI::App& app) {
  auto& verbs = registry();
  std::stable_sort(verbs.begin(), verbs.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (auto& [order, fn] : verbs) fn(app);
}

CLI::App& verb(CLI::App& app, const std::string& name, const std::string& description) {
  for (CLI::App* sub : app.get_subcommands({})) {
    if (sub->get_name() == name) return *sub;
  }
  CLI::App* sub = app.add_subcommand(name, description);
  sub->require_subcommand(1);
  return *sub;
}

VectorMap readPlan(const std::string& path, const std::string& units, bool quiet, std::string* warning_out) {
  FloorplanUnits assumed;
  FloorplanReadOptions read;
  read.units = &assumed;
  if (!units.empty()) read.unit_in_metres = parseLengthUnit(units, "units");
  VectorMap map = readFloorplan(path, read);
  const std::string warning = implausibleExtentWarning(map, assumed, path);
  if (!quiet && !warning.empty()) std::cerr << "glassmap: warning: " << warning << "\n";
  if (warning_out != nullptr) *warning_out = warning;
  return map;
}

void addUnitsOption(CLI::App& cmd, std::string& units) {
  cmd.add_option("--units", units,
                 "units of the floorplan's coordinates, overriding what the file declares (CRS units,\n"
                 "DXF $INSUNITS; GDAL's default DXF header says inches): m, cm, mm, in, ft, us-ft, ... or\n"
                 "metres per unit; default: the file's own, metres when it declares none");
}

void writeJsonFile(const std::filesystem::path& path, const nlohmann::json& j) {
  writeAtomically(path, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp);
    out << j.dump(2) << "\n";
    out.close();  // a failed write shows only once the buffer is flushed
    if (!out) throw Error("cannot write", path.string());
  });
}

Pose2 parsePose(const std::string& text, const std::string& field) {
  std::stringstream ss(text);
  double v[3];
  char c1 = 0, c2 = 0;
  if (!(ss >> v[0] >> c1 >> v[1] >> c2 >> v[2]) || c1 != ',' || c2 != ',' || !ss.eof())
    throw Error("expected x,y,theta (metres, metres, radians), got '" + text + "'", {}, 0, field);
  return {v[0], v[1], v[2]};
}

bool stderrIsTerminal() { return ::isatty(STDERR_FILENO) == 1; }

std::size_t peakMemoryBytes() {
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  return static_cast<std::size_t>(usage.ru_maxrss) * 1024;  // Linux reports KiB
}

}  // namespace glassmap::cli
