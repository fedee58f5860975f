#include "glassmap/grid/no_returns.hpp"

#include "glassmap/grid/parallel_scans.hpp"
#include "glassmap/grid/traversal.hpp"

namespace glassmap::grid {

ReturnDirections::ReturnDirections(const AngleHistograms& h)
    : words_(static_cast<std::size_t>((h.bins() + 63) / 64)), bits_(h.size() * words_, 0) {}

void ReturnDirections::merge(const ReturnDirections& other) {
  for (std::size_t i = 0; i < bits_.size(); ++i) bits_[i] |= other.bits_[i];
}

ReturnDirections returnDirections(const LaserLog& log, const BeamOptions& options, const AngleHistograms& hist) {
  const GridGeometry& g = hist.geometry();
  const int bins = hist.bins();
  tbb::enumerable_thread_specific<ReturnDirections> parts([&] { return ReturnDirections(hist); });
  forScansInParallel(log.scans.size(), {}, parts, [&](std::size_t s, ReturnDirections& part) {
    forEachBeam(log.scans[s], options, [&](const Beam& beam) {
      if (!beam.hit) return;
      const CellIndex end = g.cellAt(beam.to);
      if (!g.contains(end)) return;
      const std::int32_t id = hist.find(end.x, end.y);
      if (id != AngleHistograms::kNone) part.set(id, angleBin(beam.angle, bins));
    });
  });
  ReturnDirections out(hist);
  for (const ReturnDirections& part : parts) out.merge(part);
  return out;
}

IntegrationStats integrateNoReturns(const LaserLog& log, const BeamOptions& options, const ReturnDirections& returns,
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
  forScansInParallel(log.scans.size(), progress, parts, [&](std::size_t s, Part& part) {
    forEachBeam(log.scans[s], options, [&](const Beam& beam) {
      if (!beam.no_return) return;
      const int bin = angleBin(beam.angle, bins);
      const int prev = (bin + bins - 1) % bins, next = (bin + 1) % bins;
      part.stats.cells_traversed += traverse(g, beam.from, beam.to, [&](int x, int y, double, bool) {
        const std::int32_t id = hist.find(x, y);
        if (id != AngleHistograms::kNone) {
          // Returns this way: the beam may have been lost here (a dropout), nothing beyond counts.
          if (returns.returned(id, prev) || returns.returned(id, bin) || returns.returned(id, next)) return false;
          hist.addMiss(part.hist, id, bin);
        }
        part.counts.addMiss(x, y);
        return true;
      });
      ++part.stats.beams;
    });
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

}  // namespace glassmap::grid
