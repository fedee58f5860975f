// RayCaster::castGroups: coherent groups of rays (one beam from many nearby particles) share one
// sweep of the grid instead of walking it ray by ray.
//
// A group's rays start within a disc of radius r around their mean origin c and point within a
// cone of half-angle a around their mean direction u. A point of ray i at parameter t lies at
// axial distance (p - c) . u <= r + t and lateral distance |(p - c) . n| <= r + (x + r) tan a from
// the axis, x being its axial distance. The sweep visits the grid cells of that wedge slab by
// slab (one cell thick) in increasing axial distance, each cell once, and tests every segment
// listed there against the group's undecided rays with the walk's hit test. After the slab that
// ends at x, every segment a ray could hit at t <= x - r has been tested (its hit point lies in a
// visited cell, whose list holds it), so a ray whose best hit (or max range) is within x - r is
// decided: the nearest hit over a superset of the segments it can meet, ties to the lower id,
// which is what the walk and the brute force return.
#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <vector>

#include "glassmap/geometry/ray_caster.hpp"
#include "ray_batch.hpp"

namespace glassmap {
namespace {

constexpr double kSlack = 1e-12;                 // as ray_caster.cpp: segments lengthened by 1e-12
constexpr double kMinCos = 0.93969262078590838;  // cos 20 deg: wider groups walk ray by ray
constexpr double kMargin = 1e-7;                 // [m] widens the swept wedge against rounding

// One group's rays, structure of arrays (a decided ray's best is -inf: it takes no more hits).
struct Group {
  std::vector<double> ox, oy, ux, uy, best, max_range;
  std::vector<std::int64_t> skip, id;
  std::vector<std::uint32_t> pending;  // undecided rays [0, live)
  std::vector<std::uint32_t> visited;  // per padded cell: the stamp of the last group that swept it
  std::vector<std::uint32_t> tested;   // per segment: the stamp of the last group tested against it
  std::uint32_t stamp = 0;
  void resize(std::size_t n) {
    for (auto* v : {&ox, &oy, &ux, &uy, &best, &max_range}) v->resize(n);
    skip.resize(n);
    id.resize(n);
  }
  // Slot k holds no ray: its tests never improve it (best = -inf).
  void clear(std::size_t k) {
    ox[k] = oy[k] = uy[k] = 0.0;
    ux[k] = max_range[k] = 1.0;
    best[k] = -std::numeric_limits<double>::infinity();
    skip[k] = id[k] = -1;
  }
};

// Segment a + v d (id seg_id) against rays [0, n): the walk's hitParams, then the nearest hit, ties
// to the lower segment id (the scalar fallback of the SIMD kernels' testSegmentLanes).
double testSegmentScalar(double* __restrict best, std::int64_t* __restrict id, const double* __restrict ox,
                         const double* __restrict oy, const double* __restrict ux, const double* __restrict uy,
                         const std::int64_t* __restrict skip, std::size_t n, double ax, double ay, double dx, double dy,
                         std::int64_t seg_id) {
  double low = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < n; ++k) {
    const double wx = ax - ox[k], wy = ay - oy[k];
    const double inv = 1.0 / (ux[k] * dy - uy[k] * dx);
    const double t = (wx * dy - wy * dx) * inv;
    const double v = (wx * uy[k] - wy * ux[k]) * inv;
    const double q = v * (1.0 - v);
    const bool hit = (q >= -kSlack) & (t > 0.0) & (skip[k] != seg_id);
    const bool better = hit & ((t < best[k]) | ((t == best[k]) & (seg_id < id[k])));
    best[k] = better ? t : best[k];
    low = better && t < low ? t : low;
    id[k] = better ? seg_id : id[k];
  }
  return low;
}

// The scalar set-up of a group (ray_batch.hpp: GroupSetupFn, GroupConeFn; padded == n here).
void groupSetupScalar(const double* ox, const double* oy, const double* ux, const double* uy, const double* max_range,
                      double* best, std::size_t n, std::size_t padded, detail::GroupStats& st) {
  for (std::size_t k = 0; k < padded; ++k) {
    const double x = ox[k], y = oy[k], u = ux[k], v = uy[k], m = max_range[k];
    if (k >= n) {
      best[k] = -std::numeric_limits<double>::infinity();
      continue;
    }
    const double norm2 = u * u + v * v, sum = x + y + u + v;
    st.ok &= ((sum - sum) == 0.0) & (m > 0.0) & (norm2 > 1.0 - 1e-9) & (norm2 < 1.0 + 1e-9) & (x >= st.x0) &
             (x <= st.x1) & (y >= st.y0) & (y <= st.y1);
    st.sx += x;
    st.sy += y;
    st.su += u;
    st.sv += v;
    st.max_range = std::max(st.max_range, std::min(m, 1e300));
    st.min_range = std::min(st.min_range, m);
    const double limit = std::min(m, std::numeric_limits<double>::max());
    best[k] = std::bit_cast<double>(std::bit_cast<std::uint64_t>(limit) + 1);  // acceptLimit for m > 0
  }
}
void groupConeScalar(const double* ox, const double* oy, const double* ux, const double* uy, std::size_t n, std::size_t,
                     double cx, double cy, double ax, double ay, double& cos_a, double& radius2) {
  cos_a = 1.0;
  radius2 = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    cos_a = std::min(cos_a, ux[k] * ax + uy[k] * ay);
    const double ex = ox[k] - cx, ey = oy[k] - cy;
    radius2 = std::max(radius2, ex * ex + ey * ey);
  }
}

}  // namespace

void RayCaster::castGroups(const RayBatch& rays, const std::size_t* group_end, std::size_t groups, double* range,
                           std::int32_t* segment) const {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  thread_local Group g;
  if (g.visited.size() != spans_.size() || g.tested.size() != segs_.size()) {
    g.visited.assign(spans_.size(), 0);
    g.tested.assign(segs_.size(), 0);
    g.stamp = 0;
  }
  const std::size_t pw = static_cast<std::size_t>(nx_) + 2;
  // The inner loop on the CPU's widest lanes; groups are padded to a multiple of them.
  detail::TestSegmentFn test = testSegmentScalar;
  detail::GroupSetupFn setup = groupSetupScalar;
  detail::GroupConeFn cone = groupConeScalar;
  std::size_t lanes = 1;
#if defined(GLASSMAP_RAY_SIMD)
  if (bestIsa() == RayIsa::Avx512) {
    test = detail::testSegmentAvx512;
    setup = detail::groupSetupAvx512;
    cone = detail::groupConeAvx512;
    lanes = 8;
  } else if (bestIsa() == RayIsa::Avx2) {
    test = detail::testSegmentAvx2;
    setup = detail::groupSetupAvx2;
    cone = detail::groupConeAvx2;
    lanes = 4;
  }
#endif
  std::size_t begin = 0;
  for (std::size_t gi = 0; gi < groups; ++gi) {
    const std::size_t end = group_end[gi], n = end - begin;
    const std::size_t first = begin;
    begin = end;
    if (n == 0) continue;
    auto walkEach = [&] {  // not a coherent group: one ray at a time, SIMD lanes
      RayBatch sub = rays;
      sub.ox += first;
      sub.oy += first;
      sub.ux += first;
      sub.uy += first;
      if (sub.max_range) sub.max_range += first;
      if (sub.skip) sub.skip += first;
      sub.size = n;
      castBatch(sub, range + first, segment ? segment + first : nullptr);
    };
    if (nx_ == 0 || n < 4) {
      walkEach();
      continue;
    }
    // The group's rays into the slots (copies and fills), then its disc and cone on the CPU's
    // lanes (their sums and extremes in another order than one by one: the disc and cone only
    // bound the sweep, and any rounding of them that still covers the rays gives the same hits);
    // anything unusual walks ray by ray.
    const std::size_t padded = (n + lanes - 1) / lanes * lanes;
    g.resize(padded);
    for (std::size_t k = n; k < padded; ++k) g.clear(k);
    std::copy_n(rays.ox + first, n, g.ox.begin());
    std::copy_n(rays.oy + first, n, g.oy.begin());
    std::copy_n(rays.ux + first, n, g.ux.begin());
    std::copy_n(rays.uy + first, n, g.uy.begin());
    if (rays.max_range)
      std::copy_n(rays.max_range + first, n, g.max_range.begin());
    else
      std::fill_n(g.max_range.begin(), n, rays.range);
    if (rays.skip)
      std::copy_n(rays.skip + first, n, g.skip.begin());  // int32 -> int64
    else
      std::fill_n(g.skip.begin(), n, std::int64_t{-1});
    std::fill_n(g.id.begin(), n, std::int64_t{-1});
    detail::GroupStats st;
    st.x0 = origin_.x();
    st.y0 = origin_.y();
    st.x1 = top_.x();
    st.y1 = top_.y();
    setup(g.ox.data(), g.oy.data(), g.ux.data(), g.uy.data(), g.max_range.data(), g.best.data(), n, padded, st);
    const bool ok = st.ok;
    const double sx = st.sx, sy = st.sy, su = st.su, sv = st.sv, max_range = st.max_range;
    const double dir_norm = std::hypot(su, sv);
    if (!ok || !(dir_norm > 0.5 * static_cast<double>(n))) {
      walkEach();
      continue;
    }
    const double cx = sx / static_cast<double>(n), cy = sy / static_cast<double>(n);
    const double ux = su / dir_norm, uy = sv / dir_norm, nxv = -uy, nyv = ux;
    double cos_a = 1.0, radius2 = 0.0;
    cone(g.ox.data(), g.oy.data(), g.ux.data(), g.uy.data(), n, padded, cx, cy, ux, uy, cos_a, radius2);
    double radius = std::sqrt(radius2) * (1.0 + 1e-12);
    if (!(cos_a >= kMinCos)) {
      walkEach();
      continue;
    }
    const double tan_a = std::sqrt(std::max(0.0, 1.0 - cos_a * cos_a)) / cos_a + 1e-9;
    radius += kMargin;
    // The sweep ends where every ray's max range is passed, or beyond the grid's far corner.
    double grid_end = -kInf;
    for (const double gx : {origin_.x(), top_.x()})
      for (const double gy : {origin_.y(), top_.y()}) grid_end = std::max(grid_end, (gx - cx) * ux + (gy - cy) * uy);
    const double sweep_end = std::min(max_range + radius, grid_end + kMargin);
    if (++g.stamp == 0) {
      std::fill(g.visited.begin(), g.visited.end(), 0);
      std::fill(g.tested.begin(), g.tested.end(), 0);
      g.stamp = 1;
    }
    std::size_t live = n;
    g.pending.resize(n);
    for (std::size_t k = 0; k < n; ++k) g.pending[k] = static_cast<std::uint32_t>(k);
    // The nearest point at which an undecided ray can be decided: min of best and max range over
    // them (the tests report the hits they write), so the list is scanned only when some ray is.
    double next = st.min_range;
    auto decide = [&](std::size_t k) {  // writes ray k's result; its slot then takes no more hits
      const std::size_t i = first + k;
      const bool hit = g.id[k] >= 0;
      range[i] = hit ? g.best[k] : kInf;
      if (segment) segment[i] = hit ? static_cast<std::int32_t>(g.id[k]) : -1;
      g.best[k] = -kInf;  // no hit is better: the slot takes no more
      --live;
    };
    for (double a0 = -radius; live > 0 && a0 < sweep_end;) {
      const double a1 = a0 + cell_;
      const double w = radius + (a1 + radius) * tan_a + kMargin;
      double xmin = kInf, xmax = -kInf, ymin = kInf, ymax = -kInf;
      for (const double a : {a0 - kMargin, a1 + kMargin})
        for (const double l : {-w, w}) {
          const double px = cx + a * ux + l * nxv, py = cy + a * uy + l * nyv;
          xmin = std::min(xmin, px);
          xmax = std::max(xmax, px);
          ymin = std::min(ymin, py);
          ymax = std::max(ymax, py);
        }
      const double fx0 = std::floor((xmin - origin_.x()) * inv_cell_),
                   fx1 = std::floor((xmax - origin_.x()) * inv_cell_);
      const double fy0 = std::floor((ymin - origin_.y()) * inv_cell_),
                   fy1 = std::floor((ymax - origin_.y()) * inv_cell_);
      if (fx1 >= 0 && fy1 >= 0 && fx0 < nx_ && fy0 < ny_) {
        const int ix0 = static_cast<int>(std::max(fx0, 0.0)), ix1 = static_cast<int>(std::min(fx1, nx_ - 1.0));
        const int iy0 = static_cast<int>(std::max(fy0, 0.0)), iy1 = static_cast<int>(std::min(fy1, ny_ - 1.0));
        for (int iy = iy0; iy <= iy1; ++iy) {
          for (int ix = ix0; ix <= ix1; ++ix) {
            const std::size_t c = static_cast<std::size_t>(iy + 1) * pw + static_cast<std::size_t>(ix + 1);
            if (g.visited[c] == g.stamp) continue;
            g.visited[c] = g.stamp;
            const std::int64_t span = spans_[c];
            const auto e1 = static_cast<std::size_t>(span >> 32);
            for (auto e = static_cast<std::size_t>(span & 0xffffffff); e < e1; ++e) {
              // A segment listed in several cells of the wedge is tested once: every ray still
              // undecided then got its hit on it, wherever along the ray that lies.
              std::uint32_t& seen = g.tested[static_cast<std::size_t>(flat_ids_[e])];
              if (seen == g.stamp) continue;
              seen = g.stamp;
              const Seg4& s = flat_[e];
              // Every ray point lies in the wedge x >= -r, |l| <= r + (x + r) tan a (axial x,
              // lateral l): a segment whose two ends lie beyond one of those three lines (with
              // a margin for rounding) misses all the rays, untested.
              const double ex = s.ax - cx, ey = s.ay - cy, fx = ex + s.dx, fy = ey + s.dy;
              const double xa = ex * ux + ey * uy, xb = fx * ux + fy * uy;
              const double la = ex * nxv + ey * nyv, lb = fx * nxv + fy * nyv;
              const double wa = radius + (xa + radius) * tan_a + kMargin, wb = radius + (xb + radius) * tan_a + kMargin;
              if ((la > wa && lb > wb) || (-la > wa && -lb > wb) || (xa < -radius - kMargin && xb < -radius - kMargin))
                continue;
              next = std::min(next, test(g.best.data(), g.id.data(), g.ox.data(), g.oy.data(), g.ux.data(), g.uy.data(),
                                         g.skip.data(), padded, s.ax, s.ay, s.dx, s.dy, flat_ids_[e]));
            }
          }
        }
      }
      a0 = a1;
      const double reached = a1 - radius - kMargin;  // every ray is settled up to t = reached
      if (!(next <= reached)) continue;
      next = kInf;
      for (std::size_t l = 0; l < live;) {  // the undecided rays, listed
        const std::uint32_t k = g.pending[l];
        if (g.best[k] <= reached || g.max_range[k] <= reached) {
          decide(k);  // drops it: the list's last entry takes its place
          g.pending[l] = g.pending[live];
        } else {
          next = std::min(next, std::min(g.best[k], g.max_range[k]));
          ++l;
        }
      }
    }
    while (live > 0) decide(g.pending[live - 1]);  // the sweep passed the grid or every max range
  }
}

}  // namespace glassmap
