#pragma once
/// The pass over readings without an echo (NoReturnMode::Angular).
///
/// A no-return says the beam met nothing that sent an echo back: open space up to the sensor's
/// range, or a surface that lost this one echo (a dropout: dark, shiny or far surfaces do it a few
/// times in a hundred), or a pane the beam passed at a slant. Counting every such beam as a miss up
/// to the clearing range lets a laser that drops 3% of its echoes "see through" walls, which then
/// look hit from one side and missed from another: glass. Here a no-return crosses cells only up to
/// the first one that mostly returns beams of its direction: where beams of that direction (its
/// angle bin and the two beside it) end in the cell more often than no-returns cross it, the beam
/// was more likely lost there than passed. A wall that drops a few echoes stops them; a pane,
/// which returns only near its normal (and at other angles at most a sensor's small floor of
/// direct returns), is still crossed by the no-returns that meet it at a slant.
///
/// Order of the passes: integrateCounts (returned beams), the candidates' AngleHistograms,
/// noReturnStops, integrateNoReturns (its misses go into the counts, so the standard occupancy map
/// that the direct classifier reads d_real from sees through glass as before), then the per-angle
/// pass over the returned beams.

#include <cstdint>
#include <vector>

#include "glassmap/grid/angle_histograms.hpp"
#include "glassmap/grid/hit_miss_grid.hpp"
#include "glassmap/grid/scan_integration.hpp"

namespace glassmap::grid {

/// Per candidate cell, the angle bins in which it stops no-return beams (a bit set).
class NoReturnStops {
 public:
  explicit NoReturnStops(const AngleHistograms& histograms);
  /// True when candidate id stops no-returns of bin `bin`.
  bool stops(std::int32_t id, int bin) const {
    return (bits_[static_cast<std::size_t>(id) * words_ + static_cast<std::size_t>(bin >> 6)] >> (bin & 63)) & 1U;
  }
  void set(std::int32_t id, int bin) {
    bits_[static_cast<std::size_t>(id) * words_ + static_cast<std::size_t>(bin >> 6)] |= std::uint64_t{1} << (bin & 63);
  }
  std::size_t stopping() const;  ///< (candidate, bin) pairs that stop no-returns

 private:
  std::size_t words_;
  std::vector<std::uint64_t> bits_;
};

/// Where the no-returns of the log stop: per candidate and bin, whether the returned beams ending
/// there (end cells only, no walk) outnumber the no-returns crossing it (one walk of the
/// no-returns, counting), both over the bin and its two neighbours.
NoReturnStops noReturnStops(const LaserLog& log, const BeamOptions& options, const AngleHistograms& histograms);

/// Walks the no-return beams of the log: each adds a miss to every cell it crosses before the
/// first one that stops its bin, in `counts` and, for candidate cells, in `histograms` at its angle
/// bin (the per-angle pass adds the returned beams to them).
IntegrationStats integrateNoReturns(const LaserLog& log, const BeamOptions& options, const NoReturnStops& stops,
                                    HitMissGrid& counts, AngleHistograms& histograms, const Progress& progress = {});

/// The no-return pass as the mapping runs it: nothing unless options.deferNoReturns(); otherwise
/// noReturnStops, then integrateNoReturns with them. Call it between the candidates'
/// AngleHistograms and the per-angle pass.
IntegrationStats integrateNoReturns(const LaserLog& log, const BeamOptions& options, HitMissGrid& counts,
                                    AngleHistograms& histograms, const Progress& progress = {});

}  // namespace glassmap::grid
