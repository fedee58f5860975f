#include "glassmap/glass/phantoms.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "glass_tiles.hpp"
#include "glassmap/grid/parallel_scans.hpp"
#include "glassmap/grid/traversal.hpp"
#include "mirror_image.hpp"

namespace glassmap::glass {

namespace {

// Unit normal of the line through cell (cx, cy): minor axis of the cells within kR cells that
// `member` accepts. False when too few cells make a line (a speck, not a wall or a pane).
template <int kR, class Member>
bool lineNormal(const CellEvidence& e, int cx, int cy, Member&& member, Vec2& normal) {
  const grid::GridGeometry& g = e.geometry;
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
  for (int dy = -kR; dy <= kR; ++dy)
    for (int dx = -kR; dx <= kR; ++dx) {
      const int x = cx + dx, y = cy + dy;
      if (!g.contains(x, y) || !member(e.label[g.index(x, y)])) continue;
      n += 1;
      sx += dx;
      sy += dy;
      sxx += dx * dx;
      sxy += dx * dy;
      syy += dy * dy;
    }
  if (n < 4) return false;
  const double mx = sx / n, my = sy / n;
  const double cxx = sxx / n - mx * mx, cxy = sxy / n - mx * my, cyy = syy / n - my * my;
  const double angle = 0.5 * std::atan2(2.0 * cxy, cxx - cyy);  // direction of the major axis
  normal = Vec2(-std::sin(angle), std::cos(angle));
  return true;
}

bool wallNormal(const CellEvidence& e, int cx, int cy, Vec2& normal) {
  return lineNormal<3>(
      e, cx, cy, [](int l) { return l == kOccupied; }, normal);
}

// True when `reading` lies at least `margin` beyond the pane of glass label `pane_label` crossed
// at `at`, and its mirror image across that pane falls on an occupied or glass cell (within the
// uncertainty of the pane's 5-degree angle bin over the mirrored distance).
bool mirrorsASurface(const CellEvidence& e, int pane_label, const Vec2& at, const Vec2& reading, double margin) {
  const grid::GridGeometry& g = e.geometry;
  // The pane's line from the glass cells around the crossing (a label's angle bin is 5 deg wide,
  // and a wide lobe blurs it further); the bin's direction when too few cells make a line.
  const grid::CellIndex p = g.cellAt(at);
  Vec2 n;
  double tolerance = 0.5 * kPi / e.bins;
  if (lineNormal<5>(
          e, p.x, p.y, [](int l) { return isGlass(l); }, n)) {
    tolerance = deg2rad(1.5);
  } else {
    const double normal_angle = glassBin(pane_label) * kPi / e.bins;  // bin b is centred on b * 180 / bins
    n = Vec2(std::cos(normal_angle), std::sin(normal_angle));
  }
  const double beyond = n.dot(reading - at);
  return std::abs(beyond) >= margin && detail::mirrorFallsOnSurface(g, e.label, reading, n, beyond, tolerance);
}

}  // namespace

PhantomStats suppressMirrorPhantoms(const LaserLog& log, const grid::BeamOptions& beams, const PhantomOptions& options,
                                    CellEvidence& e) {
  PhantomStats stats;
  if (e.countGlass() == 0 || e.cells.empty()) return stats;
  const grid::GridGeometry& g = e.geometry;

  const detail::GlassTiles tiles(e);
  const detail::CandidateIndex candidates(e);

  // Per thread: returns and folded returns per candidate cell, beam counts. Integer sums, so the
  // result does not depend on how the scans were shared out.
  struct Tally {
    std::vector<std::uint32_t> returns, folded;
    std::size_t through_glass = 0, folded_beams = 0;
  };
  tbb::enumerable_thread_specific<Tally> tallies([&] {
    Tally t;
    t.returns.assign(e.cells.size(), 0);
    t.folded.assign(e.cells.size(), 0);
    return t;
  });
  grid::forScansInParallel(log, {}, tallies, [&](const LaserScan& scan, std::size_t, Tally& tally) {
    grid::forEachBeam(
        scan, beams,
        [&](const grid::Beam& beam) {
          const grid::CellIndex end = g.cellAt(beam.to);
          if (!g.contains(end)) return;
          const std::int64_t c = candidates.find(end.x, end.y);
          if (c < 0) return;
          ++tally.returns[static_cast<std::size_t>(c)];
          // From the first tile near glass on: before it the beam crosses no glass, and nothing counts.
          double from = 0.0;
          if (!tiles.near(beam.from, beam.to, &from)) return;
          const double glass_until = beam.range - options.glass_margin;
          const double block_until = beam.range - options.block_margin;
          bool is_folded = false, in_glass = false;
          // Where the beam entered each run of glass cells (the first few; none: it crossed no
          // glass): a reading beyond two panes may be the image the second folded, the beam having
          // passed the first.
          constexpr int kPanes = 4;
          int panes = 0;
          int pane_label[kPanes];
          Vec2 pane_at[kPanes];
          grid::traverse(
              g, beam.from, beam.to,
              [&](int x, int y, double t, bool) {
                const double d = t * beam.range;
                if (d >= glass_until) return false;
                const int l = e.label[g.index(x, y)];
                const bool glass = isGlass(l);
                if (glass && !in_glass && panes < kPanes) {
                  pane_label[panes] = l;
                  pane_at[panes++] = beam.from + d * (beam.to - beam.from) / beam.range;
                }
                in_glass = glass;
                if (panes > 0 && l == kOccupied && d < block_until) {
                  // Blocked only if the reading lies well beyond the wall's line, not just further
                  // along a wall the beam grazes (a pane's frame, a corner).
                  Vec2 n;
                  const Vec2 centre = g.origin + (Vec2(x, y) + Vec2(0.5, 0.5)) * g.resolution;
                  if (wallNormal(e, x, y, n) && std::abs(n.dot(beam.to - centre)) >= options.block_margin) {
                    is_folded = true;
                    return false;
                  }
                }
                return true;
              },
              from);
          // A reading in a glass cell beyond a pane whose mirror image (across that pane) is a
          // surface in front of it: the path the pane folded, which draws a phantom pane with the
          // very signature of glass (the mirrored pane's direct returns, from one angle).
          if (!is_folded && isGlass(e.label[g.index(end)])) {
            for (int i = 0; i < panes && !is_folded; ++i)
              is_folded = mirrorsASurface(e, pane_label[i], pane_at[i], beam.to, options.block_margin);
          }
          tally.through_glass += panes > 0;
          tally.folded_beams += is_folded;
          tally.folded[static_cast<std::size_t>(c)] += is_folded;
        },
        grid::BeamFilter::Hit);
  });

  std::vector<std::uint32_t> returns(e.cells.size(), 0), folded(e.cells.size(), 0);
  for (const Tally& t : tallies) {
    for (std::size_t i = 0; i < e.cells.size(); ++i) {
      returns[i] += t.returns[i];
      folded[i] += t.folded[i];
    }
    stats.beams_through_glass += t.through_glass;
    stats.folded_beams += t.folded_beams;
  }
  for (std::size_t i = 0; i < e.cells.size(); ++i) {
    if (folded[i] == 0) continue;
    std::uint8_t& l = e.label[e.cells[i]];
    if (l == kEmpty || l == kUnknown) continue;
    if (static_cast<double>(folded[i]) < options.min_folded_fraction * static_cast<double>(returns[i])) continue;
    l = kUnknown;
    ++stats.cells_cleared;
  }
  return stats;
}

}  // namespace glassmap::glass
