#include "glassmap/geometry/ray_caster.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "glassmap/core/error.hpp"

namespace glassmap {

namespace {

constexpr std::int32_t kNone = std::numeric_limits<std::int32_t>::max();

// Relative slack on the segment parameter: a ray counts as hitting a + v*d for v in
// [-kSlack, 1 + kSlack], so rounding cannot let a ray slip between two segments that share an
// endpoint (a wall corner). It lengthens each segment by 1e-12 of its length at either end.
constexpr double kSlack = 1e-12;

// Ray o + t*u against segment a + v*d, v in [0, 1]. Solving t*u - v*d = a - o = w with 2D cross
// products: t = (w x d) / (u x d), v = (w x u) / (u x d). Sets t and q, and the ray hits when
// t > 0 and q = v (1 - v) >= -kSlack (v within [0, 1] up to the slack). Parallel and collinear
// rays (u x d == 0) never hit: t and v are then infinite or NaN and fail both tests.
// Both the grid walk and the brute force call this: they agree bit for bit.
template <class S>
inline void hitParams(double ox, double oy, double ux, double uy, const S& s, double& t, double& q) {
  const double wx = s.ax - ox, wy = s.ay - oy;
  const double inv = 1.0 / (ux * s.dy - uy * s.dx);
  t = (wx * s.dy - wy * s.dx) * inv;
  const double v = (wx * uy - wy * ux) * inv;
  q = v * (1.0 - v);
}

template <class S>
inline bool hitTest(double ox, double oy, double ux, double uy, const S& s, double& t) {
  double q;
  hitParams(ox, oy, ux, uy, s, t, q);
  return (q >= -kSlack) & (t > 0.0);
}

// Initial "best" range: hits are accepted while t < limit, i.e. t <= max_range.
inline double acceptLimit(double max_range) {
  const double m = std::min(max_range, std::numeric_limits<double>::max());
  // The next double up; for positive finite m that is the next bit pattern (no libm call).
  if (m > 0.0) return std::bit_cast<double>(std::bit_cast<std::uint64_t>(m) + 1);
  return std::nextafter(m, std::numeric_limits<double>::infinity());
}

// Does the segment a + v*d touch the box [x0,x1] x [y0,y1]? The caller guarantees that the
// boxes of the two overlap; this checks the separating axis along the segment's normal.
bool segmentTouchesBox(double ax, double ay, double dx, double dy, double x0, double y0, double x1, double y1) {
  const double f00 = dx * (y0 - ay) - dy * (x0 - ax);
  const double f10 = dx * (y0 - ay) - dy * (x1 - ax);
  const double f01 = dx * (y1 - ay) - dy * (x0 - ax);
  const double f11 = dx * (y1 - ay) - dy * (x1 - ax);
  const bool all_pos = f00 > 0 && f10 > 0 && f01 > 0 && f11 > 0;
  const bool all_neg = f00 < 0 && f10 < 0 && f01 < 0 && f11 < 0;
  return !(all_pos || all_neg);
}

}  // namespace

RayCaster::RayCaster(const VectorMap& map, RayCasterOptions options) : map_(map) {
  const std::size_t n = map_.segments.size();
  segs_.resize(n);
  materials_.resize(n);
  Eigen::AlignedBox2d box;
  double total_length = 0.0;
  std::size_t valid = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const MapSegment& m = map_.segments[i];
    segs_[i] = {m.a.x(), m.a.y(), m.b.x() - m.a.x(), m.b.y() - m.a.y()};
    materials_[i] = m.material;
    if (segs_[i].dx == 0.0 && segs_[i].dy == 0.0) continue;
    // A segment with a NaN or infinite coordinate cannot be hit (the brute force's tests fail on
    // it too) and would poison the grid's box: it stays out of the cells, as zero-length ones do.
    if (!m.a.allFinite() || !m.b.allFinite()) {
      segs_[i] = {0.0, 0.0, 0.0, 0.0};
      continue;
    }
    box.extend(m.a);
    box.extend(m.b);
    total_length += m.length();
    ++valid;
  }
  if (valid == 0) {  // nothing can be hit: an empty grid makes every cast miss
    cell_start_.assign(1, 0);
    return;
  }
  const double width = box.max().x() - box.min().x();
  const double height = box.max().y() - box.min().y();
  const double extent = std::max({width, height, 1e-6});
  if (!std::isfinite(extent))  // coordinates near +-1.8e308: the grid's size overflows
    throw Error("the map's extent overflows a double: a coordinate is beyond +-1e307 m", {}, 0, "segments");

  // Cell size: the mean segment length, which keeps each cell's list short while a ray
  // crosses few cells; bounded so the grid has at most ~4M cells and at least one.
  double cell = options.cell_size;
  if (!(cell > 0.0)) cell = total_length / static_cast<double>(valid);
  cell = std::clamp(cell, extent / 2048.0, extent);
  cell_ = cell;
  inv_cell_ = 1.0 / cell;

  // Pad the box so segments on its border lie strictly inside; eps widens every cell when
  // segments are listed, so a hit on (or within rounding of) a cell border is in both cells.
  const double eps = 1e-6 * cell;
  const double pad = 2 * eps;
  origin_ = box.min() - Vec2::Constant(pad);
  nx_ = std::max(1, static_cast<int>(std::ceil((width + 2 * pad) * inv_cell_)));
  ny_ = std::max(1, static_cast<int>(std::ceil((height + 2 * pad) * inv_cell_)));
  top_ = origin_ + Vec2(nx_ * cell, ny_ * cell);

  std::vector<std::vector<std::uint32_t>> lists(static_cast<std::size_t>(nx_) * ny_);
  auto index = [&](double v, double o, int count) {
    return std::clamp(static_cast<int>(std::floor((v - o) * inv_cell_)), 0, count - 1);
  };
  for (std::size_t i = 0; i < n; ++i) {
    const Seg& s = segs_[i];
    if (s.dx == 0.0 && s.dy == 0.0) continue;
    const double xa = std::min(s.ax, s.ax + s.dx), xb = std::max(s.ax, s.ax + s.dx);
    const double ya = std::min(s.ay, s.ay + s.dy), yb = std::max(s.ay, s.ay + s.dy);
    const int ix0 = index(xa - eps, origin_.x(), nx_), ix1 = index(xb + eps, origin_.x(), nx_);
    const int iy0 = index(ya - eps, origin_.y(), ny_), iy1 = index(yb + eps, origin_.y(), ny_);
    for (int iy = iy0; iy <= iy1; ++iy) {
      // Only the columns the segment can reach within this row's slab (plus one on each side
      // against rounding; segmentTouchesBox decides): a long diagonal segment costs O(nx + ny)
      // box tests, not O(nx * ny) (a 1e9 m segment would otherwise test all ~4M cells).
      int jx0 = ix0, jx1 = ix1;
      if (s.dy != 0.0) {
        const double y0 = origin_.y() + iy * cell - eps, y1 = origin_.y() + (iy + 1) * cell + eps;
        double t0 = (y0 - s.ay) / s.dy, t1 = (y1 - s.ay) / s.dy;
        if (t0 > t1) std::swap(t0, t1);
        t0 = std::clamp(t0, 0.0, 1.0);
        t1 = std::clamp(t1, 0.0, 1.0);
        const double xs0 = s.ax + t0 * s.dx, xs1 = s.ax + t1 * s.dx;
        jx0 = std::max(ix0, index(std::min(xs0, xs1) - eps, origin_.x(), nx_) - 1);
        jx1 = std::min(ix1, index(std::max(xs0, xs1) + eps, origin_.x(), nx_) + 1);
      }
      for (int ix = jx0; ix <= jx1; ++ix) {
        const double x0 = origin_.x() + ix * cell - eps, x1 = origin_.x() + (ix + 1) * cell + eps;
        const double y0 = origin_.y() + iy * cell - eps, y1 = origin_.y() + (iy + 1) * cell + eps;
        if (segmentTouchesBox(s.ax, s.ay, s.dx, s.dy, x0, y0, x1, y1)) {
          lists[static_cast<std::size_t>(iy) * nx_ + ix].push_back(static_cast<std::uint32_t>(i));
        }
      }
    }
  }
  // CSR in pairs: each cell's list (ascending id) padded to an even length with a zero-length
  // dummy that never hits, so the walk tests two segments per SSE2 instruction.
  cell_start_.resize(lists.size() + 1);
  std::size_t pairs = 0;
  for (std::size_t c = 0; c < lists.size(); ++c) {
    cell_start_[c] = static_cast<std::uint32_t>(pairs);
    pairs += (lists[c].size() + 1) / 2;
  }
  cell_start_[lists.size()] = static_cast<std::uint32_t>(pairs);
  // The batch kernels' layout: unpadded lists, cells with a border ring (span -1).
  spans_.assign(static_cast<std::size_t>(nx_ + 2) * static_cast<std::size_t>(ny_ + 2), -1);
  for (int iy = 0; iy < ny_; ++iy) {
    for (int ix = 0; ix < nx_; ++ix) {
      const auto& list = lists[static_cast<std::size_t>(iy) * nx_ + ix];
      const auto begin = static_cast<std::int64_t>(flat_.size());
      for (const std::uint32_t id : list) {
        const Seg& sg = segs_[id];
        flat_.push_back({sg.ax, sg.ay, sg.dx, sg.dy});
        flat_ids_.push_back(static_cast<std::int32_t>(id));
      }
      const auto end = static_cast<std::int64_t>(flat_.size());
      spans_[static_cast<std::size_t>(iy + 1) * static_cast<std::size_t>(nx_ + 2) + static_cast<std::size_t>(ix + 1)] =
          begin | (end << 32);
    }
  }
  if (flat_.size() >= (std::size_t{1} << 31))
    throw Error("the ray caster's cell lists exceed 2^31 entries: the map is too large for one index", {}, 0,
                "segments");
  items_.resize(pairs);
  cell_items_.resize(2 * pairs);
  std::size_t k = 0;
  for (const auto& list : lists) {
    for (std::size_t j = 0; j < list.size(); j += 2, ++k) {
      SegPair& pair = items_[k];
      for (std::size_t lane = 0; lane < 2; ++lane) {
        const bool real = j + lane < list.size();
        const std::uint32_t id = real ? list[j + lane] : list[j];
        const Seg& sg = segs_[id];
        pair.ax[lane] = real ? sg.ax : 0.0;
        pair.ay[lane] = real ? sg.ay : 0.0;
        pair.dx[lane] = real ? sg.dx : 0.0;
        pair.dy[lane] = real ? sg.dy : 0.0;
        cell_items_[2 * k + lane] = id;
      }
    }
  }
}

template <bool kSkip>
RayCaster::Best RayCaster::walk(double ox, double oy, double ux, double uy, double max_range, std::int32_t skip) const {
  const double limit = acceptLimit(max_range);
  if (nx_ == 0 || !(max_range > 0)) return {limit, kNone};
  if (!std::isfinite(ox + oy + ux + uy)) return {limit, kNone};  // NaN/inf input: no hit
  const double inv_ux = 1.0 / ux, inv_uy = 1.0 / uy;             // +-inf for axis-parallel rays

  // Entry point: the origin when it is inside the grid (the common case), else the point where
  // the ray enters the grid box (slab method). Where the ray leaves the box the cell index
  // leaves the grid and the walk ends.
  double px = ox, py = oy;
  if (!(ox >= origin_.x() && ox <= top_.x() && oy >= origin_.y() && oy <= top_.y())) {
    double t0 = 0.0, t1 = max_range;
    if (ux != 0.0) {
      const double ta = (origin_.x() - ox) * inv_ux, tb = (top_.x() - ox) * inv_ux;
      t0 = std::max(t0, std::min(ta, tb));
      t1 = std::min(t1, std::max(ta, tb));
    } else if (!(ox >= origin_.x() && ox <= top_.x())) {
      return {limit, kNone};
    }
    if (uy != 0.0) {
      const double ta = (origin_.y() - oy) * inv_uy, tb = (top_.y() - oy) * inv_uy;
      t0 = std::max(t0, std::min(ta, tb));
      t1 = std::min(t1, std::max(ta, tb));
    } else if (!(oy >= origin_.y() && oy <= top_.y())) {
      return {limit, kNone};
    }
    if (!(t0 <= t1)) return {limit, kNone};
    px = ox + t0 * ux;
    py = oy + t0 * uy;
  }

  // Amanatides-Woo DDA from the entry cell.
  int ix = std::clamp(static_cast<int>((px - origin_.x()) * inv_cell_), 0, nx_ - 1);
  int iy = std::clamp(static_cast<int>((py - origin_.y()) * inv_cell_), 0, ny_ - 1);
  const double inf = std::numeric_limits<double>::infinity();
  int step_x = 1, step_y = 1;
  double t_max_x = inf, t_max_y = inf, t_delta_x = inf, t_delta_y = inf;
  if (ux > 0.0) {
    t_max_x = (origin_.x() + (ix + 1) * cell_ - ox) * inv_ux;
    t_delta_x = cell_ * inv_ux;
  } else if (ux < 0.0) {
    step_x = -1;
    t_max_x = (origin_.x() + ix * cell_ - ox) * inv_ux;
    t_delta_x = -cell_ * inv_ux;
  }
  if (uy > 0.0) {
    t_max_y = (origin_.y() + (iy + 1) * cell_ - oy) * inv_uy;
    t_delta_y = cell_ * inv_uy;
  } else if (uy < 0.0) {
    step_y = -1;
    t_max_y = (origin_.y() + iy * cell_ - oy) * inv_uy;
    t_delta_y = -cell_ * inv_uy;
  }
  const std::ptrdiff_t stride_y = static_cast<std::ptrdiff_t>(step_y) * nx_;
  std::ptrdiff_t c = static_cast<std::ptrdiff_t>(iy) * nx_ + ix;
  const std::uint32_t* start = cell_start_.data();
  const SegPair* items = items_.data();
#if defined(__SSE2__)
  const __m128d vox = _mm_set1_pd(ox), voy = _mm_set1_pd(oy);
  const __m128d vux = _mm_set1_pd(ux), vuy = _mm_set1_pd(uy);
  const __m128d one = _mm_set1_pd(1.0), zero = _mm_setzero_pd(), slack = _mm_set1_pd(-kSlack);
  const __m128d inf2 = _mm_set1_pd(std::numeric_limits<double>::infinity());
#endif
  const std::uint32_t* ids = cell_items_.data();
  const auto skip_id = static_cast<std::uint32_t>(skip);  // -1 matches no real id
  for (;;) {
    // Best hit within this cell's list. Lists are in ascending segment id (lane 0 before
    // lane 1), so keeping the first of equal ranges keeps the lowest id, as the brute force does.
    double best_t = limit;
    std::uint32_t best_k = 0;  // lane index into ids
    const std::uint32_t end = start[c + 1];
    for (std::uint32_t k = start[c]; k < end; ++k) {
      const SegPair& p = items[k];
#if defined(__SSE2__)
      // hitParams() on both lanes; the same IEEE operations, so the same bits.
      const __m128d wx = _mm_sub_pd(_mm_load_pd(p.ax), vox);
      const __m128d wy = _mm_sub_pd(_mm_load_pd(p.ay), voy);
      const __m128d dx = _mm_load_pd(p.dx), dy = _mm_load_pd(p.dy);
      const __m128d inv = _mm_div_pd(one, _mm_sub_pd(_mm_mul_pd(vux, dy), _mm_mul_pd(vuy, dx)));
      const __m128d t = _mm_mul_pd(_mm_sub_pd(_mm_mul_pd(wx, dy), _mm_mul_pd(wy, dx)), inv);
      const __m128d v = _mm_mul_pd(_mm_sub_pd(_mm_mul_pd(wx, vuy), _mm_mul_pd(wy, vux)), inv);
      const __m128d q = _mm_mul_pd(v, _mm_sub_pd(one, v));
      __m128d m = _mm_and_pd(_mm_cmpge_pd(q, slack), _mm_cmpgt_pd(t, zero));
      if constexpr (kSkip) {
        m = _mm_and_pd(
            m, _mm_castsi128_pd(_mm_set_epi64x(ids[2 * k + 1] == skip_id ? 0 : -1, ids[2 * k] == skip_id ? 0 : -1)));
      }
      const __m128d tm = _mm_or_pd(_mm_and_pd(m, t), _mm_andnot_pd(m, inf2));
      const double lo = _mm_cvtsd_f64(tm), hi = _mm_cvtsd_f64(_mm_unpackhi_pd(tm, tm));
#else
      double lo = std::numeric_limits<double>::infinity(), hi = lo;
      for (int lane = 0; lane < 2; ++lane) {
        const Seg sg{p.ax[lane], p.ay[lane], p.dx[lane], p.dy[lane]};
        double t;
        const bool ok = hitTest(ox, oy, ux, uy, sg, t) && (!kSkip || ids[2 * k + lane] != skip_id);
        (lane == 0 ? lo : hi) = ok ? t : std::numeric_limits<double>::infinity();
      }
#endif
      const std::uint32_t lane = hi < lo ? 1 : 0;
      const double t_min = lane ? hi : lo;
      const bool better = t_min < best_t;
      best_t = better ? t_min : best_t;
      best_k = better ? 2 * k + lane : best_k;
    }
    // A hit within this cell's part of the ray is the first one: every segment that could be
    // hit earlier lies in a cell already visited. A hit beyond it is forgotten: its point lies
    // in a later cell, whose list holds the segment too. The ray also ends here when it reaches
    // max_range (best_t == limit <= t_exit).
    const double t_exit = std::min(t_max_x, t_max_y);
    if (best_t <= t_exit) {
      return {best_t, best_t < limit ? static_cast<std::int32_t>(ids[best_k]) : kNone};
    }
    if (t_max_x < t_max_y) {
      ix += step_x;
      if (static_cast<unsigned>(ix) >= static_cast<unsigned>(nx_)) break;
      c += step_x;
      t_max_x += t_delta_x;
    } else {
      iy += step_y;
      if (static_cast<unsigned>(iy) >= static_cast<unsigned>(ny_)) break;
      c += stride_y;
      t_max_y += t_delta_y;
    }
  }
  return {limit, kNone};
}

RayCaster::Best RayCaster::walk(double ox, double oy, double ux, double uy, double max_range, std::int32_t skip) const {
  return skip >= 0 ? walk<true>(ox, oy, ux, uy, max_range, skip) : walk<false>(ox, oy, ux, uy, max_range, skip);
}

RayCaster::Best RayCaster::brute(double ox, double oy, double ux, double uy, double max_range,
                                 std::int32_t skip) const {
  Best best{acceptLimit(max_range), kNone};
  if (!(max_range > 0)) return best;
  for (std::size_t i = 0; i < segs_.size(); ++i) {
    const auto sid = static_cast<std::int32_t>(i);
    if (sid == skip) continue;
    double t;
    if (hitTest(ox, oy, ux, uy, segs_[i], t) && t < best.t) best = {t, sid};  // lowest id wins ties
  }
  return best;
}

RayHit RayCaster::finish(const Best& best, double ux, double uy) const {
  RayHit hit;
  if (best.id == kNone) return hit;
  const Seg& s = segs_[static_cast<std::size_t>(best.id)];
  hit.range = best.t;
  hit.segment = best.id;
  hit.material = materials_[static_cast<std::size_t>(best.id)];
  // Angle to the normal: cos = |u x d| / |d|, sin = |u . d| / |d|.
  // atan of the ratio is several times faster than atan2 here; cross == 0 gives atan(inf) = pi/2.
  hit.incidence = std::atan(std::abs(ux * s.dx + uy * s.dy) / std::abs(ux * s.dy - uy * s.dx));
  return hit;
}

double RayCaster::incidence(std::int32_t segment, const Vec2& dir) const {
  const Seg& s = segs_[static_cast<std::size_t>(segment)];
  const double ux = dir.x(), uy = dir.y();
  return std::atan(std::abs(ux * s.dx + uy * s.dy) / std::abs(ux * s.dy - uy * s.dx));
}

RayHit RayCaster::castSurface(const Vec2& origin, const Vec2& dir, double max_range, std::int32_t skip) const {
  const Best best = walk(origin.x(), origin.y(), dir.x(), dir.y(), max_range, skip);
  RayHit hit;
  if (best.id == kNone) return hit;
  hit.range = best.t;
  hit.segment = best.id;
  hit.material = materials_[static_cast<std::size_t>(best.id)];
  return hit;
}

RayHit RayCaster::cast(const Vec2& origin, double angle, double max_range, std::int32_t skip) const {
  return cast(origin, Vec2(std::cos(angle), std::sin(angle)), max_range, skip);
}

RayHit RayCaster::cast(const Vec2& origin, const Vec2& dir, double max_range, std::int32_t skip) const {
  return finish(walk(origin.x(), origin.y(), dir.x(), dir.y(), max_range, skip), dir.x(), dir.y());
}

double RayCaster::castRange(const Vec2& origin, const Vec2& dir, double max_range, std::int32_t skip) const {
  const Best best = walk(origin.x(), origin.y(), dir.x(), dir.y(), max_range, skip);
  return best.id == kNone ? std::numeric_limits<double>::infinity() : best.t;
}

void RayCaster::castScan(const Vec2& origin, double start_angle, double step, int count, double max_range,
                         double* ranges) const {
  double ux = std::cos(start_angle), uy = std::sin(start_angle);
  const double cs = std::cos(step), sn = std::sin(step);
  for (int k = 0; k < count; ++k) {
    const Best best = walk(origin.x(), origin.y(), ux, uy, max_range, -1);
    ranges[k] = best.id == kNone ? max_range : best.t;
    const double nux = ux * cs - uy * sn;
    uy = ux * sn + uy * cs;
    ux = nux;
  }
}

RayHit RayCaster::castBruteForce(const Vec2& origin, double angle, double max_range, std::int32_t skip) const {
  return castBruteForce(origin, Vec2(std::cos(angle), std::sin(angle)), max_range, skip);
}

RayHit RayCaster::castBruteForce(const Vec2& origin, const Vec2& dir, double max_range, std::int32_t skip) const {
  return finish(brute(origin.x(), origin.y(), dir.x(), dir.y(), max_range, skip), dir.x(), dir.y());
}

}  // namespace glassmap
