#pragma once
/// The grid glass-mapping pipeline as one library call: log -> counts -> per-angle statistics ->
/// cell evidence. Later stages (MRF, vectorisation) refine the returned CellEvidence.

#include <functional>
#include <memory>
#include <string>

#include "glassmap/glass/classifiers.hpp"
#include "glassmap/glass/evidence.hpp"
#include "glassmap/grid/scan_integration.hpp"

namespace glassmap::glass {

/// Cell classifier. (The MRF refines Direct's evidence: pipeline/map_log.hpp runs the whole chain.)
enum class Method { Heuristic, Direct };

/// "heuristic" / "direct".
const char* toString(Method m);
/// Parses "heuristic" / "direct"; throws Error otherwise.
Method parseMethod(const std::string& name);

/// Bytes per grid cell that the map pipeline holds in dense layers at its peak (label array,
/// ROS map, label raster, PNG image, vectorisation grids). Measured: a 6102 x 6160-cell grid with
/// almost nothing observed peaks at 562 MB, 15 bytes per cell with the process baseline.
inline constexpr double kDenseBytesPerCell = 16.0;

/// Everything mapLog needs.
struct MappingOptions {
  double resolution = 0.05;    ///< cell size [m]
  double angle_bin_deg = 5.0;  ///< incidence-angle bin width [deg]; must divide 180
  double margin = 1.0;         ///< grid margin around what was seen [m]
  /// Refuse, before allocating, a grid whose dense per-cell layers (labels, rasters, images,
  /// vectorisation) would need more than this [bytes]; see kDenseBytesPerCell.
  std::size_t max_memory_bytes = std::size_t{4} << 30;
  Method method = Method::Direct;
  grid::BeamOptions beams;
  grid::OccupancyModel occupancy;
  HeuristicOptions heuristic;
  DirectOptions direct;
  bool operator==(const MappingOptions&) const = default;
};

/// What mapLog did: counts, sizes, times.
struct MappingStats {
  std::size_t scans = 0;                 ///< scans integrated
  std::size_t beams = 0;                 ///< beams traversed (per pass)
  std::size_t hit_beams = 0;             ///< beams that ended in a hit
  std::size_t cells_traversed = 0;       ///< cell visits of the occupancy pass
  std::size_t observed_cells = 0;        ///< cells some beam touched
  std::size_t candidate_cells = 0;       ///< cells with per-angle histograms (some beam ended there)
  std::size_t glass_cells = 0;           ///< cells labelled glass
  std::size_t occupied_cells = 0;        ///< cells labelled OCC
  std::size_t state_bytes = 0;           ///< counts + histograms + sigmoid sums [bytes]
  double bytes_per_observed_cell = 0.0;  ///< state_bytes / observed_cells
  double seconds_counts = 0.0;           ///< occupancy pass [s]
  double seconds_angles = 0.0;           ///< per-angle (and sigmoid) pass [s]
  double seconds_classify = 0.0;         ///< classification [s]
  EmptyHitRate empty;                    ///< hits of empty cells away from surfaces (emptyHitRate)
  double p_hit_emp = 0.0;                ///< the direct classifier's P(hit | EMP) (DirectOptions)
};

/// The outcome of mapping one log.
struct MappingResult {
  CellEvidence evidence;  ///< labels + costs (what mrf/ consumes)
  MappingStats stats;
};

/// The passes over a log's beams that mapLog makes before it classifies: the hit/miss counts, the
/// per-angle histograms and the direct classifier's sigmoid sums. A calibration round changes only
/// the classifier's lobe, so its pass over the same log reuses them (the same integers: the labels
/// come out as a fresh pass's would). Holds the grid's state between the passes.
class BeamPasses {
 public:
  BeamPasses();
  ~BeamPasses();
  BeamPasses(BeamPasses&&) noexcept;
  BeamPasses& operator=(BeamPasses&&) noexcept;
  /// How many mapLog calls took the passes from here instead of walking the beams.
  int reused() const { return reused_; }

 private:
  friend MappingResult mapLog(const LaserLog&, const MappingOptions&,
                              const std::function<void(const char*, double)>&, BeamPasses*);
  struct Data;
  std::unique_ptr<Data> data_;
  int reused_ = 0;
};

/// Maps a log: grid from the laser poses and beams, occupancy pass, per-angle pass, classifier.
/// progress(stage, fraction) reports "counts"/"angles" passes in [0, 1]. With `passes`, the
/// passes over the beams are taken from there when it holds those of this very log made with
/// options that differ at most in what only the classifier reads (the lobe, the priors, the pane
/// share's range noise), and left there otherwise.
MappingResult mapLog(const LaserLog& log, const MappingOptions& options,
                     const std::function<void(const char* stage, double fraction)>& progress = {},
                     BeamPasses* passes = nullptr);

}  // namespace glassmap::glass
