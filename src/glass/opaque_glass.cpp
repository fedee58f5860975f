#include "glassmap/glass/opaque_glass.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <boost/pending/disjoint_sets.hpp>

#include "binomial.hpp"
#include "glass_tiles.hpp"
#include "glassmap/glass/scan_coherence.hpp"
#include "glassmap/grid/parallel_scans.hpp"
#include "glassmap/grid/traversal.hpp"

namespace glassmap::glass {

namespace {

// The pane of each glass cell (cells: ascending, slots: their index): a representative slot of
// the glass cells connected to it (8-neighbours) whose normals are at most max_bin_gap bins apart.
std::vector<std::size_t> paneOf(const CellEvidence& e, const std::vector<std::size_t>& cells,
                                const detail::CandidateIndex& slots, int max_bin_gap = 1) {
  boost::disjoint_sets_with_storage<> sets(cells.size());
  for (std::size_t c = 0; c < cells.size(); ++c) sets.make_set(c);
  const auto bin_gap = [&](std::size_t a, std::size_t b) {
    const int d = std::abs(glassBin(e.label[cells[a]]) - glassBin(e.label[cells[b]]));
    return std::min(d, e.bins - d);
  };
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const grid::CellIndex at = e.geometry.cellOf(cells[c]);
    constexpr int kForward[4][2] = {{1, 0}, {1, 1}, {0, 1}, {-1, 1}};  // each neighbour pair once
    for (const auto& d : kForward) {
      const std::int64_t n = slots.find(at.x + d[0], at.y + d[1]);
      if (n >= 0 && bin_gap(c, static_cast<std::size_t>(n)) <= max_bin_gap)
        sets.union_set(c, static_cast<std::size_t>(n));
    }
  }
  std::vector<std::size_t> pane(cells.size());
  for (std::size_t c = 0; c < cells.size(); ++c) pane[c] = sets.find_set(c);
  return pane;
}

// The laser's spurious readings, from the scans themselves: a reading between two neighbours that
// lie on one surface (ranges within what a flat surface at that spacing allows) that returned
// nothing or read well beyond them (max(beyond, 5 sigma)): a dropout or a random reading, what a
// wall lets "through".
void countSpurious(const LaserScan& scan, const OpaqueGlassOptions& o, std::uint64_t& surface,
                   std::uint64_t& spurious) {
  const double step = std::abs(scan.angular_step);
  for (std::size_t i = 1; i + 1 < scan.ranges.size(); ++i) {
    if (!scan.isReturn(i - 1) || !scan.isReturn(i + 1)) continue;
    const double a = scan.ranges[i - 1], c = scan.ranges[i + 1], r = 0.5 * (a + c);
    if (r < 0.05 || std::abs(c - a) > 6.0 * r * step) continue;  // near-flat pairs only
    ++surface;
    const double beyond = std::max(o.beyond, 5.0 * std::hypot(o.range_sigma, o.range_sigma_rel * r));
    if (!scan.isReturn(i) || scan.ranges[i] > r + beyond) ++spurious;
  }
}

using detail::log10BinomialCdf;
using sparse::kLeastNormalRate;

// How the near-normal beams of each pane (or unit: indexed by its representative slot, the
// beams' `run`) hang together within scans and by visit, and whether that makes it a transient
// (opaque_glass.hpp).
struct PaneCoherence {
  sparse::ScanCoherence by_scan, by_visit;
  bool transient = false;
  bool still = false;  // seen in enough scans to show a transient, and its beams kept apart: static
};
std::vector<PaneCoherence> coherenceOf(std::vector<sparse::NearNormalBeam>& near, std::size_t slots,
                                       const OpaqueGlassOptions& o) {
  std::vector<PaneCoherence> out(slots);
  if (!(o.max_transient_p > 0.0) || near.empty()) return out;
  const double bin = deg2rad(o.lobe_bin_deg);
  const std::vector<sparse::ScanCoherence> by_scan = sparse::scanCoherence(near, slots, bin);
  const std::vector<sparse::ScanCoherence> by_visit = o.max_visit_gap_s > 0.0
                                                          ? sparse::visitCoherence(near, slots, bin, o.max_visit_gap_s)
                                                          : std::vector<sparse::ScanCoherence>(slots);
  for (std::size_t p = 0; p < slots; ++p) {
    PaneCoherence& c = out[p];
    c.by_scan = by_scan[p];
    c.by_visit = by_visit[p];
    c.transient = sparse::isTransient(c.by_scan, o.max_transient_p, o.min_transient_correlation) ||
                  sparse::isTransient(c.by_visit, o.max_transient_p, o.min_visit_correlation);
    c.still = !c.transient && c.by_scan.scans >= static_cast<std::size_t>(o.min_static_scans) &&
              c.by_scan.correlation < 0.5 * o.min_transient_correlation;
  }
  return out;
}

// Per glass cell of a transient pane: whether it returned near-normal beams in two of the pane's
// visits or more (a visit: a stretch of the pane's near-normal beams without a gap over max_gap_s).
// A person standing in front of a pane joins the pane's cells, and the pane, blocked scan by scan,
// comes out a transient as a whole; the pane's own cells answered every visit, the person's the
// one it was there for.
std::vector<bool> returnedInTwoVisits(const std::vector<sparse::NearNormalBeam>& near,
                                      std::vector<std::pair<std::uint32_t, double>> returned_at,
                                      const std::vector<std::size_t>& pane, const std::vector<PaneCoherence>& of_pane,
                                      double max_gap_s) {
  std::vector<bool> stays(pane.size(), false);
  if (!(max_gap_s > 0.0)) return stays;
  std::vector<std::vector<double>> times(pane.size());  // per transient pane: its near-normal beams' times
  for (const sparse::NearNormalBeam& b : near)
    if (of_pane[b.run].transient) times[b.run].push_back(b.time);
  std::vector<std::vector<double>> starts(pane.size());  // ...and the times its visits start
  for (std::size_t p = 0; p < pane.size(); ++p) {
    std::sort(times[p].begin(), times[p].end());
    for (std::size_t i = 0; i < times[p].size(); ++i)
      if (i == 0 || times[p][i] - times[p][i - 1] > max_gap_s) starts[p].push_back(times[p][i]);
  }
  std::sort(returned_at.begin(), returned_at.end());
  for (std::size_t i = 0; i < returned_at.size();) {
    const std::uint32_t c = returned_at[i].first;
    const std::vector<double>& s = starts[pane[c]];
    std::ptrdiff_t first_visit = -1;
    for (; i < returned_at.size() && returned_at[i].first == c; ++i) {
      if (s.empty()) continue;
      const std::ptrdiff_t v = std::upper_bound(s.begin(), s.end(), returned_at[i].second) - s.begin() - 1;
      if (first_visit < 0) first_visit = v;
      if (v != first_visit) stays[c] = true;
    }
  }
  return stays;
}

}  // namespace

OpaqueGlassStats relabelOpaqueGlass(const LaserLog& log, const grid::BeamOptions& beams, const OpaqueGlassOptions& o,
                                    CellEvidence& e) {
  OpaqueGlassStats stats;
  const grid::GridGeometry& g = e.geometry;
  // Glass cells get a slot; the pane normal of each from its label's angle bin.
  std::vector<bool> is_glass(g.cells(), false);
  std::vector<std::size_t> cells;  // ascending
  std::vector<Vec2> normals;
  for (std::size_t i = 0; i < g.cells(); ++i) {
    if (!isGlass(e.label[i])) continue;
    is_glass[i] = true;
    cells.push_back(i);
    const double a = glassBin(e.label[i]) * kPi / e.bins;  // bin b is centred on b * 180 / bins
    normals.emplace_back(std::cos(a), std::sin(a));
  }
  stats.glass_cells = cells.size();
  if (cells.empty()) return stats;
  // Within a cell of a glass cell: a beam through a one-cell gap in a pane's labels went through
  // the pane.
  std::vector<bool> near_glass(g.cells(), false);
  for (std::size_t i : cells) {
    const grid::CellIndex c = g.cellOf(i);
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        if (g.contains(c.x + dx, c.y + dy)) near_glass[g.index(c.x + dx, c.y + dy)] = true;
  }

  // Per thread: passes and stops per glass cell. Integer sums: the result does not depend on how
  // the scans were shared out.
  struct Tally {
    std::vector<std::uint32_t> pass, stop, own;
    // Returns that came through another pane first; direct returns and passes along the normal.
    std::vector<std::uint32_t> through, near_own, near_pass;
    std::uint64_t surface = 0, spurious = 0;   // in-scan: readings between two on one surface, and wrong ones
    std::vector<sparse::NearNormalBeam> near;  // the transient test's: `run` is the unit's slot
    std::vector<std::pair<std::uint32_t, double>> returned_at;  // ...those returned: the cell's slot, time
  };
  tbb::enumerable_thread_specific<Tally> tallies([&] {
    const std::vector<std::uint32_t> zero(cells.size(), 0);
    return Tally{zero, zero, zero, zero, zero, zero, 0, 0, {}, {}};
  });
  // Along the normal: within half a bin of it (the label's own bin).
  const double cos_near = std::cos(0.5 * kPi / e.bins);
  const detail::GlassTiles tiles(e);
  const detail::CandidateIndex slots(g, cells);  // glass cell -> its slot
  const std::vector<std::size_t> pane = paneOf(e, cells, slots);
  const std::vector<std::size_t> unit = paneOf(e, cells, slots, 0);  // ...of one normal bin
  const bool transient_test = o.max_transient_p > 0.0;
  grid::forScansInParallel(log, {}, tallies, [&](const LaserScan& scan, std::size_t index, Tally& t) {
    countSpurious(scan, o, t.surface, t.spurious);
    grid::forEachBeam(scan, beams, [&](const grid::Beam& beam) {
      // Only beams that come near glass; walked from the laser on (a wall before the pane counts).
      if (!tiles.near(beam.from, beam.to)) return;
      // A beam that went through a pane may have been folded by it: beyond that pane, where its
      // straight continuation ends says nothing about what it crosses.
      auto slot = [&](int x, int y) { return static_cast<std::size_t>(slots.find(x, y)); };
      // A return in a glass cell itself.
      const grid::CellIndex end = g.cellAt(beam.to);
      const bool own = beam.hit && g.contains(end) && is_glass[g.index(end)];
      if (own) ++t.own[slot(end.x, end.y)];
      // The glass cells it crosses, up to where it leaves the first pane. The beam's terms are
      // worked out at its first glass cell (most beams near a pane cross none).
      bool in_glass = false, direct = false, gap = false;
      double beyond = 0.0;
      Vec2 dir = Vec2::Zero();
      // The transient test's record, for the unit of the first glass cell met: that cell's slot
      // and incidence, and whether the beam passed a cell of its pane (or returned in one).
      std::size_t first = 0;
      double first_cos = 0.0;
      bool passed_first = false;
      grid::traverse(g, beam.from, beam.to, [&](int x, int y, double, bool last) {
        const std::size_t i = g.index(x, y);
        if (!is_glass[i]) {
          if (in_glass) return false;  // past the first pane: nothing more counts
          // Through a wall (not a pane's frame) first: a straight path that cannot have been,
          // a beam some pane folded (a mirror image of a mirror image between facing panes
          // lies beyond the walls behind them) or a spurious reading; it says nothing here.
          if (e.label[i] == kOccupied && !near_glass[i]) return false;
          if (near_glass[i]) gap = true;
          return !gap || near_glass[i];  // out of a gap in a pane's labels: through the pane
        }
        const std::size_t c = slot(x, y);
        if (!in_glass) {
          const double sigma = std::hypot(o.range_sigma, o.range_sigma_rel * beam.range);
          beyond = std::max(o.beyond, 5.0 * sigma);
          dir = (beam.to - beam.from) / std::max(beam.range, 1e-9);
          first = c;
          first_cos = std::abs(dir.dot(normals[c]));
        }
        in_glass = true;
        if (last) {
          direct = true;  // its reading in the first pane it met
          return false;
        }
        const Vec2 n = dir.dot(normals[c]) >= 0.0 ? normals[c] : Vec2(-normals[c]);
        const double past = n.dot(beam.to - g.center(x, y));
        const bool pass = !beam.hit || past >= beyond;
        ++(pass ? t.pass[c] : t.stop[c]);
        if (pass && std::abs(dir.dot(n)) >= cos_near) ++t.near_pass[c];
        passed_first = passed_first || (pass && pane[c] == pane[first]);
        return true;
      });
      bool returned = false;
      if (own) {  // direct: the walk reached its reading in the first pane (dir is set)
        const std::size_t c = slot(end.x, end.y);
        if (!direct) {
          ++t.through[c];
        } else if (std::abs(dir.dot(normals[c])) >= cos_near) {
          ++t.near_own[c];
        }
        returned = direct && pane[c] == pane[first];
      }
      if (transient_test && in_glass && first_cos >= cos_near && (returned || passed_first)) {
        t.near.push_back({static_cast<std::uint32_t>(unit[first]), static_cast<std::uint32_t>(index),
                          static_cast<float>(std::acos(std::min(1.0, first_cos))), returned, scan.timestamp});
        if (returned) t.returned_at.emplace_back(static_cast<std::uint32_t>(slot(end.x, end.y)), scan.timestamp);
      }
    });
  });
  std::vector<std::uint32_t> pass(cells.size(), 0), stop(cells.size(), 0), own(cells.size(), 0);
  std::vector<std::uint32_t> through(cells.size(), 0), near_own(cells.size(), 0), near_pass(cells.size(), 0);
  std::vector<sparse::NearNormalBeam> near;
  std::vector<std::pair<std::uint32_t, double>> returned_at;
  for (const Tally& t : tallies) {
    near.insert(near.end(), t.near.begin(), t.near.end());
    returned_at.insert(returned_at.end(), t.returned_at.begin(), t.returned_at.end());
    stats.surface_readings += t.surface;
    stats.spurious_readings += t.spurious;
    for (std::size_t c = 0; c < cells.size(); ++c) {
      pass[c] += t.pass[c];
      stop[c] += t.stop[c];
      own[c] += t.own[c];
      through[c] += t.through[c];
      near_own[c] += t.near_own[c];
      near_pass[c] += t.near_pass[c];
    }
  }

  // People, by their beams' timing: each unit (connected glass cells of one normal bin) and each
  // pane (units whose normals are at most a bin apart) on its own near-normal beams.
  std::vector<sparse::NearNormalBeam> near_pane = near;
  for (sparse::NearNormalBeam& b : near_pane) b.run = static_cast<std::uint32_t>(pane[b.run]);
  const std::vector<PaneCoherence> unit_time = coherenceOf(near, cells.size(), o);
  const std::vector<PaneCoherence> pane_time = coherenceOf(near_pane, cells.size(), o);
  for (const PaneCoherence& p : pane_time) {
    stats.panes_tested += p.by_scan.beams > 0;
    stats.transient_panes += p.transient;
  }
  const std::vector<bool> two_visits = returnedInTwoVisits(near_pane, returned_at, pane, pane_time, o.max_visit_gap_s);
  // A cell is a transient's when its unit is one, or when its pane is one and nothing says the
  // cell stood there: it answered one visit only, and its unit is not plainly still (a person
  // beside a pane joins the pane, and their transient pooled makes the pane's a transient; the
  // pane's own cells are a unit that returned all along).
  const auto transientCell = [&](std::size_t c) {
    const PaneCoherence& u = unit_time[unit[c]];
    return u.transient || (pane_time[pane[c]].transient && !two_visits[c] && !u.still);
  };

  // A pane lets light through somewhere along it: cells too thinly seen to decide alone (the MRF
  // carries a label along a line of cells few beams reached) take the verdict of their pane, its
  // evidence pooled.
  struct Pooled {
    double pass = 0, stop = 0, own = 0, through = 0, near_own = 0, near_pass = 0;
  };
  std::vector<Pooled> pooled(cells.size());
  for (std::size_t c = 0; c < cells.size(); ++c) {
    Pooled& p = pooled[pane[c]];
    p.pass += pass[c];
    p.stop += stop[c];
    p.own += own[c];
    p.through += through[c];
    p.near_own += near_own[c];
    p.near_pass += near_pass[c];
  }
  // The verdict on evidence (passes, stops, returns in the cells): nullopt when too little.
  const auto opaque = [&](double p, double s, double returns) -> std::optional<bool> {
    // Returned by many beams and passed by none that came to it directly: nothing says it lets
    // light through (glass seen only through other glass, and the far walls behind it).
    if (p == 0 && returns >= o.min_unpassed_returns) return true;
    if (p + s < o.min_crossings) return std::nullopt;
    return p < o.min_transmission * (p + s);
  };
  // A pane's pooled evidence first: many beams returned from it and its passes are no more than
  // the laser's spurious readings make at a wall (no-return and random readings: their share among
  // readings between two of one surface, countSpurious; a binomial upper bound at 3 sigma) says
  // nothing lets light through, whatever the few crossings of one cell say (a crossing count that
  // ignores the returns takes a dropout behind a wall for a pass). Then the cell's own evidence,
  // then, for a cell too thinly seen, its pane's crossings pooled.
  const auto spuriousOnly = [&](const Pooled& p) {
    const double spurious = stats.spuriousShare() * (p.pass + p.own);
    return p.own >= o.min_unpassed_returns && p.pass <= spurious + 3.0 * std::sqrt(spurious);
  };
  // A mirror image drawn in open space: its returns came through other glass (the straight path
  // of a beam that a pane turned runs on through the pane), while the beams that came to it
  // directly along its normal passed it and did not return, where a pane returns at least
  // kLeastNormalRate of them per cell (a faint laser's lobe, spread over a pane's cells:
  // PaneLanding); P(so few | that rate) < 1e-3.
  const auto imageOnly = [&](const Pooled& p) {
    if (p.through < o.min_unpassed_returns || p.own - p.through > 0.1 * p.own) return false;
    return log10BinomialCdf(static_cast<int>(p.near_own), static_cast<int>(p.near_own + p.near_pass),
                            kLeastNormalRate) < -3.0;
  };
  // Seen only through other glass, and too thinly to decide: every return of the cell and of its
  // pane came through another pane first and no beam reached them directly to pass or stop. Such
  // evidence cannot tell a pane from the noisy band of a far wall seen through glass (its few
  // returns near the normal and misses at grazing incidence look like a lobe): nothing says glass.
  const auto onlyThroughGlass = [&](const Pooled& p) {
    return p.own > 0 && p.through >= p.own && p.pass + p.stop < o.min_crossings;
  };
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const Pooled& of_pane = pooled[pane[c]];
    std::optional<bool> verdict;
    if (transientCell(c)) {
      verdict = true;
      ++stats.decided_by_pane;
      ++stats.transient_cells;
    } else if (imageOnly(of_pane)) {
      verdict = true;
      ++stats.decided_by_pane;
      ++stats.images;
    } else if (spuriousOnly(of_pane)) {
      verdict = true;
      ++stats.decided_by_pane;
    } else if ((verdict = opaque(pass[c], stop[c], own[c]))) {
      ++stats.decided;
    } else if ((verdict = opaque(of_pane.pass, of_pane.stop, of_pane.own))) {
      ++stats.decided_by_pane;
    } else if (onlyThroughGlass(of_pane)) {
      verdict = true;
      ++stats.decided_by_pane;
      ++stats.through_glass_only;
    } else {
      continue;
    }
    if (!*verdict) continue;
    const std::size_t i = cells[c];
    const std::int64_t id = e.candidate(static_cast<std::uint32_t>(i));
    std::uint8_t best = kEmpty;
    if (id >= 0) {
      const float* cost = e.costs(static_cast<std::size_t>(id));
      best = cost[kOccupied] < cost[kEmpty] ? kOccupied : kEmpty;
    }
    e.label[i] = best;
    ++stats.relabelled;
  }
  return stats;
}

}  // namespace glassmap::glass
