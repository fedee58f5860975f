#include "glassmap/vector/scan_fit.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "box_pairs.hpp"
#include "segment_index.hpp"

namespace glassmap::vector {
namespace {

// Offsets are summed as integers of this many metres: sums over threads in any order agree.
constexpr double kUnit = 1e-5;

// Per movable segment: its returns' signed offsets from its line, binned, with exact sums.
struct Tally {
  std::vector<std::uint32_t> count;  // [segment * bins + bin]
  std::vector<std::int64_t> sum;     // offsets in kUnit
};

// The line's shift onto its returns (0: it stays), from one segment's bins.
double bestShift(const std::uint32_t* count, const std::int64_t* sum, std::size_t bins, const ScanFitOptions& o,
                 std::size_t& total, std::size_t& before, std::size_t& after) {
  const int half = static_cast<int>(bins / 2);
  auto offset = [&](int k) { return (k - half) * o.bin; };
  auto within = [&](double centre, double width) {
    std::size_t n = 0;
    for (std::size_t k = 0; k < bins; ++k)
      if (std::abs(offset(static_cast<int>(k)) - centre) <= width + 1e-12) n += count[k];
    return n;
  };
  total = 0;
  for (std::size_t k = 0; k < bins; ++k) total += count[k];
  const std::size_t inside = within(0.0, o.tolerance);
  before = after = within(0.0, o.band);
  if (total < std::max<std::size_t>(o.min_returns, 1)) return 0.0;
  // The densest band: centres on the bins, the band inside the evidence's reach.
  int best = half;
  std::size_t best_n = within(0.0, o.band);
  for (int k = 0; k < static_cast<int>(bins); ++k) {
    const double c = offset(k);
    if (std::abs(c) + o.band > o.reach + 1e-12) continue;
    const std::size_t n = within(c, o.band);
    if (n > best_n || (n == best_n && std::abs(k - half) < std::abs(best - half))) best = k, best_n = n;
  }
  // Its returns' mean offset.
  std::int64_t s = 0;
  std::size_t n = 0;
  for (std::size_t k = 0; k < bins; ++k)
    if (std::abs(offset(static_cast<int>(k)) - offset(best)) <= o.band + 1e-12) s += sum[k], n += count[k];
  if (n == 0) return 0.0;
  // To 0.1 mm: finer is no information, and a log read with float32 angles (a ROS bag) moves the
  // returns' mean in the 8th digit.
  const double shift = 1e-4 * std::round(kUnit * static_cast<double>(s) / static_cast<double>(n) / 1e-4);
  // Moved when its band then holds clearly more of the returns (a wall a few centimetres off its
  // face keeps them all within a coarse tolerance, yet a range model of 1-3 cm misses them), and
  // no fewer lie within the tolerance.
  const std::size_t banded = within(shift, o.band);
  const double gain = static_cast<double>(banded) - static_cast<double>(before);
  if (gain < o.min_gain * static_cast<double>(total) || within(shift, o.tolerance) < inside) return 0.0;
  after = banded;
  return shift;
}

// Where the lines through (a, b) and (c, d) cross; false when nearly parallel.
bool crossing(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d, Vec2& out) {
  const Vec2 r = b - a, s = d - c;
  const double den = r.x() * s.y() - r.y() * s.x();
  if (std::abs(den) < 1e-12 * r.norm() * s.norm()) return false;
  const Vec2 q = c - a;
  out = a + ((q.x() * s.y() - q.y() * s.x()) / den) * r;
  return true;
}

}  // namespace

ScanFitStats fitToScans(VectorizeResult& plan, const LaserLog& log, const grid::BeamOptions& beams,
                        const ScanFitOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  ScanFitStats stats;
  stats.band = o.band;
  if (!o.enabled || !(o.bin > 0) || !(o.reach > 0)) return stats;
  std::vector<MapSegment*> segs;
  for (VectorMap* m : {&plan.map, &plan.extras.clutter})
    for (MapSegment& s : m->segments)
      if (s.length() > 0) segs.push_back(&s);
  if (segs.empty()) return stats;
  const detail::SegmentIndex index(segs, o.reach);
  const std::size_t n = segs.size();
  const std::size_t bins = 2 * static_cast<std::size_t>(std::ceil(o.reach / o.bin - 1e-9)) + 1;
  const int half = static_cast<int>(bins / 2);
  // Each segment's unit direction, normal and length, once (the loop over the returns needs them).
  std::vector<Vec2> dir(n), normal(n);
  std::vector<double> length(n);
  for (std::size_t k = 0; k < n; ++k) {
    dir[k] = segs[k]->direction();
    normal[k] = Vec2(-dir[k].y(), dir[k].x());
    length[k] = segs[k]->length();
  }

  // Each return to its nearest segment within reach; a movable one's tally takes its offset.
  tbb::enumerable_thread_specific<Tally> tallies([&] {
    return Tally{std::vector<std::uint32_t>(n * bins, 0), std::vector<std::int64_t>(n * bins, 0)};
  });
  forEachScanBlock(log, [&](std::span<const LaserScan> block, std::size_t) {
    tbb::parallel_for(std::size_t{0}, block.size(), [&](std::size_t i) {
      Tally& t = tallies.local();
      grid::forEachBeam(
          block[i], beams,
          [&](const grid::Beam& beam) {
            if (!(beam.range < o.max_range)) return;
            const auto* cands = index.near(beam.to);
            if (!cands) return;
            double best = o.reach;
            std::uint32_t which = std::numeric_limits<std::uint32_t>::max();
            for (std::uint32_t k : *cands) {
              const double d = segs[k]->distanceTo(beam.to);
              if (d < best || (d == best && k < which)) best = d, which = k;
            }
            if (which == std::numeric_limits<std::uint32_t>::max() || segs[which]->material == Material::Glass) return;
            const Vec2 q = beam.to - segs[which]->a;
            const double along = q.dot(dir[which]);
            if (along < 0 || along > length[which]) return;  // beyond an end: not evidence of its line
            const double d = q.dot(normal[which]);
            const int k = std::clamp(static_cast<int>(std::lround(d / o.bin)) + half, 0, static_cast<int>(bins) - 1);
            t.count[which * bins + static_cast<std::size_t>(k)] += 1;
            t.sum[which * bins + static_cast<std::size_t>(k)] += std::llround(d / kUnit);
          },
          grid::BeamFilter::Hit);
    });
  });
  Tally all{std::vector<std::uint32_t>(n * bins, 0), std::vector<std::int64_t>(n * bins, 0)};
  for (const Tally& t : tallies)
    for (std::size_t k = 0; k < n * bins; ++k) all.count[k] += t.count[k], all.sum[k] += t.sum[k];

  // The shifts.
  std::vector<double> shift(n, 0.0);
  std::size_t before_all = 0, after_all = 0;
  double moved_sum = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    if (segs[k]->material == Material::Glass) continue;
    std::size_t total = 0, before = 0, after = 0;
    shift[k] = bestShift(&all.count[k * bins], &all.sum[k * bins], bins, o, total, before, after);
    stats.returns += total;
    before_all += before;
    after_all += after;
    if (total >= std::max<std::size_t>(o.min_returns, 1)) ++stats.segments;
    if (shift[k] != 0.0) ++stats.moved, moved_sum += std::abs(shift[k]);
  }
  if (stats.returns > 0) {
    stats.explained_before = static_cast<double>(before_all) / static_cast<double>(stats.returns);
    stats.explained_after = static_cast<double>(after_all) / static_cast<double>(stats.returns);
  }
  if (stats.moved > 0) stats.mean_shift = moved_sum / static_cast<double>(stats.moved);

  // Ends that met another segment's line (a corner, a T) before the move, and the doors' ends on
  // a moved line, then the move.
  struct Junction {
    std::size_t seg, other;
    bool end_b;
  };
  std::vector<Junction> junctions;
  const double min_sin = std::sin(o.junction_angle_deg * kPi / 180.0);
  {
    // Candidates: the ends inside a segment's box grown by the tolerance.
    std::vector<Vec2> ends(2 * n);
    std::vector<Eigen::AlignedBox2d> boxes(n);
    for (std::size_t k = 0; k < n; ++k) {
      ends[2 * k] = segs[k]->a;
      ends[2 * k + 1] = segs[k]->b;
      boxes[k].extend(segs[k]->a.cwiseMin(segs[k]->b) - Vec2::Constant(o.junction));
      boxes[k].extend(segs[k]->a.cwiseMax(segs[k]->b) + Vec2::Constant(o.junction));
    }
    const auto pairs = detail::pointsInBoxes(ends, boxes);  // sorted by end, then by segment
    for (std::size_t first = 0; first < pairs.size();) {
      const std::size_t e = pairs[first].first, i = e / 2;
      std::size_t last = first;
      while (last < pairs.size() && pairs[last].first == e) ++last;
      double best = o.junction;
      std::size_t which = n;
      for (std::size_t m = first; m < last; ++m) {
        const std::size_t j = pairs[m].second;
        if (j == i || (shift[i] == 0.0 && shift[j] == 0.0)) continue;
        if (std::abs(dir[i].dot(normal[j])) < min_sin) continue;
        const Vec2 q = ends[e] - segs[j]->a;
        const double off = std::abs(q.dot(normal[j])), along = q.dot(dir[j]);
        if (off <= best && along >= -o.junction && along <= length[j] + o.junction) best = off, which = j;
      }
      if (which < n) junctions.push_back({i, which, e % 2 == 1});
      first = last;
    }
  }
  std::vector<Vec2> door_move;
  for (const DoorOpening& d : plan.extras.doors)
    for (const Vec2& p : {d.a, d.b}) {
      Vec2 move = Vec2::Zero();
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t k = 0; k < n; ++k) {
        if (shift[k] == 0.0 || std::abs((p - segs[k]->a).dot(normal[k])) > o.junction) continue;
        const double d_end = segs[k]->distanceTo(p);
        if (d_end < best) best = d_end, move = shift[k] * normal[k];
      }
      door_move.push_back(move);
    }
  for (std::size_t k = 0; k < n; ++k) {
    segs[k]->a += shift[k] * normal[k];
    segs[k]->b += shift[k] * normal[k];
  }
  for (const Junction& j : junctions) {
    MapSegment& s = *segs[j.seg];
    const MapSegment& other = *segs[j.other];
    Vec2 x;
    Vec2& e = j.end_b ? s.b : s.a;
    if (!crossing(s.a, s.b, other.a, other.b, x) || (x - e).norm() > 2.0 * o.reach) continue;
    const Vec2 rest = j.end_b ? s.a : s.b;  // the segment keeps its direction and some length
    if ((j.end_b ? x - rest : rest - x).dot(dir[j.seg]) <= 0.0) continue;
    e = x;
    ++stats.junctions;
  }
  std::size_t m = 0;
  for (DoorOpening& d : plan.extras.doors) {
    d.a += door_move[m++];
    d.b += door_move[m++];
  }
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return stats;
}

}  // namespace glassmap::vector
