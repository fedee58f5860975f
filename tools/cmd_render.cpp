// glassmap render FLOORPLAN [--log LOG] -o out.png|out.svg
#include <filesystem>
#include <fstream>
#include <iostream>

#include "cli_common.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/io/floorplan.hpp"
#include "glassmap/io/log.hpp"
#include "glassmap/io/render_floorplan.hpp"

namespace glassmap {
namespace {

namespace fs = std::filesystem;

struct RenderArgs {
  std::string floorplan, log, outcomes, out, units, layers;
  double ppm = 40.0;
  int every = 10;
  LogReadOptions read;
};

// Colours of the simulator's beam outcomes (codes of sim::BeamOutcome).
constexpr std::uint32_t kOutcomeColour[] = {0x9a9a9a, 0x2ca02c, 0xff7f0e, 0x17becf, 0x9467bd,
                                            0xffffff, 0xffffff, 0xbcbd22, 0x8c564b};

void run(const RenderArgs& args) {
  const VectorMap map = cli::readPlan(args.floorplan, args.units, args.layers);
  FloorplanPicture pic;
  pic.pixels_per_metre = args.ppm;
  if (!args.log.empty()) {
    LogReadOptions read = args.read;
    read.ros2.pose_source = BagPoseSource::Auto;
    const LaserLog log = cli::readLogReporting(args.log, read);
    std::vector<std::uint8_t> outcomes;
    if (!args.outcomes.empty()) {
      std::ifstream in(args.outcomes, std::ios::binary);
      if (!in) throw Error("cannot open", args.outcomes);
      outcomes.assign(std::istreambuf_iterator<char>(in), {});
    }
    std::size_t offset = 0, expected = 0;
    for (const LaserScan& s : log.scans) expected += s.ranges.size();
    if (!outcomes.empty() && outcomes.size() != expected)
      throw Error(
          "has " + std::to_string(outcomes.size()) + " outcomes, the log " + std::to_string(expected) + " beams",
          args.outcomes);
    for (std::size_t k = 0; k < log.scans.size(); ++k) {
      const LaserScan& s = log.scans[k];
      pic.trajectory.push_back(s.laser_pose.t);
      if (args.every > 0 && k % static_cast<std::size_t>(args.every) == 0) {
        for (std::size_t i = 0; i < s.ranges.size(); ++i) {
          if (!s.isReturn(i)) continue;
          const double a = s.laser_pose.theta + s.beamAngle(i);
          const Vec2 p = s.laser_pose.t + s.ranges[i] * Vec2(std::cos(a), std::sin(a));
          const std::uint8_t code = outcomes.empty() ? 0 : outcomes[offset + i];
          pic.points.push_back({p, code < std::size(kOutcomeColour) ? kOutcomeColour[code] : 0xff0000});
        }
      }
      offset += s.ranges.size();
    }
  }
  renderFloorplan(args.out, map, pic);
  std::cout << "wrote " << args.out << "\n";
}

const cli::Registrar reg(35, [](CLI::App& app) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* sub =
      app.add_subcommand("render",
                         "Draw a floorplan to PNG or SVG: walls dark, glass blue; optionally a log's trajectory (red)\n"
                         "and scan endpoints, coloured by simulated outcome when --outcomes is given (grey wall,\n"
                         "green direct glass return, orange reflection phantom, cyan through glass, purple person,\n"
                         "olive spurious short reading, brown spurious random reading).");
  sub->add_option("floorplan", args->floorplan, "floorplan (any format glassmap reads)")
      ->required()
      ->check(CLI::ExistingFile);
  sub->add_option("-o,--output", args->out, "output picture, .png or .svg")->required();
  cli::addUnitsOption(*sub, args->units);
  cli::addLayersOption(*sub, args->layers);
  sub->add_option("--log", args->log, std::string(cli::kLogHelp) + ": draw its laser poses and scan endpoints")
      ->check(CLI::ExistingPath);
  cli::addLogOptions(*sub, args->read);
  sub->add_option("--outcomes", args->outcomes, "outcomes.bin written by 'glassmap simulate' for the same log")
      ->check(CLI::ExistingFile);
  sub->add_option("--every", args->every, "draw the endpoints of every N-th scan (0: none)")->capture_default_str();
  sub->add_option("--ppm", args->ppm, "pixels per metre")->capture_default_str();
  sub->callback([args] { run(*args); });
});

}  // namespace
}  // namespace glassmap
