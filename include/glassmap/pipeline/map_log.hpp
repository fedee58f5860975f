#pragma once
/// The whole mapping pipeline as one call (DESIGN.md, "The pipeline"):
///
///   log -> grid counts and per-angle statistics -> cell classifier (paper 2.5.3 / 2.5.4)
///       -> MRF (2.5.5) -> mirror-phantom test -> vectorization -> pane fit of the cells
///
/// The command line (`glassmap map`), the tests and the bench call this; each step's own module
/// holds its options and its code.

#include <cstddef>
#include <functional>
#include <string>

#include "glassmap/core/laser_scan.hpp"
#include "glassmap/glass/mapping.hpp"
#include "glassmap/glass/phantoms.hpp"
#include "glassmap/mrf/refine.hpp"
#include "glassmap/vector/vectorize.hpp"

namespace glassmap::pipeline {

/// How cells are labelled: a classifier alone, or the direct classifier refined by the MRF.
enum class MapMethod { Heuristic, Direct, Mrf };

/// "heuristic" / "direct" / "mrf".
const char* toString(MapMethod method);
/// Parses "heuristic" / "direct" / "mrf"; throws Error naming the field "method" otherwise.
MapMethod parseMapMethod(const std::string& name);

/// Everything mapLog needs; each step's options are its own module's.
struct MapOptions {
  MapMethod method = MapMethod::Mrf;
  glass::MappingOptions mapping;  ///< grid, beams, classifiers (mapping.method is set from method)
  mrf::RefineOptions mrf;         ///< used when method == Mrf
  bool phantoms = true;           ///< run the mirror-phantom test
  glass::PhantomOptions phantom;
  bool fit_floorplan = true;         ///< vectorize the labels into a floorplan
  bool prune_unfitted_glass = true;  ///< glass cells no fitted pane explains take their best other
                                     ///< label (fits the floorplan even when fit_floorplan is off)
  double prune_tolerance = 0.10;     ///< ... farther than this from every glass segment [m]
  vector::VectorizeOptions vectorize;
};

/// Wall-clock time of each step [s].
struct MapTimes {
  double counts = 0.0, angles = 0.0, classify = 0.0;  ///< grid passes and classifier
  double mrf = 0.0, phantoms = 0.0, vectorize = 0.0;  ///< later steps (0 when skipped)
  double total = 0.0;                                 ///< the whole call
};

/// The outcome of mapping one log.
struct MapResult {
  glass::CellEvidence evidence;       ///< final labels (after every step) and costs
  glass::MappingStats stats;          ///< grid and classifier figures; glass/occupied counts are final
  mrf::RefineResult mrf;              ///< MRF figures (zero unless method == Mrf)
  glass::PhantomStats phantoms;       ///< mirror-phantom figures (zero when skipped)
  vector::VectorizeResult floorplan;  ///< the fitted floorplan (empty unless fitted)
  bool has_floorplan = false;         ///< the floorplan was fitted
  std::size_t pruned_glass = 0;       ///< glass cells the pane fit relabelled
  MapTimes seconds;
};

/// progress(stage, fraction): "counts" and "angles" report fractions in [0, 1]; "mrf",
/// "phantoms" and "vectorize" report 0 when they start and 1 when they end.
using Progress = std::function<void(const char* stage, double fraction)>;

/// Maps a log with the laser poses of its scans. Throws Error for bad options or a log with no
/// scans, and before allocating a grid larger than options.mapping.max_memory_bytes allows.
MapResult mapLog(const LaserLog& log, const MapOptions& options = {}, const Progress& progress = {});

}  // namespace glassmap::pipeline
