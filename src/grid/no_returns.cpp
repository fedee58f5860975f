#include "glassmap/grid/no_returns.hpp"

#include <bit>
#include <vector>

#include "glassmap/grid/parallel_scans.hpp"
#include "glassmap/grid/traversal.hpp"

namespace glassmap::grid {

NoReturnStops::NoReturnStops(const AngleHistograms& h)
    : words_(static_cast<std::size_t>((h.bins() + 63) / 64)), bits_(h.size() * words_, 0) {}

std::size_t NoReturnStops::stopping() const {
  std::size_t n = 0;
  for (const std::uint64_t w : bits_) n += static_cast<std::size_t>(std::popcount(w));
  return n;
}

NoReturnStops noReturnStops(const LaserLog& log, const BeamOptions& options, const AngleHistograms& hist) {
  const GridGeometry& g = hist.geometry();
  const int bins = hist.bins();
  // Per candidate and bin: returned beams ending there (the hits half of a histogram) and
  // no-returns crossing it (the misses half). Saturating counts, summed over threads.
  tbb::enumerable_thread_specific<std::vector<std::uint16_t>> parts([&] { return hist.emptyCounts(); });
  forScansInParallel(log, {}, parts, [&](const LaserScan& scan, std::size_t, std::vector<std::uint16_t>& part) {
    forEachBeam(scan, options, [&](const Beam& beam) {
      const int bin = angleBin(beam.angle, bins);
      if (beam.no_return) {
        AngleHistograms::Cursor candidates(hist);
        traverse(g, beam.from, beam.to, [&](int x, int y, double, bool) {
          const std::int32_t id = candidates.find(x, y);
          if (id != AngleHistograms::kNone) hist.addMiss(part, id, bin);
        });
      } else if (beam.hit) {
        const CellIndex end = g.cellAt(beam.to);
        if (!g.contains(end)) return;
        const std::int32_t id = hist.find(end.x, end.y);
        if (id != AngleHistograms::kNone) hist.addHit(part, id, bin);
      }
    });
  });
  std::vector<std::uint32_t> tally(hist.emptyCounts().size(), 0);
  for (const std::vector<std::uint16_t>& part : parts)
    for (std::size_t i = 0; i < tally.size(); ++i) tally[i] += part[i];
  NoReturnStops stops(hist);
  const auto n = static_cast<std::int32_t>(hist.size());
  std::vector<std::uint32_t> returned(static_cast<std::size_t>(bins)), crossing(static_cast<std::size_t>(bins));
  for (std::int32_t id = 0; id < n; ++id) {
    for (int b = 0; b < bins; ++b) {
      returned[static_cast<std::size_t>(b)] = tally[hist.countsIndex(id, b, false)];
      crossing[static_cast<std::size_t>(b)] = tally[hist.countsIndex(id, b, true)];
    }
    for (int b = 0; b < bins; ++b) {
      const auto p = static_cast<std::size_t>((b + bins - 1) % bins), q = static_cast<std::size_t>((b + 1) % bins);
      const auto c = static_cast<std::size_t>(b);
      const std::uint32_t r = returned[p] + returned[c] + returned[q];
      if (r > 0 && r >= crossing[p] + crossing[c] + crossing[q]) stops.set(id, b);
    }
  }
  return stops;
}

IntegrationStats integrateNoReturns(const LaserLog& log, const BeamOptions& options, const NoReturnStops& stops,
                                    HitMissGrid& counts, AngleHistograms& hist, const Progress& progress) {
  const GridGeometry& g = counts.geometry();
  const int bins = hist.bins();
  // A thread's misses: a grid and histogram counts of its own, merged afterwards (saturating
  // integer counts: the same result on any number of threads).
  struct Part {
    HitMissGrid counts;
    std::vector<std::uint16_t> hist;
    IntegrationStats stats;
  };
  tbb::enumerable_thread_specific<Part> parts([&] { return Part{HitMissGrid(g), hist.emptyCounts(), {}}; });
  forScansInParallel(log, progress, parts, [&](const LaserScan& scan, std::size_t, Part& part) {
    forEachBeam(
        scan, options,
        [&](const Beam& beam) {
          const int bin = angleBin(beam.angle, bins);
          AngleHistograms::Cursor candidates(hist);
          HitMissGrid::Cursor cells(part.counts);
          part.stats.cells_traversed += traverse(g, beam.from, beam.to, [&](int x, int y, double, bool) {
            const std::int32_t id = candidates.find(x, y);
            if (id != AngleHistograms::kNone) {
              if (stops.stops(id, bin)) return false;  // more likely lost here than passed
              hist.addMiss(part.hist, id, bin);
            }
            cells.addMiss(x, y);
            return true;
          });
          ++part.stats.beams;
        },
        BeamFilter::NoReturn);
    ++part.stats.scans;
  });
  IntegrationStats total;
  for (Part& part : parts) {
    counts.merge(part.counts);
    hist.merge(part.hist);
    total += part.stats;
  }
  return total;
}

IntegrationStats integrateNoReturns(const LaserLog& log, const BeamOptions& options, HitMissGrid& counts,
                                    AngleHistograms& hist, const Progress& progress) {
  if (!options.deferNoReturns()) return {};
  return integrateNoReturns(log, options, noReturnStops(log, options, hist), counts, hist, progress);
}

}  // namespace glassmap::grid
