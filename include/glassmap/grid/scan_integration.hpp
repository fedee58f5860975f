#pragma once
/// Laser scans into grids: beams as segments, the occupancy pass and the per-angle pass.

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "glassmap/core/laser_scan.hpp"
#include "glassmap/grid/angle_histograms.hpp"
#include "glassmap/grid/hit_miss_grid.hpp"

namespace glassmap::grid {

/// What a reading without an echo (a no-return or max-range reading) says about the cells it
/// crossed.
enum class NoReturnMode {
  /// The beam crossed every cell up to the clearing range: open space (the classic reading; a
  /// scanner that drops a few echoes on walls then "sees through" them).
  Open,
  /// The beam crossed cells up to the first one that returned beams of its direction (within a bin
  /// either side): there it may have been lost as a dropout, so nothing beyond counts. Glass, which
  /// returns only near its normal, is still crossed by oblique no-returns; a wall with dropouts is
  /// not (grid/no_returns.hpp).
  Angular,
};

/// "open" / "angular".
const char* toString(NoReturnMode mode);
/// Parses "open" / "angular"; throws Error naming the field "no_returns" otherwise.
NoReturnMode parseNoReturnMode(const std::string& name);

/// How readings become beams.
struct BeamOptions {
  double range_cap = 30.0;                         ///< beams are used up to this range [m]; longer returns and
                                                   ///< max-range readings clear free space up to here, with no hit
  double min_range = 0.05;                         ///< readings below this are dropped (sensor dead zone) [m]
  bool clear_no_return = true;                     ///< no-return and max-range readings clear free space (to the cap)
  double no_return_range = 0.0;                    ///< ...but only up to this range [m]; 0: range_cap (real SICK logs
                                                   ///< report glass, black and far surfaces as max range: use ~8 m)
  double miss_margin = 0.1;                        ///< a returned beam adds no miss to cells it enters within this
                                                   ///< distance before its reading [m]: grazing beams along a thin wall
                                                   ///< would otherwise clear the wall's own cells
  NoReturnMode no_return = NoReturnMode::Angular;  ///< see NoReturnMode
  /// True when the passes over returned beams skip no-return beams (a later pass walks them).
  bool deferNoReturns() const { return clear_no_return && no_return == NoReturnMode::Angular; }
  bool operator==(const BeamOptions&) const = default;
};

/// One beam as a segment in the map frame.
struct Beam {
  Vec2 from;               ///< laser position [m]
  Vec2 to;                 ///< end of the traversed segment [m]
  double angle = 0.0;      ///< beam direction in the map frame [rad]
  double range = 0.0;      ///< length of the segment [m]
  bool hit = false;        ///< true: the beam returned at `to` (the last cell is a hit)
  bool no_return = false;  ///< true: a no-return or max-range reading (no echo at all)
};

/// Whether a cell a beam enters counts a miss (see miss_margin): every cell of a beam without a
/// hit, and the cells of a hit entered more than miss_margin before its reading. Made once per
/// beam (the walks call it per cell).
class MissTest {
 public:
  MissTest(const Beam& beam, double miss_margin)
      : all_(!beam.hit), range_(beam.range), before_(beam.range - miss_margin) {}
  /// t: where the cell is entered, as a fraction of the beam (traverse's t) [-].
  bool operator()(double t) const { return all_ || t * range_ < before_; }

 private:
  bool all_;
  double range_, before_;
};

/// Which usable beams forEachBeam hands to its callback; the others cost no trigonometry.
enum class BeamFilter {
  All,       ///< every usable beam
  Returned,  ///< beams with an echo (hits and returns beyond the range cap)
  NoReturn,  ///< no-return and max-range readings
  Hit,       ///< beams that returned within the range cap
};

/// The directions of a scan's beams in the laser frame, cos and sin of start_angle + i * angular_step:
/// every scan of a log has the same few layouts, so a pass over the beams needs one sincos per scan
/// (the laser's heading) instead of one per beam.
struct BeamDirections {
  double start_angle = 0.0, angular_step = 0.0;
  std::vector<double> cos, sin;
};

/// The directions of scan's layout, made on first use and kept per thread (a few layouts).
std::shared_ptr<const BeamDirections> beamDirections(const LaserScan& scan);

/// Calls fn(const Beam&) for every usable beam of scan (see BeamOptions) that `filter` lets through.
/// A beam's direction is the laser's heading turned by its layout's direction (beamDirections):
/// within a few units in the last place of cos and sin of beam.angle.
template <class Fn>
void forEachBeam(const LaserScan& scan, const BeamOptions& options, Fn&& fn, BeamFilter filter = BeamFilter::All) {
  const double cap = options.range_cap;
  const std::shared_ptr<const BeamDirections> dirs = beamDirections(scan);
  const double ct = std::cos(scan.laser_pose.theta), st = std::sin(scan.laser_pose.theta);
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    const float r = scan.ranges[i];
    Beam beam;
    if (scan.isReturn(i)) {
      if (r < options.min_range || filter == BeamFilter::NoReturn) continue;
      beam.hit = r <= cap;
      if (!beam.hit && filter == BeamFilter::Hit) continue;
      beam.range = beam.hit ? static_cast<double>(r) : cap;  // beyond the cap: clear up to it
    } else {
      if (!options.clear_no_return || filter == BeamFilter::Returned || filter == BeamFilter::Hit) continue;
      beam.no_return = true;
      const double clear = options.no_return_range > 0 ? std::min(cap, options.no_return_range) : cap;
      beam.range = scan.max_range > 0 ? std::min(clear, scan.max_range) : clear;
    }
    beam.angle = scan.laser_pose.theta + scan.beamAngle(i);
    beam.from = scan.laser_pose.t;
    const double c = dirs->cos[i], s = dirs->sin[i];
    beam.to = beam.from + beam.range * Vec2(ct * c - st * s, st * c + ct * s);
    fn(beam);
  }
}

/// The beams the passes over returned beams walk: with options.deferNoReturns() the no-return
/// beams are left to integrateNoReturns.
inline BeamFilter passBeams(const BeamOptions& options) {
  return options.deferNoReturns() ? BeamFilter::Returned : BeamFilter::All;
}

/// A grid covering every laser position and beam segment of the log, plus margin [m].
GridGeometry geometryForLog(const LaserLog& log, double resolution, const BeamOptions& options, double margin = 1.0);

/// What a pass over a log did.
struct IntegrationStats {
  std::size_t scans = 0;            ///< scans integrated
  std::size_t beams = 0;            ///< beams traversed
  std::size_t hit_beams = 0;        ///< beams ending in a hit
  std::size_t cells_traversed = 0;  ///< cell visits (hits + misses)
};

/// Progress callback: fraction done in [0, 1].
using Progress = std::function<void(double)>;

/// Pass 1: every beam adds a miss to each cell it crosses and, if it returned, a hit to its last cell.
/// With options.deferNoReturns() the no-return beams are left to integrateNoReturns (no_returns.hpp);
/// so are they in the per-angle passes and in geometryForLog.
IntegrationStats integrateCounts(const LaserLog& log, const BeamOptions& options, HitMissGrid& grid,
                                 const Progress& progress = {});

/// Pass 2: the same beams into the per-angle histograms of the candidate cells.
IntegrationStats integrateAngles(const LaserLog& log, const BeamOptions& options, AngleHistograms& histograms,
                                 const Progress& progress = {});

}  // namespace glassmap::grid
