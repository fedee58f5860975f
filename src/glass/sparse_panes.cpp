#include "glassmap/glass/sparse_panes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <Eigen/Geometry>

#include "binomial.hpp"
#include "glassmap/glass/scan_coherence.hpp"
#include "glassmap/grid/angle_histograms.hpp"
#include "glassmap/grid/parallel_scans.hpp"
#include "glassmap/grid/traversal.hpp"
#include "line_votes.hpp"
#include "mirror_image.hpp"
#include "weak_returns.hpp"

namespace glassmap::glass {
namespace {

using detail::log10BinomialCdf;
using detail::log10BinomialTail;
using sparse::angleDiff;
using sparse::kAngleBins;
using sparse::Line;
using sparse::seedLines;
using sparse::WeakReturn;
using sparse::WeakReturns;
using sparse::wrapPi;

// A run of weak returns along a line, from s0 to s1 along its tangent.
struct Run {
  Line line;
  double s0 = 0.0, s1 = 0.0;
  std::vector<std::size_t> returns;
  double log10_nfa = 0.0;                             // expected false alarms of a run like it, log10
  double transmission = 0.0;                          // share of the beams meeting it that passed
  sparse::ScanCoherence by_scan, by_visit, by_place;  // its near-normal beams within scans, within visits, at one place
  Vec2 end(double s) const { return line.rho * line.normal() + s * line.tangent(); }
};

// Unused returns compatible with `line` (angle within tol_a, offset within tol_r).
std::vector<std::size_t> gather(const WeakReturns& weak, const std::vector<bool>& used, const Line& line, double tol_a,
                                double tol_r) {
  std::vector<std::size_t> out;
  const std::vector<WeakReturn>& w = weak.returns();
  const int span = static_cast<int>(std::ceil(tol_a * kAngleBins / kPi)) + 1;
  const Vec2 n = line.normal();
  weak.forNearLine(line.angle, line.rho, span, tol_r, [&](std::size_t i) {
    if (used[i] || std::abs(angleDiff(w[i].normal, line.angle)) > tol_a) return;
    if (std::abs(n.dot(w[i].at) - line.rho) <= tol_r) out.push_back(i);
  });
  std::sort(out.begin(), out.end());
  return out;
}

// The line through returns `idx`: their principal axis when they spread along it (standard
// deviation over 0.3 m) and it lies within 2 tol_a of their mean beam direction, else that mean
// direction; the offset is the median.
Line fitLine(const std::vector<WeakReturn>& w, const std::vector<std::size_t>& idx, const Line& seed, double tol_a) {
  double c2 = 0, s2 = 0, mx = 0, my = 0;
  for (std::size_t i : idx) {
    c2 += std::cos(2.0 * angleDiff(w[i].normal, seed.angle));
    s2 += std::sin(2.0 * angleDiff(w[i].normal, seed.angle));
    mx += w[i].at.x();
    my += w[i].at.y();
  }
  const double n = static_cast<double>(idx.size());
  mx /= n;
  my /= n;
  double angle = seed.angle + 0.5 * std::atan2(s2, c2);
  double sxx = 0, sxy = 0, syy = 0;
  for (std::size_t i : idx) {
    const double dx = w[i].at.x() - mx, dy = w[i].at.y() - my;
    sxx += dx * dx;
    sxy += dx * dy;
    syy += dy * dy;
  }
  const double axis = 0.5 * std::atan2(2.0 * sxy, sxx - syy);  // direction of the major axis
  const double spread = 0.5 * (sxx + syy) + std::sqrt(0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy);
  const double pca_normal = wrapPi(axis + 0.5 * kPi);
  angle = wrapPi(angle);
  if (std::sqrt(spread / n) > 0.3 && std::abs(angleDiff(pca_normal, angle)) <= 2.0 * tol_a) angle = pca_normal;
  Line line;
  line.angle = angle;
  std::vector<double> rho;
  rho.reserve(idx.size());
  const Vec2 nn = line.normal();
  for (std::size_t i : idx) rho.push_back(nn.dot(w[i].at));
  std::nth_element(rho.begin(), rho.begin() + static_cast<std::ptrdiff_t>(rho.size() / 2), rho.end());
  line.rho = rho[rho.size() / 2];
  return line;
}

// Runs of returns `idx` along `line`, split at gaps over max_gap, or over gap_factor times the
// median spacing of the cells the returns fill along the line (a pane's ends are where its returns
// stop; a stray return a metre on would otherwise stretch it).
std::vector<Run> splitRuns(const std::vector<WeakReturn>& w, std::vector<std::size_t> idx, const Line& line,
                           double cell, double max_gap, double gap_factor) {
  const Vec2 t = line.tangent();
  std::sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return t.dot(w[a].at) < t.dot(w[b].at); });
  std::vector<double> filled;  // cells along the line that hold returns
  for (std::size_t i : idx) {
    const double q = std::floor(t.dot(w[i].at) / cell);
    if (filled.empty() || q != filled.back()) filled.push_back(q);
  }
  std::vector<double> gaps;
  for (std::size_t k = 1; k < filled.size(); ++k) gaps.push_back(filled[k] - filled[k - 1]);
  double split = max_gap;
  if (!gaps.empty()) {
    std::nth_element(gaps.begin(), gaps.begin() + static_cast<std::ptrdiff_t>(gaps.size() / 2), gaps.end());
    split = std::min(max_gap, cell * std::max(3.0, gap_factor * gaps[gaps.size() / 2]));
  }
  std::vector<Run> runs;
  for (std::size_t i : idx) {
    const double s = t.dot(w[i].at);
    if (runs.empty() || s - runs.back().s1 > split) {
      runs.emplace_back();
      runs.back().line = line;
      runs.back().s0 = s;
    }
    runs.back().s1 = s;
    runs.back().returns.push_back(i);
  }
  return runs;
}

// The runs by coarse tile (1 m): run r is listed in every tile that its segment, widened by `band`
// (and a tile more, for beams that only touch a tile's edge), reaches.
struct RunTiles {
  static constexpr double kTile = 1.0;  // [m]
  grid::GridGeometry grid;
  std::vector<std::uint32_t> start, runs;  // tile i lists runs[start[i] .. start[i + 1])
  RunTiles(const std::vector<Run>& all, double band) {
    Eigen::AlignedBox2d box;
    for (const Run& run : all) box.extend(run.end(run.s0)).extend(run.end(run.s1));
    if (box.isEmpty()) box.extend(Vec2::Zero());
    const double pad = band + kTile;
    grid.resolution = kTile;
    grid.origin = box.min() - Vec2(pad, pad);
    grid.width = static_cast<int>(std::ceil((box.max().x() - box.min().x() + 2 * pad) / kTile)) + 1;
    grid.height = static_cast<int>(std::ceil((box.max().y() - box.min().y() + 2 * pad) / kTile)) + 1;
    std::vector<std::vector<std::uint32_t>> lists(grid.cells());
    for (std::size_t r = 0; r < all.size(); ++r) {
      Eigen::AlignedBox2d b;
      b.extend(all[r].end(all[r].s0)).extend(all[r].end(all[r].s1));
      const grid::CellIndex lo = grid.cellAt(b.min() - Vec2(pad, pad)), hi = grid.cellAt(b.max() + Vec2(pad, pad));
      for (int y = std::max(lo.y, 0); y <= std::min(hi.y, grid.height - 1); ++y)
        for (int x = std::max(lo.x, 0); x <= std::min(hi.x, grid.width - 1); ++x)
          lists[grid.index(x, y)].push_back(static_cast<std::uint32_t>(r));
    }
    start.assign(grid.cells() + 1, 0);
    for (std::size_t i = 0; i < lists.size(); ++i)
      start[i + 1] = start[i] + static_cast<std::uint32_t>(lists[i].size());
    runs.reserve(start.back());
    for (const auto& l : lists) runs.insert(runs.end(), l.begin(), l.end());
  }
};

// Per run: beams that pass the run (returned beams that end at least `beyond` past it, beams
// without an echo within the cap that meet it before any occupied cell of `e`), and beams that
// return on it (within `band`) or just behind it; and those of them within tol_a of its normal
// that returned on it or passed it (no echo counts as passing), with their scans; those another
// run's line folded `margin` before it are marked (NearNormalBeam::folded).
template <class Beyond>
void countCrossings(const LaserLog& log, const grid::BeamOptions& beams, const CellEvidence& e,
                    const std::vector<Run>& runs, double band, double tol_a, double margin, Beyond&& beyond_at,
                    std::vector<std::uint64_t>& pass, std::vector<std::uint64_t>& hit,
                    std::vector<sparse::NearNormalBeam>& near) {
  struct Crossing {
    std::uint32_t run;
    double at;  // where the beam crossed the run's line, as a share of the beam [-]
  };
  struct Tally {
    std::vector<std::uint64_t> pass, hit;
    std::vector<sparse::NearNormalBeam> near;
    std::vector<std::uint32_t> seen;  // per run: the last beam that tested it (runs span several tiles)
    std::uint32_t beam = 0;
    std::vector<std::pair<double, sparse::NearNormalBeam>> pending;  // this beam's, with their `at`
    std::vector<Crossing> passed;                                    // the runs this beam passed
  };
  tbb::enumerable_thread_specific<Tally> tallies([&] {
    return Tally{std::vector<std::uint64_t>(runs.size(), 0),
                 std::vector<std::uint64_t>(runs.size(), 0),
                 {},
                 std::vector<std::uint32_t>(runs.size(), 0),
                 0,
                 {},
                 {}};
  });
  // Only the runs a beam comes within `band` of can count it: runs by coarse tile, each registered
  // in the tiles its segment widened by `band` reaches; a beam tests the runs of the tiles it
  // crosses, each once (the counts are those of testing every run).
  const RunTiles tiles(runs, band);
  grid::forScansInParallel(log, {}, tallies, [&](const LaserScan& scan, std::size_t index, Tally& t) {
    grid::forEachBeam(scan, beams, [&](const grid::Beam& beam) {
      const double beyond = beyond_at(beam.range);
      const double direction = wrapPi(beam.angle);
      double clear = -1.0;  // a beam without an echo: where it meets the first occupied cell (once)
      if (++t.beam == 0) {  // the stamps wrapped: start again
        std::fill(t.seen.begin(), t.seen.end(), 0u);
        t.beam = 1;
      }
      t.pending.clear();
      t.passed.clear();
      auto test = [&](std::size_t r) {
        const Vec2 n = runs[r].line.normal(), tg = runs[r].line.tangent();
        const double f = n.dot(beam.from) - runs[r].line.rho, g = n.dot(beam.to) - runs[r].line.rho;
        const double incidence = std::abs(angleDiff(direction, runs[r].line.angle));
        const double at_line = (f > 0) != (g > 0) ? f / (f - g) : 1.0;
        auto nearNormal = [&](bool returned, double along) {
          if (!returned) t.passed.push_back({static_cast<std::uint32_t>(r), at_line});
          if (incidence <= tol_a)
            t.pending.push_back(
                {at_line,
                 {static_cast<std::uint32_t>(r), static_cast<std::uint32_t>(index), static_cast<float>(incidence),
                  returned, scan.timestamp, static_cast<float>(along - runs[r].s0)}});
        };
        if (!beam.hit) {
          // No echo within the cap (nothing in range behind the run, or a dropout): the run did not
          // answer it. It passed the run when it met no wall first (a wall's dropouts stop there)
          // and its end lies `beyond` past it (a surface at the edge of the range reads beyond it).
          // The near-normal tally counts it too; leaving it out would make the scans whose passing
          // beams find nothing in range look as if every near-normal beam returned.
          if ((f > 0) != (g > 0)) {
            const double at = f / (f - g);
            const double along = tg.dot(beam.from + at * (beam.to - beam.from));
            if (along < runs[r].s0 || along > runs[r].s1) return;
            nearNormal(false, along);
            if (clear < 0.0) clear = sparse::clearUntil(e.geometry, e.label, beam.from, beam.to);
            if (at < clear && (1.0 - at) * beam.range >= beyond) ++t.pass[r];
          }
          return;
        }
        if (std::abs(g) <= band) {
          const double along = tg.dot(beam.to);
          if (along >= runs[r].s0 && along <= runs[r].s1 && std::abs(f) > band) {
            ++t.hit[r];
            nearNormal(true, along);
          }
        } else if ((f > 0) != (g > 0)) {
          // Crossed: a pass when it ends well beyond, else it stopped just behind (a wall's face).
          const double along = tg.dot(beam.from + (f / (f - g)) * (beam.to - beam.from));
          if (along < runs[r].s0 || along > runs[r].s1) return;
          if (std::abs(g) >= beyond) {
            ++t.pass[r];
            nearNormal(false, along);
          } else {
            ++t.hit[r];
          }
        }
      };
      grid::traverse(tiles.grid, beam.from, beam.to, [&](int x, int y, double, bool) {
        const std::size_t cell = tiles.grid.index(x, y);
        for (std::uint32_t k = tiles.start[cell]; k < tiles.start[cell + 1]; ++k) {
          const std::uint32_t r = tiles.runs[k];
          if (t.seen[r] == t.beam) continue;
          t.seen[r] = t.beam;
          test(r);
        }
      });
      // A near-normal beam folded by another candidate `margin` before it met a run's line (it
      // passed that line, and its reading mirrored back across it falls on a surface) never
      // reached the run: the run's visits are judged without it (a pane seen from the far side of
      // a glass room through its near pane, which folds most beams, would answer those visits
      // hardly ever). The tests within scans and at one place keep it: there a passer-by's track,
      // whose line such a mirror test also passes by chance in a rectangular room, must not hide
      // the beams that show a person.
      const double m = margin / std::max(beam.range, 1e-9);
      for (auto& [at, b] : t.pending) {
        b.folded = beam.hit && std::any_of(t.passed.begin(), t.passed.end(), [&](const Crossing& c) {
                     if (c.run == b.run || c.at >= at - m) return false;
                     const Vec2 n = runs[c.run].line.normal();
                     return detail::mirrorFallsOnSurface(e.geometry, e.label, beam.to, n,
                                                         n.dot(beam.to) - runs[c.run].line.rho, deg2rad(1.5));
                   });
        t.near.push_back(b);
      }
    });
  });
  pass.assign(runs.size(), 0);
  hit.assign(runs.size(), 0);
  near.clear();
  for (const Tally& t : tallies) {
    for (std::size_t r = 0; r < runs.size(); ++r) {
      pass[r] += t.pass[r];
      hit[r] += t.hit[r];
    }
    near.insert(near.end(), t.near.begin(), t.near.end());
  }
}

// Calls visit(linear cell index) for the cells of a run's line, half a cell past either end.
template <class Visit>
void forRunCells(const grid::GridGeometry& g, const Run& run, Visit&& visit) {
  const double half = 0.5 * g.resolution;
  grid::traverse(g, run.end(run.s0 - half), run.end(run.s1 + half),
                 [&](int x, int y, double, bool) { visit(g.index(x, y)); });
}

// Where a run's line may still be glass: from s0 and s1 on along the line over observed cells
// that are not walls, up to the run's length either way. A faint pane's run ends where its
// near-normal returns stop, which need not be where the pane stops (its ends are seen obliquely).
struct PaneLine {
  const Run* run = nullptr;
  Vec2 n, t;  // the run's line's normal and tangent
  double s0 = 0.0, s1 = 0.0;
};
PaneLine openExtent(const Run& run, const grid::GridGeometry& g, const std::vector<std::uint8_t>& labels) {
  const double step = 0.5 * g.resolution, cap = run.s1 - run.s0;
  auto reach = [&](double from, double dir) {
    double e = 0.0;
    for (; e < cap; e += step) {
      const grid::CellIndex c = g.cellAt(run.end(from + dir * (e + step)));
      if (!g.contains(c.x, c.y)) break;
      const int l = labels[g.index(c.x, c.y)];
      if (l == kOccupied || l == kUnknown) break;
    }
    return e;
  };
  return {&run, run.line.normal(), run.line.tangent(), run.s0 - reach(run.s0, -1.0), run.s1 + reach(run.s1, 1.0)};
}

// True when the return's beam crossed `pane`'s line (at least glass_margin before the return)
// where it may be glass, and its mirror image across that line falls on a surface of `labels`
// (within a fitted line's direction error, 1.5 deg): the beam was folded by the pane.
bool mirroredBy(const PaneLine& pane, const WeakReturn& r, const grid::GridGeometry& g,
                const std::vector<std::uint8_t>& labels, const SparsePaneOptions& o) {
  const double rho = pane.run->line.rho;
  const double d0 = pane.n.dot(r.from) - rho, d1 = pane.n.dot(r.at) - rho;
  if (d0 * d1 >= 0.0 || std::abs(d1) < o.glass_margin) return false;
  const double s = pane.t.dot(r.from + d0 / (d0 - d1) * (r.at - r.from));
  return s >= pane.s0 && s <= pane.s1 && detail::mirrorFallsOnSurface(g, labels, r.at, pane.n, d1, deg2rad(1.5));
}

// True when most of the run's returns crossed another pane of `panes` (labels with the candidate
// runs drawn in; a glass cell with at least min_pane_cells glass cells in its 5 x 5 block, more than
// tol_r + glass_margin off the run's line and not its mirror image of a surface) at least
// glass_margin before the return, or were folded by another run of `others` (mirroredBy). Beyond
// a pane, mirror images (a wall seen via the pane at the wall's normal) and walls seen through it
// at grazing incidence (shifted sideways by up to the pane's thickness, they land in front of
// themselves) have the signature of a faint pane.
bool seenThroughAnotherPane(const std::vector<WeakReturn>& w, const Run& run, const std::vector<PaneLine>& others,
                            const CellEvidence& panes, double tol_r, const SparsePaneOptions& o) {
  const grid::GridGeometry& g = panes.geometry;
  // Not another pane: glass within the run's own band (tol_r) and glass_margin of its line (a
  // second candidate along the same pane, a few degrees off), and glass that mirrors a surface
  // across the run's line: the run's phantom, seen by beams from across the run (through the
  // room and back off it).
  const Vec2 n = run.line.normal();
  auto ownBandOrPhantom = [&](int x, int y) {
    const Vec2 c = g.center(x, y);
    const double d = n.dot(c) - run.line.rho;
    return std::abs(d) < tol_r + o.glass_margin || detail::mirrorFallsOnSurface(g, panes.label, c, n, d, deg2rad(1.5));
  };
  auto isPane = [&](int x, int y) {
    return sparse::glassInBlock(g, panes.label, x, y, 2) >= o.min_pane_cells && !ownBandOrPhantom(x, y);
  };
  std::size_t via = 0;
  for (std::size_t i : run.returns) {
    const double range = (w[i].at - w[i].from).norm();
    bool crossed = false;
    grid::traverse(g, w[i].from, w[i].at, [&](int x, int y, double enter, bool) {
      if (enter * range >= range - o.glass_margin) return false;
      crossed = isGlass(panes.label[g.index(x, y)]) && isPane(x, y);
      return !crossed;
    });
    if (!crossed)
      crossed = std::any_of(others.begin(), others.end(), [&](const PaneLine& other) {
        return other.run != &run && mirroredBy(other, w[i], g, panes.label, o);
      });
    via += crossed;
  }
  return static_cast<double>(via) >= o.max_via * static_cast<double>(run.returns.size());
}

// True when a run's near-normal beams (near_hit of near_met returned) are not shown to return
// more often than its other beams (other_hit of other_met), or are shown to return less often
// than `contrast` times their rate (one-sided binomial p below max_p): no lobe, so no pane.
bool lacksLobe(int near_hit, int near_met, std::uint64_t other_hit, std::uint64_t other_met, double contrast,
               double max_p) {
  if (other_met == 0) return false;
  const double other_rate = static_cast<double>(other_hit) / static_cast<double>(other_met);
  const double log10_p = std::log10(max_p);
  const bool above = other_rate <= 0.0 || log10BinomialTail(near_hit, near_met, other_rate) < log10_p;
  const double contrast_rate = std::min(1.0, contrast * other_rate);
  const bool below = contrast_rate > 0.0 && log10BinomialCdf(near_hit, near_met, contrast_rate) < log10_p;
  return !above || below;
}

// True when half of `run`'s returns or more lie within `reach` of `pane`'s segment (along it,
// within half a reach of its ends): the same pane, seen by beams that met it further off its
// normal.
bool liesAlong(const Run& run, const Run& pane, const std::vector<WeakReturn>& w, double reach) {
  const Vec2 n = pane.line.normal(), t = pane.line.tangent();
  const auto on_pane = std::count_if(run.returns.begin(), run.returns.end(), [&](std::size_t i) {
    const double along = t.dot(w[i].at);
    return std::abs(n.dot(w[i].at) - pane.line.rho) <= reach && along >= pane.s0 - 0.5 * reach &&
           along <= pane.s1 + 0.5 * reach;
  });
  return 2 * static_cast<std::size_t>(on_pane) >= run.returns.size();
}

// The share of observed cells around a run (within `margin`, off its band of half-width tol_r)
// that hold a weak return compatible with its line: weak returns gather near surfaces, well above
// their average over the floor.
double localBackground(const WeakReturns& weak, const CellEvidence& e, const Run& run, double margin, double tol_r,
                       double tol_a) {
  const grid::GridGeometry& g = e.geometry;
  const Vec2 n = run.line.normal(), t = run.line.tangent();
  const double m = margin;
  Vec2 lo = run.end(run.s0 - m) - m * n, hi = lo;
  const Vec2 corners[] = {run.end(run.s0 - m) + m * n, run.end(run.s1 + m) - m * n, run.end(run.s1 + m) + m * n};
  for (const Vec2& c : corners) {
    lo = lo.cwiseMin(c);
    hi = hi.cwiseMax(c);
  }
  const grid::CellIndex a = g.cellAt(lo), b = g.cellAt(hi);
  double seen = 0.0, holding = 0.0;
  for (int y = std::max(0, a.y); y <= std::min(g.height - 1, b.y); ++y)
    for (int x = std::max(0, a.x); x <= std::min(g.width - 1, b.x); ++x) {
      const Vec2 c = g.center(x, y);
      const double d = std::abs(n.dot(c) - run.line.rho), along = t.dot(c);
      if (d <= tol_r || d > m || along < run.s0 - m || along > run.s1 + m) continue;
      const std::size_t i = g.index(x, y);
      if (e.label[i] == kUnknown) continue;
      seen += 1.0;
      holding += weak.compatible(static_cast<std::uint32_t>(i), run.line.angle, tol_a);
    }
  return seen > 0.0 ? holding / seen : 0.0;
}

}  // namespace

SparsePaneStats findSparsePanes(const LaserLog& log, const grid::BeamOptions& beams, const SparsePaneOptions& o,
                                CellEvidence& e) {
  SparsePaneStats stats;
  const grid::GridGeometry& g = e.geometry;
  if (e.cells.empty() || log.scanCount() == 0) return stats;
  const double tol_r = std::max(o.offset_tol, 2.5 * o.range_sigma);
  const double tol_a = deg2rad(o.angle_tol_deg);
  auto sigmaAt = [&](double range) { return sparse::rangeSigma(o, range); };

  const WeakReturns weak_returns(log, beams, o, e);
  const std::vector<WeakReturn>& weak = weak_returns.returns();
  stats.weak_returns = weak.size();
  if (weak.size() < static_cast<std::size_t>(o.min_returns)) return stats;
  const int pad = static_cast<int>(std::ceil(o.angle_tol_deg));
  const int wr = std::max(1, static_cast<int>(std::ceil(tol_r / g.resolution)));
  const std::vector<Line> seeds = seedLines(weak, g, pad, wr, o.min_returns);
  const double rho_bins = 2.0 * std::ceil((0.5 * (g.maxCorner() - g.origin).norm() + 1.0) / g.resolution) + 1.0;

  // Runs along each peak's line; a contrario against the background of its direction.
  const double diagonal_cells = (g.maxCorner() - g.origin).norm() / g.resolution;
  const double log10_tests = std::log10(kAngleBins * rho_bins) + 2.0 * std::log10(diagonal_cells);
  const double band_cells = std::max(1.0, 2.0 * tol_r / g.resolution);
  std::vector<bool> used(weak.size(), false);
  std::vector<Run> runs;
  for (const Line& seed : seeds) {
    std::vector<std::size_t> idx = gather(weak_returns, used, seed, tol_a, tol_r);
    if (idx.size() < static_cast<std::size_t>(o.min_returns)) continue;
    Line line = fitLine(weak, idx, seed, tol_a);
    idx = gather(weak_returns, used, line, tol_a, tol_r);
    if (idx.size() < static_cast<std::size_t>(o.min_returns)) continue;
    // Refit while the line gathers more: a line fitted to the part of a long pane near the seed
    // drifts off the pane's far parts (a tenth of a degree is 5 cm at 30 m), which then split
    // into runs too short to stand out, or go to a second line.
    for (int round = 0; round < 3; ++round) {
      const Line refit = fitLine(weak, idx, line, tol_a);
      std::vector<std::size_t> more = gather(weak_returns, used, refit, tol_a, tol_r);
      if (more.size() <= idx.size()) break;
      line = refit;
      idx = std::move(more);
    }
    for (std::size_t i : idx) used[i] = true;
    // Optionally (off by default), each cell by the share of its returns near the line's normal:
    // a cell that returns to beams of every direction is a corner, a post or an edge. A share is
    // no rate, though (SparsePaneOptions::min_specific); the lobe test per run below replaces it.
    if (o.min_specific > 0.0)
      idx.erase(std::remove_if(idx.begin(), idx.end(),
                               [&](std::size_t i) {
                                 return !weak_returns.specific(weak[i].cell, line.angle, deg2rad(o.specific_tol_deg),
                                                               o.min_specific);
                               }),
                idx.end());
    const double p = weak_returns.background(line.angle, pad);
    for (Run& run : splitRuns(weak, idx, line, g.resolution, o.max_gap, o.gap_factor)) {
      if (run.returns.size() < static_cast<std::size_t>(o.min_returns) || run.s1 - run.s0 < o.min_length) continue;
      ++stats.runs_tested;
      std::vector<std::uint32_t> cells;
      for (std::size_t i : run.returns) cells.push_back(weak[i].cell);
      std::sort(cells.begin(), cells.end());
      const int k = static_cast<int>(std::unique(cells.begin(), cells.end()) - cells.begin());
      const int n = static_cast<int>(std::ceil(((run.s1 - run.s0) / g.resolution + 1.0) * band_cells));
      // The tail grows with the background, so a run chance explains at the floor-wide density p
      // needs no local one.
      run.log10_nfa = log10_tests + log10BinomialTail(k, n, p);
      if (run.log10_nfa < o.log10_max_nfa) {
        const double local = localBackground(weak_returns, e, run, o.background_margin, tol_r, tol_a);
        if (local > p) run.log10_nfa = log10_tests + log10BinomialTail(k, n, local);
      }
      if (run.log10_nfa >= o.log10_max_nfa) {
        ++stats.rejected_chance;
        continue;
      }
      runs.push_back(std::move(run));
    }
  }

  // Glass is crossed: most beams that meet the run pass it and end well beyond.
  std::vector<std::uint64_t> pass, hit;
  std::vector<sparse::NearNormalBeam> near;
  countCrossings(
      log, beams, e, runs, tol_r, tol_a, o.glass_margin,
      [&](double range) { return std::max(o.beyond, 5.0 * sigmaAt(range)); }, pass, hit, near);
  // Each run's near-normal beams, and those it returned.
  std::vector<int> near_met(runs.size(), 0), near_returned(runs.size(), 0);
  for (const sparse::NearNormalBeam& b : near) {
    ++near_met[b.run];
    near_returned[b.run] += b.returned ? 1 : 0;
  }
  const std::vector<sparse::ScanCoherence> coherence =
      sparse::scanCoherence(near, runs.size(), deg2rad(o.lobe_bin_deg));
  std::vector<sparse::NearNormalBeam> own;  // the beams no other candidate folded first
  std::copy_if(near.begin(), near.end(), std::back_inserter(own),
               [](const sparse::NearNormalBeam& b) { return !b.folded; });
  const std::vector<sparse::ScanCoherence> by_visit =
      o.max_visit_gap_s > 0.0 ? sparse::visitCoherence(own, runs.size(), deg2rad(o.lobe_bin_deg), o.max_visit_gap_s)
                              : std::vector<sparse::ScanCoherence>(runs.size());
  const std::vector<sparse::ScanCoherence> by_place =
      o.max_place_dt_s > 0.0
          ? sparse::placeCoherence(near, runs.size(), deg2rad(o.lobe_bin_deg), o.max_place_dt_s, o.max_place_ds)
          : std::vector<sparse::ScanCoherence>(runs.size());
  std::vector<Run> seen_through;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const double total = static_cast<double>(pass[r] + hit[r]);
    if (pass[r] < static_cast<std::uint64_t>(o.min_returns) ||
        static_cast<double>(pass[r]) < o.min_transmission * total) {
      ++stats.rejected_opaque;
      continue;
    }
    // Far fewer near-normal returns than the faintest pane gives: hits now and then (people).
    if (o.min_normal_rate > 0.0 &&
        log10BinomialCdf(near_returned[r], near_met[r], o.min_normal_rate) < std::log10(o.max_faint_p)) {
      ++stats.rejected_faint;
      continue;
    }
    // No more often near the normal than at other angles: no lobe, so no pane.
    const std::uint64_t met = pass[r] + hit[r];
    const auto near_hits = static_cast<std::uint64_t>(near_returned[r]);
    if (o.min_lobe_contrast > 0.0 &&
        lacksLobe(near_returned[r], near_met[r], hit[r] - std::min(hit[r], near_hits),
                  met - std::min(met, static_cast<std::uint64_t>(near_met[r])), o.min_lobe_contrast, o.max_faint_p)) {
      ++stats.rejected_unspecific;
      continue;
    }
    runs[r].transmission = static_cast<double>(pass[r]) / total;
    runs[r].by_scan = coherence[r];
    runs[r].by_visit = by_visit[r];  // all zero when the test is off: never a transient
    runs[r].by_place = by_place[r];  // (the same)
    if (sparse::isTransient(coherence[r], o.max_transient_p, o.min_transient_correlation)) {
      ++stats.rejected_transient;
      continue;
    }
    // Seen in one visit only (by_visit.scans counts the visits with two near-normal beams or more;
    // 0 when the visit test is off): the within-scan test alone decides, at a weaker significance
    // (a p at most max_transient_p rejects nothing the test above kept).
    if (by_visit[r].scans == 1 &&
        sparse::isTransient(coherence[r], o.max_one_visit_transient_p, o.min_transient_correlation)) {
      ++stats.rejected_transient;
      ++stats.rejected_transient_one_visit;
      continue;
    }
    if (sparse::isTransient(by_visit[r], o.max_transient_p, o.min_visit_correlation)) {
      ++stats.rejected_one_visit;
      continue;
    }
    // At one place moments apart, at the within-scan test's significance (its one-visit one for a
    // run seen in one visit).
    if (sparse::isTransient(by_place[r], by_visit[r].scans == 1 ? o.max_one_visit_transient_p : o.max_transient_p,
                            o.min_transient_correlation)) {
      ++stats.rejected_place;
      continue;
    }
    seen_through.push_back(std::move(runs[r]));
  }

  // Each run's cells to draw: empty ones, not within 2 cells of glass the classifiers found (a
  // second line of glass beside a classified pane, a cell off, would make a band the vectorizer
  // fits between the two).
  std::vector<std::vector<std::size_t>> to_draw(seen_through.size());
  for (std::size_t r = 0; r < seen_through.size(); ++r)
    forRunCells(g, seen_through[r], [&](std::size_t i) {
      const grid::CellIndex c = g.cellOf(i);
      if (e.label[i] == kEmpty && sparse::glassInBlock(g, e.label, c.x, c.y, 2) == 0) to_draw[r].push_back(i);
    });
  // Not seen through another pane: the labels with every candidate drawn in as glass.
  CellEvidence panes;
  panes.geometry = g;
  panes.bins = e.bins;
  panes.num_labels = e.num_labels;
  panes.label = e.label;
  auto labelOf = [&](const Run& run) {
    return static_cast<std::uint8_t>(glassLabel(grid::angleBin(run.line.angle, e.bins)));
  };
  for (const Run& run : seen_through)
    forRunCells(g, run, [&](std::size_t i) {
      if (panes.label[i] == kEmpty) panes.label[i] = labelOf(run);
    });
  std::vector<PaneLine> lines;
  for (const Run& run : seen_through) lines.push_back(openExtent(run, g, panes.label));
  std::vector<std::size_t> accepted;
  for (std::size_t r = 0; r < seen_through.size(); ++r) {
    if (seenThroughAnotherPane(weak, seen_through[r], lines, panes, tol_r, o))
      ++stats.rejected_through;
    else
      accepted.push_back(r);
  }
  // One pane, one run: a run that crosses a pane a few degrees off its line gathers, over a metre
  // or more when the range noise is large, the returns of beams that met the pane that far off its
  // normal (within a broad lobe they come back). Most of its returns then lie within 2 tol_r of
  // the pane's segment: it is dropped for the run with more returns.
  std::vector<std::size_t> by_strength = accepted;
  std::stable_sort(by_strength.begin(), by_strength.end(), [&](std::size_t a, std::size_t b) {
    return seen_through[a].returns.size() > seen_through[b].returns.size();
  });
  std::vector<std::uint8_t> duplicate(seen_through.size(), 0);
  std::vector<const Run*> kept;
  for (std::size_t r : by_strength) {
    duplicate[r] = std::any_of(kept.begin(), kept.end(),
                               [&](const Run* pane) { return liesAlong(seen_through[r], *pane, weak, 2.0 * tol_r); });
    if (!duplicate[r]) kept.push_back(&seen_through[r]);
  }
  for (std::size_t r : accepted) {
    const Run& run = seen_through[r];
    if (duplicate[r]) {
      ++stats.rejected_duplicate;
      continue;
    }
    ++stats.panes;
    stats.metres += run.s1 - run.s0;
    stats.found.push_back({run.end(run.s0), run.end(run.s1), run.returns.size(), run.log10_nfa, run.transmission,
                           run.by_scan, run.by_visit, run.by_place});
    for (std::size_t i : to_draw[r]) {
      if (e.label[i] != kEmpty) continue;  // an earlier pane drew it
      e.label[i] = labelOf(run);
      ++stats.cells_labelled;
    }
  }
  return stats;
}

}  // namespace glassmap::glass
