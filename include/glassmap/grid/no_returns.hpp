#pragma once
/// The pass over readings without an echo (NoReturnMode::Angular).
///
/// A no-return says the beam met nothing that sent an echo back: open space up to the sensor's
/// range, or a surface that lost this one echo (a dropout: dark, shiny or far surfaces do it a few
/// times in a hundred), or a pane the beam passed at a slant. Counting every such beam as a miss up
/// to the clearing range lets a laser that drops 3% of its echoes "see through" walls, which then
/// look hit from one side and missed from another: glass. Here a no-return crosses cells only up to
/// the first one that returned beams of its own direction (its angle bin or a neighbouring one):
/// there the beam may have been lost. A pane, which returns only near its normal, is still crossed
/// by the no-returns that meet it at a slant; a wall seen from that direction stops them.
///
/// Order of the passes: integrateCounts (returned beams), the candidates' AngleHistograms,
/// returnDirections, integrateNoReturns (its misses go into the counts, so the standard occupancy
/// map that the direct classifier reads d_real from sees through glass as before), then the
/// per-angle pass over the returned beams.

#include <cstdint>
#include <vector>

#include "glassmap/grid/angle_histograms.hpp"
#include "glassmap/grid/hit_miss_grid.hpp"
#include "glassmap/grid/scan_integration.hpp"

namespace glassmap::grid {

/// Per candidate cell, the angle bins some returned beam ended in it from (a bit set).
class ReturnDirections {
 public:
  explicit ReturnDirections(const AngleHistograms& histograms);
  /// True when candidate id returned a beam of bin `bin`.
  bool returned(std::int32_t id, int bin) const {
    return (bits_[static_cast<std::size_t>(id) * words_ + static_cast<std::size_t>(bin >> 6)] >> (bin & 63)) & 1U;
  }
  void set(std::int32_t id, int bin) {
    bits_[static_cast<std::size_t>(id) * words_ + static_cast<std::size_t>(bin >> 6)] |= std::uint64_t{1} << (bin & 63);
  }
  /// Bitwise or of another set of the same shape.
  void merge(const ReturnDirections& other);
  std::size_t bytes() const { return bits_.capacity() * sizeof(std::uint64_t); }

 private:
  std::size_t words_;
  std::vector<std::uint64_t> bits_;
};

/// The directions the returned beams of the log ended in each candidate from (end cells only, no
/// walk: a fraction of a full pass).
ReturnDirections returnDirections(const LaserLog& log, const BeamOptions& options, const AngleHistograms& histograms);

/// Walks the no-return beams of the log: each adds a miss to every cell it crosses before the
/// first one that returned beams of its bin or a neighbouring one, in `counts` and, for candidate
/// cells, in `histograms` at its angle bin (the per-angle pass adds the returned beams to them).
IntegrationStats integrateNoReturns(const LaserLog& log, const BeamOptions& options, const ReturnDirections& returns,
                                    HitMissGrid& counts, AngleHistograms& histograms, const Progress& progress = {});

}  // namespace glassmap::grid
