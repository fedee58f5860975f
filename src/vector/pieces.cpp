// Step 2 of vectorize(): a grown region becomes pieces: a least-squares line, cut where the cells
// leave a gap, split while the Bayesian information criterion says two lines beat one.
#include "piece.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <vector>

#include "glassmap/core/angles.hpp"

namespace glassmap::vector::detail {

namespace {

// Circular mean of glass normals (period pi) as a unit normal.
Vec2 meanGlassNormal(const CellCloud& cloud, const std::vector<std::uint32_t>& ids) {
  std::complex<double> s = 0;
  for (const std::uint32_t i : ids) {
    const Vec2& n = cloud.normals[i];
    const double a = std::atan2(n.y(), n.x());
    s += std::polar(1.0, 2.0 * a);
  }
  const double a = 0.5 * std::arg(s);
  return {std::cos(a), std::sin(a)};
}

}  // namespace

// Fits the piece's line to its cells (CGAL least squares; for short glass pieces the angle labels
// are the better direction estimate) and clips it to its cells' extent plus end_margin_cells.
void refit(Piece& p, const CellCloud& cloud, Material material, const Context& ctx) {
  const double res = cloud.resolution;
  p.moments = {};
  for (const std::uint32_t i : p.ids) p.moments.add(cloud.points[i]);
  double l_max, l_min, angle;
  p.moments.eigen(l_max, l_min, angle);
  const double short_sd = ctx.opt.short_glass_sd_cells * res;  // 3 cells: about 10 cells of length
  const bool short_piece = l_max < short_sd * short_sd;
  if (material == Material::Glass && short_piece) {
    const Vec2 n = meanGlassNormal(cloud, p.ids);
    p.c = p.moments.mean();
    p.d = Vec2(-n.y(), n.x());
  } else if (l_max > 0) {
    const detail::Line2 line = detail::fitLine(cloud.points, p.ids);
    p.c = line.c;
    p.d = line.d;
  } else {
    p.c = p.moments.mean();
  }
  // A canonical direction: pointing into the half plane x > 0 (or up), so results are stable.
  if (p.d.x() < -1e-12 || (std::abs(p.d.x()) <= 1e-12 && p.d.y() < 0)) p.d = -p.d;
  double lo = 1e300, hi = -1e300;
  for (const std::uint32_t i : p.ids) {
    const double t = p.d.dot(cloud.points[i] - p.c);
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  }
  p.t0 = lo - ctx.opt.end_margin_cells * res;
  p.t1 = hi + ctx.opt.end_margin_cells * res;
  if (!p.faces_merged) {
    // A band of cells of width w spreads w^2/12 across the line; at least one cell.
    const double var = p.moments.rss() / std::max(1.0, p.moments.n);
    p.thickness = std::max(res, std::sqrt(12.0 * var));
  }
}

namespace {

// Splits sorted ids (by position along the line) while two lines beat one by the BIC.
void bicSplit(std::vector<std::uint32_t> ids, const CellCloud& cloud, const Context& ctx, std::size_t min_cells,
              std::vector<std::vector<std::uint32_t>>& out) {
  const std::size_t n = ids.size();
  const std::size_t k_min = std::max<std::size_t>(min_cells, 3);
  if (n < 2 * k_min) {
    out.push_back(std::move(ids));
    return;
  }
  // Order along the principal axis of these cells.
  Moments all;
  for (const std::uint32_t i : ids) all.add(cloud.points[i]);
  double l_max, l_min, angle;
  all.eigen(l_max, l_min, angle);
  const Vec2 d(std::cos(angle), std::sin(angle));
  std::sort(ids.begin(), ids.end(),
            [&](std::uint32_t a, std::uint32_t b) { return d.dot(cloud.points[a]) < d.dot(cloud.points[b]); });
  std::vector<Moments> prefix(n + 1);
  for (std::size_t k = 0; k < n; ++k) {
    prefix[k + 1] = prefix[k];
    prefix[k + 1].add(cloud.points[ids[k]]);
  }
  double best = 1e300;
  std::size_t best_k = 0;
  for (std::size_t k = k_min; k + k_min <= n; ++k) {
    const double rss = prefix[k].rss() + (all - prefix[k]).rss();
    if (rss < best) best = rss, best_k = k;
  }
  const double nn = static_cast<double>(n);
  if (best_k == 0 || ctx.bic(best, nn, 2) >= ctx.bic(all.rss(), nn, 1)) {
    out.push_back(std::move(ids));
    return;
  }
  ++ctx.stats.bic_splits;
  bicSplit(std::vector<std::uint32_t>(ids.begin(), ids.begin() + static_cast<std::ptrdiff_t>(best_k)), cloud, ctx,
           min_cells, out);
  bicSplit(std::vector<std::uint32_t>(ids.begin() + static_cast<std::ptrdiff_t>(best_k), ids.end()), cloud, ctx,
           min_cells, out);
}

}  // namespace

// Region -> pieces: cut where the cells leave a gap, then split by the criterion.
void piecesOfRegion(const std::vector<std::uint32_t>& region, const CellCloud& cloud, Material material,
                    const MaterialOptions& mo, const Context& ctx, std::vector<Piece>& out) {
  Piece whole;
  whole.ids = region;
  refit(whole, cloud, material, ctx);
  std::vector<std::pair<double, std::uint32_t>> along;
  along.reserve(region.size());
  for (const std::uint32_t i : region) along.push_back({whole.d.dot(cloud.points[i] - whole.c), i});
  std::sort(along.begin(), along.end());
  std::vector<std::vector<std::uint32_t>> runs(1);
  for (std::size_t k = 0; k < along.size(); ++k) {
    if (k > 0 && along[k].first - along[k - 1].first - cloud.resolution > mo.max_gap) runs.emplace_back();
    runs.back().push_back(along[k].second);
  }
  for (auto& run : runs) {
    std::vector<std::vector<std::uint32_t>> parts;
    bicSplit(std::move(run), cloud, ctx, mo.min_cells, parts);
    for (auto& ids : parts) {
      if (ids.size() < 2) continue;
      Piece p;
      p.ids = std::move(ids);
      refit(p, cloud, material, ctx);
      out.push_back(std::move(p));
    }
  }
}

}  // namespace glassmap::vector::detail
