#include "glassmap/vector/vectorize.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <numeric>
#include <unordered_map>

#include "fitting.hpp"
#include "glassmap/core/angles.hpp"
#include "glassmap/core/error.hpp"

namespace glassmap::vector {

MaterialOptions VectorizeOptions::glassDefaults() {
  MaterialOptions o;
  o.max_distance = 0.06;
  o.max_angle_deg = 15.0;  // three 5-degree bins either side
  o.neighbour_radius = 0.11;
  o.min_cells = 6;
  o.min_length = 0.40;
  o.min_elongation = 5.0;
  o.max_gap = 0.30;
  o.merge_gap = 0.30;
  o.max_bridge = 1.0;
  o.merge_angle_deg = 6.0;
  o.merge_offset = 0.10;
  o.thickness = 0.01;
  return o;
}

MaterialOptions VectorizeOptions::wallDefaults() {
  MaterialOptions o;
  o.max_distance = 0.10;
  o.max_angle_deg = 20.0;
  o.neighbour_radius = 0.11;
  o.normal_radius = 0.16;
  o.min_cells = 8;
  o.min_length = 0.50;
  o.min_elongation = 2.5;
  o.max_gap = 0.50;    // real walls are seen in patches; doors (0.8 m and up) stay open
  o.merge_gap = 0.50;
  o.max_bridge = 2.0;
  o.merge_angle_deg = 6.0;
  o.merge_offset = 0.10;
  o.thickness = 0.10;
  return o;
}

namespace {

using detail::CellCloud;
using detail::Moments;

// A segment under construction: its cells, line and extent along the line.
struct Piece {
  std::vector<std::uint32_t> ids;  // points of the material's cloud
  Moments moments;
  Vec2 c = Vec2::Zero();  // a point of the line
  Vec2 d = Vec2::UnitX(); // unit direction
  double t0 = 0, t1 = 0;  // extent along d from c [m]
  double thickness = 0;   // measured or merged thickness [m]
  bool faces_merged = false;
  bool alive = true;

  Vec2 a() const { return c + t0 * d; }
  Vec2 b() const { return c + t1 * d; }
  double length() const { return t1 - t0; }
  Vec2 normal() const { return {-d.y(), d.x()}; }
};

struct Context {
  const LabelGrid& grid;
  const VectorizeOptions& opt;
  VectorizeStats& stats;
  double sigma0_sq;  // BIC noise floor [m^2]
  double bic(double rss, double n, double segments) const {
    return n * std::log(std::max(rss / n, sigma0_sq)) + segments * opt.params_per_segment * std::log(n);
  }
};

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

// Fits the piece's line to its cells (CGAL least squares; for short glass pieces the angle labels
// are the better direction estimate) and clips it to its cells' extent plus half a cell.
void refit(Piece& p, const CellCloud& cloud, Material material) {
  const double res = cloud.resolution;
  p.moments = {};
  for (const std::uint32_t i : p.ids) p.moments.add(cloud.points[i]);
  double l_max, l_min, angle;
  p.moments.eigen(l_max, l_min, angle);
  const bool short_piece = l_max < (3.0 * res) * (3.0 * res);  // spread under ~10 cells of length
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
  p.t0 = lo - 0.5 * res;
  p.t1 = hi + 0.5 * res;
  if (!p.faces_merged) {
    // A band of cells of width w spreads w^2/12 across the line; at least one cell.
    const double var = p.moments.rss() / std::max(1.0, p.moments.n);
    p.thickness = std::max(res, std::sqrt(12.0 * var));
  }
}

// Splits sorted ids (by position along the line) while two lines beat one by the BIC.
void bicSplit(std::vector<std::uint32_t> ids, const CellCloud& cloud, const Context& ctx,
              std::size_t min_cells, std::vector<std::vector<std::uint32_t>>& out) {
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
  bicSplit(std::vector<std::uint32_t>(ids.begin(), ids.begin() + static_cast<std::ptrdiff_t>(best_k)), cloud,
           ctx, min_cells, out);
  bicSplit(std::vector<std::uint32_t>(ids.begin() + static_cast<std::ptrdiff_t>(best_k), ids.end()), cloud, ctx,
           min_cells, out);
}

// Region -> pieces: cut where the cells leave a gap, then split by the criterion.
void piecesOfRegion(const std::vector<std::uint32_t>& region, const CellCloud& cloud, Material material,
                    const MaterialOptions& mo, const Context& ctx, std::vector<Piece>& out) {
  Piece whole;
  whole.ids = region;
  refit(whole, cloud, material);
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
      refit(p, cloud, material);
      out.push_back(std::move(p));
    }
  }
}

// Interval of q's extent projected on p's line.
std::pair<double, double> projectedExtent(const Piece& p, const Piece& q) {
  const double u = p.d.dot(q.a() - p.c), v = p.d.dot(q.b() - p.c);
  return {std::min(u, v), std::max(u, v)};
}

// Calls f(i, j), i < j, for the alive pieces whose bounding boxes, grown by margin, overlap:
// a sweep over x so that large maps do not cost a full pairwise pass.
template <typename F>
void forNearbyPairs(const std::vector<Piece>& pieces, double margin, F&& f) {
  struct Entry {
    double x0, x1, y0, y1;
    std::size_t i;
  };
  std::vector<Entry> e;
  e.reserve(pieces.size());
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const Piece& p = pieces[i];
    if (!p.alive) continue;
    const Vec2 a = p.a(), b = p.b();
    e.push_back({std::min(a.x(), b.x()) - margin, std::max(a.x(), b.x()) + margin, std::min(a.y(), b.y()) - margin,
                 std::max(a.y(), b.y()) + margin, i});
  }
  std::sort(e.begin(), e.end(), [](const Entry& a, const Entry& b) { return a.x0 < b.x0 || (a.x0 == b.x0 && a.i < b.i); });
  for (std::size_t k = 0; k < e.size(); ++k)
    for (std::size_t m = k + 1; m < e.size() && e[m].x0 <= e[k].x1; ++m) {
      if (e[m].y0 > e[k].y1 || e[k].y0 > e[m].y1) continue;
      f(std::min(e[k].i, e[m].i), std::max(e[k].i, e[m].i));
    }
}

// True when no stretch of the gap [t, t + len] along p's line was seen free: at most a fifth of its
// samples have free space on the line and on both sides (a door or an opening is seen free; a wall
// that was hit sparsely, or not seen, is not).
bool unseenGap(const Piece& p, double t, double len, const LabelGrid& grid) {
  const double res = grid.resolution;
  const Vec2 n = p.normal();
  const auto isFree = [&](const Vec2& q) {
    const int x = static_cast<int>(std::floor((q.x() - grid.origin.x()) / res));
    const int y = static_cast<int>(std::floor((q.y() - grid.origin.y()) / res));
    return x >= 0 && y >= 0 && x < grid.width && y < grid.height && grid.code(x, y) == kCodeEmpty;
  };
  int samples = 0, free = 0;
  for (double s = 0.5 * res; s < len; s += res) {
    const Vec2 q = p.c + (t + s) * p.d;
    ++samples;
    if (isFree(q) && isFree(q + res * n) && isFree(q - res * n)) ++free;
  }
  return free * 5 <= samples;
}

// Greedy merging of collinear neighbours across gaps up to merge_gap, each merge accepted only when
// one line explains both cell sets at a lower BIC than two.
void mergeCollinear(std::vector<Piece>& pieces, const CellCloud& cloud, Material material,
                    const MaterialOptions& mo, const Context& ctx) {
  const double cos_max = std::cos(deg2rad(mo.merge_angle_deg));
  for (bool changed = true; changed;) {
    changed = false;
    struct Candidate {
      double gain;
      std::size_t i, j;
    };
    std::vector<Candidate> candidates;
    forNearbyPairs(pieces, 0.5 * std::max(mo.merge_gap, mo.max_bridge) + mo.merge_offset, [&](std::size_t i, std::size_t j) {
      const Piece& p = pieces[i];
      const Piece& q = pieces[j];
      {
        if (std::abs(p.d.dot(q.d)) < cos_max) return;
        const auto [u0, u1] = projectedExtent(p, q);
        const double gap = std::max(u0 - p.t1, p.t0 - u1);
        if (gap > mo.max_bridge || (gap > mo.merge_gap && !unseenGap(p, u0 > p.t1 ? p.t1 : u1, gap, ctx.grid))) return;
        const Vec2 np = p.normal(), nq = q.normal();
        const double off = std::max({std::abs(np.dot(q.a() - p.c)), std::abs(np.dot(q.b() - p.c)),
                                     std::abs(nq.dot(p.a() - q.c)), std::abs(nq.dot(p.b() - q.c))});
        if (off > mo.merge_offset) return;
        Moments u = p.moments;
        u += q.moments;
        const double gain = ctx.bic(p.moments.rss() + q.moments.rss(), u.n, 2) - ctx.bic(u.rss(), u.n, 1);
        if (gain > 0) candidates.push_back({gain, i, j});
      }
    });
    std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
      return a.gain > b.gain || (a.gain == b.gain && std::make_pair(a.i, a.j) < std::make_pair(b.i, b.j));
    });
    std::vector<bool> touched(pieces.size(), false);
    for (const Candidate& c : candidates) {
      if (touched[c.i] || touched[c.j]) continue;
      touched[c.i] = touched[c.j] = true;
      Piece& p = pieces[c.i];
      Piece& q = pieces[c.j];
      p.ids.insert(p.ids.end(), q.ids.begin(), q.ids.end());
      const bool faced = p.faces_merged || q.faces_merged;
      const double thick = std::max(p.thickness, q.thickness);
      refit(p, cloud, material);
      if (faced) p.thickness = thick, p.faces_merged = true;
      q.alive = false;
      ++ctx.stats.merges;
      changed = true;
    }
  }
}

// Wall faces: two near-parallel wall pieces less than max_wall_thickness apart, overlapping over
// half the shorter one, with no free space between them, become one centre line.
void mergeFaces(std::vector<Piece>& pieces, const CellCloud& cloud, const Context& ctx) {
  const LabelGrid& grid = ctx.grid;
  const double cos_max = std::cos(deg2rad(ctx.opt.wall.merge_angle_deg));
  const auto isFree = [&](const Vec2& p) {
    const int x = static_cast<int>(std::floor((p.x() - grid.origin.x()) / grid.resolution));
    const int y = static_cast<int>(std::floor((p.y() - grid.origin.y()) / grid.resolution));
    return x >= 0 && y >= 0 && x < grid.width && y < grid.height && grid.code(x, y) == kCodeEmpty;
  };
  for (bool changed = true; changed;) {
    changed = false;
    struct Candidate {
      double sep;
      std::size_t i, j;
    };
    std::vector<Candidate> candidates;
    forNearbyPairs(pieces, ctx.opt.max_wall_thickness, [&](std::size_t i, std::size_t j) {
      const Piece& p = pieces[i];
      const Piece& q = pieces[j];
      {
        if (std::abs(p.d.dot(q.d)) < cos_max) return;
        const double sep = std::abs(p.normal().dot(q.c - p.c));
        if (sep > ctx.opt.max_wall_thickness) return;
        const auto [u0, u1] = projectedExtent(p, q);
        const double overlap = std::min(u1, p.t1) - std::max(u0, p.t0);
        if (overlap < 0.5 * std::min(p.length(), q.length())) return;
        // Free cells between the faces: a corridor or a gap, not one wall.
        const double lo = std::max(u0, p.t0), hi = std::min(u1, p.t1);
        int free = 0;
        constexpr int kSamples = 9;
        for (int k = 0; k < kSamples; ++k) {
          const double t = lo + (hi - lo) * (k + 0.5) / kSamples;
          const Vec2 on_p = p.c + t * p.d;
          const Vec2 foot = q.c + q.d * q.d.dot(on_p - q.c);
          if (isFree(0.5 * (on_p + foot))) ++free;
        }
        if (free * 3 > kSamples) return;
        candidates.push_back({sep, i, j});
      }
    });
    std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
      return a.sep < b.sep || (a.sep == b.sep && std::make_pair(a.i, a.j) < std::make_pair(b.i, b.j));
    });
    std::vector<bool> touched(pieces.size(), false);
    for (const Candidate& c : candidates) {
      if (touched[c.i] || touched[c.j]) continue;
      touched[c.i] = touched[c.j] = true;
      Piece& p = pieces[c.i];
      Piece& q = pieces[c.j];
      Vec2 dq = q.d;
      if (dq.dot(p.d) < 0) dq = -dq;
      const Vec2 d = (p.length() * p.d + q.length() * dq).normalized();
      const Vec2 n(-d.y(), d.x());
      // Midline between the two face lines, equally weighted whatever their cell counts.
      const double off = 0.5 * (n.dot(p.c) + n.dot(q.c));
      const double t_lo = std::min({d.dot(p.a()), d.dot(p.b()), d.dot(q.a()), d.dot(q.b())});
      const double t_hi = std::max({d.dot(p.a()), d.dot(p.b()), d.dot(q.a()), d.dot(q.b())});
      const double sep = std::abs(n.dot(q.c - p.c));
      p.ids.insert(p.ids.end(), q.ids.begin(), q.ids.end());
      p.moments += q.moments;
      p.c = off * n;
      p.d = d;
      p.t0 = t_lo;
      p.t1 = t_hi;
      p.thickness = std::min(ctx.opt.max_wall_thickness, std::max(p.thickness, sep + cloud.resolution));
      p.faces_merged = true;
      q.alive = false;
      ++ctx.stats.face_merges;
      changed = true;
    }
  }
}

void compact(std::vector<Piece>& pieces) {
  pieces.erase(std::remove_if(pieces.begin(), pieces.end(), [](const Piece& p) { return !p.alive; }), pieces.end());
}

// Share of a glass piece's cells whose angle label agrees with the fitted pane normal.
double labelAgreement(const Piece& p, const CellCloud& cloud, double max_angle_deg) {
  const double cos_max = std::cos(deg2rad(max_angle_deg));
  const Vec2 n = p.normal();
  std::size_t agree = 0;
  for (const std::uint32_t i : p.ids)
    if (std::abs(cloud.normals[i].dot(n)) >= cos_max) ++agree;
  return p.ids.empty() ? 0.0 : static_cast<double>(agree) / static_cast<double>(p.ids.size());
}

// Share of a glass piece's cells that have glass cells two cells away across the line: about 0 for
// a pane (one to three cells thick), high for a strip cut out of a blob.
double sideCrowding(const Piece& p, const CellCloud& cloud) {
  const Vec2 off = 2.0 * cloud.resolution * p.normal();
  const auto glassAt = [&](const Vec2& q) {
    const int x = static_cast<int>(std::floor(q.x() / cloud.resolution - cloud.origin_cells.x()));
    const int y = static_cast<int>(std::floor(q.y() / cloud.resolution - cloud.origin_cells.y()));
    return x >= 0 && y >= 0 && x < cloud.width && y < cloud.height &&
           cloud.index[static_cast<std::size_t>(y) * cloud.width + x] >= 0;
  };
  std::size_t crowded = 0;
  for (const std::uint32_t i : p.ids)
    if (glassAt(cloud.points[i] + off) || glassAt(cloud.points[i] - off)) ++crowded;
  return p.ids.empty() ? 1.0 : static_cast<double>(crowded) / static_cast<double>(p.ids.size());
}

// Drops pieces the evidence does not support: too few cells, too short, a blob, or (glass) cells
// whose angle labels disagree with the line through them.
void filterPieces(std::vector<Piece>& pieces, Material material, const MaterialOptions& mo, const CellCloud& cloud,
                  const Context& ctx) {
  for (Piece& p : pieces) {
    if (!p.alive) continue;
    const double width = std::max(cloud.resolution, p.faces_merged ? cloud.resolution : p.thickness);
    if (p.ids.size() < mo.min_cells || p.length() < mo.min_length || p.length() < mo.min_elongation * width ||
        (material == Material::Glass && (labelAgreement(p, cloud, mo.max_angle_deg) < mo.min_label_agreement ||
                                         sideCrowding(p, cloud) > 0.5))) {
      p.alive = false;
      ++ctx.stats.dropped;
    }
  }
  compact(pieces);
}

std::vector<Piece> fitMaterial(const CellCloud& cloud, Material material, const MaterialOptions& mo,
                               const Context& ctx) {
  std::vector<Piece> pieces;
  if (cloud.points.empty()) return pieces;
  detail::GrowParams gp;
  gp.max_distance = mo.max_distance;
  gp.max_angle_deg = mo.max_angle_deg;
  gp.radius = mo.neighbour_radius;
  gp.min_region = 3;
  const auto regions = detail::growRegions(cloud, gp);
  ctx.stats.regions += regions.size();
  for (const auto& r : regions) piecesOfRegion(r, cloud, material, mo, ctx, pieces);
  mergeCollinear(pieces, cloud, material, mo, ctx);
  compact(pieces);
  if (material == Material::Wall) {
    mergeFaces(pieces, cloud, ctx);
    compact(pieces);
    mergeCollinear(pieces, cloud, material, mo, ctx);
    compact(pieces);
  }
  filterPieces(pieces, material, mo, cloud, ctx);
  return pieces;
}

// Cells of one material as a cloud with normals and seed scores.
CellCloud makeCloud(const LabelGrid& grid, Material material, const MaterialOptions& mo) {
  CellCloud cloud;
  cloud.width = grid.width;
  cloud.height = grid.height;
  cloud.resolution = grid.resolution;
  cloud.origin_cells = grid.origin / grid.resolution;
  cloud.index.assign(grid.cells(), -1);
  for (int y = 0; y < grid.height; ++y)
    for (int x = 0; x < grid.width; ++x) {
      const std::uint8_t code = grid.code(x, y);
      if (material == Material::Glass ? !isGlassCode(code) : !isWallCode(code)) continue;
      const std::size_t li = static_cast<std::size_t>(y) * grid.width + x;
      cloud.index[li] = static_cast<std::int32_t>(cloud.points.size());
      cloud.points.push_back(grid.center(x, y));
      cloud.cell.push_back(static_cast<std::int32_t>(li));
    }
  const std::size_t n = cloud.points.size();
  cloud.normals.resize(n);
  cloud.seed_score.resize(n);
  const auto at = [&](int x, int y) -> std::int32_t {
    if (x < 0 || y < 0 || x >= grid.width || y >= grid.height) return -1;
    return cloud.index[static_cast<std::size_t>(y) * grid.width + x];
  };
  if (material == Material::Glass) {
    const double bin = deg2rad(grid.angle_bin_deg);
    const int bins = static_cast<int>(std::lround(180.0 / grid.angle_bin_deg));
    for (std::size_t i = 0; i < n; ++i) {
      const int li = cloud.cell[i];
      const int x = li % grid.width, y = li / grid.width;
      const int k = grid.code(x, y) - kCodeFirstGlass;
      cloud.normals[i] = Vec2(std::cos(k * bin), std::sin(k * bin));
      // Seeds: cells whose neighbours agree with their angle label.
      int agree = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const std::int32_t j = at(x + dx, y + dy);
          if ((dx == 0 && dy == 0) || j < 0) continue;
          const int kj = grid.code(x + dx, y + dy) - kCodeFirstGlass;
          const int diff = std::abs(k - kj) % bins;
          if (std::min(diff, bins - diff) <= 1) ++agree;
        }
      cloud.seed_score[i] = agree >= 1 ? agree : -1.0;
    }
  } else {
    // Normal of a wall cell: minor axis of the wall cells within normal_radius.
    const int r = std::max(1, static_cast<int>(std::floor(mo.normal_radius / grid.resolution)));
    const double r2 = (mo.normal_radius / grid.resolution) * (mo.normal_radius / grid.resolution);
    for (std::size_t i = 0; i < n; ++i) {
      const int li = cloud.cell[i];
      const int x = li % grid.width, y = li / grid.width;
      Moments m;
      for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx)
          if (dx * dx + dy * dy <= r2 + 1e-9 && at(x + dx, y + dy) >= 0) m.add(Vec2(dx, dy));
      double l_max, l_min, angle;
      m.eigen(l_max, l_min, angle);
      cloud.normals[i] = Vec2(-std::sin(angle), std::cos(angle));
      cloud.seed_score[i] = m.n >= 4 && l_max > 0 ? 1.0 - l_min / l_max : -1.0;
    }
  }
  return cloud;
}

// The floor's dominant wall direction modulo 90 degrees: the direction with the most wall length
// within 1 degree (on the 4-fold circle, so 0 and 90 degrees count together), refined by the
// length-weighted circular mean of those walls.
double dominantAxis(const std::vector<Piece>& walls) {
  const double window = deg2rad(1.0);
  const auto dir4 = [](const Piece& p) { return std::atan2(p.d.y(), p.d.x()); };
  double best_len = -1, best = 0;
  for (const Piece& cand : walls) {
    double len = 0;
    for (const Piece& p : walls)
      if (std::abs(std::remainder(dir4(p) - dir4(cand), 0.5 * kPi)) <= window) len += p.length();
    if (len > best_len) best_len = len, best = dir4(cand);
  }
  std::complex<double> s = 0;
  for (const Piece& p : walls)
    if (std::abs(std::remainder(dir4(p) - best, 0.5 * kPi)) <= window) s += p.length() * std::polar(1.0, 4.0 * dir4(p));
  return std::abs(s) > 0 ? 0.25 * std::arg(s) : best;
}

// Rotates pieces within the angle of an axis (dominant + k * 90 deg) onto it, about their middle.
void regularize(std::vector<Piece>& pieces, double axis, const Context& ctx) {
  const double tol = deg2rad(ctx.opt.regularize_angle_deg);
  for (Piece& p : pieces) {
    const double a = std::atan2(p.d.y(), p.d.x());
    const double delta = std::remainder(a - axis, 0.5 * kPi);
    if (std::abs(delta) > tol || delta == 0.0) continue;
    const Vec2 mid = 0.5 * (p.a() + p.b());
    const double half = 0.5 * p.length();
    p.d = Vec2(std::cos(a - delta), std::sin(a - delta));
    p.c = mid;
    p.t0 = -half;
    p.t1 = half;
    ++ctx.stats.regularized;
  }
}

// Closes corners and T junctions: a segment end within corner_snap of the intersection of its
// line with a wall's line (crossing at 30 degrees or more, the intersection on or near that wall)
// moves to the intersection. Glass ends snap to walls, wall ends to walls.
void snapCorners(std::vector<Piece>& glass, std::vector<Piece>& walls, const Context& ctx) {
  const double snap = ctx.opt.corner_snap;
  const double sin_min = std::sin(deg2rad(30.0));
  struct Move {
    Piece* piece;
    bool end;  // false: t0, true: t1
    double t;
  };
  std::vector<Move> moves;
  // Walls bucketed by their boxes grown by the snap distance, on a 2 m grid.
  constexpr double kBucket = 2.0;
  std::unordered_map<std::int64_t, std::vector<std::size_t>> buckets;
  const auto key = [](std::int64_t bx, std::int64_t by) { return (bx << 32) ^ (by & 0xffffffff); };
  for (std::size_t k = 0; k < walls.size(); ++k) {
    const Vec2 lo = walls[k].a().cwiseMin(walls[k].b()) - Vec2::Constant(2 * snap);
    const Vec2 hi = walls[k].a().cwiseMax(walls[k].b()) + Vec2::Constant(2 * snap);
    for (auto bx = static_cast<std::int64_t>(std::floor(lo.x() / kBucket)); bx <= std::floor(hi.x() / kBucket); ++bx)
      for (auto by = static_cast<std::int64_t>(std::floor(lo.y() / kBucket)); by <= std::floor(hi.y() / kBucket); ++by)
        buckets[key(bx, by)].push_back(k);
  }
  static const std::vector<std::size_t> kNone;
  const auto near = [&](const Vec2& q) -> const std::vector<std::size_t>& {
    const auto it = buckets.find(key(static_cast<std::int64_t>(std::floor(q.x() / kBucket)),
                                     static_cast<std::int64_t>(std::floor(q.y() / kBucket))));
    return it == buckets.end() ? kNone : it->second;
  };
  // Only pieces long enough to be walls (or panes) of the plan take part; clutter stays apart.
  const double min_len = 2.0 * snap;
  const auto consider = [&](Piece& p, bool own_wall_index_valid, std::size_t own) {
    if (p.length() < min_len) return;
    for (int e = 0; e < 2; ++e) {
      const Vec2 end = e == 0 ? p.a() : p.b();
      double best = snap;
      double best_t = 0;
      bool found = false;
      for (const std::size_t k : near(end)) {
        if (own_wall_index_valid && k == own) continue;
        const Piece& w = walls[k];
        if (w.length() < min_len) continue;
        const double cross = p.d.x() * w.d.y() - p.d.y() * w.d.x();
        if (std::abs(cross) < sin_min) continue;
        // p.c + t p.d = w.c + s w.d
        const Vec2 diff = w.c - p.c;
        const double t = (diff.x() * w.d.y() - diff.y() * w.d.x()) / cross;
        const double s = (diff.x() * p.d.y() - diff.y() * p.d.x()) / cross;
        const Vec2 x = p.c + t * p.d;
        const double dist = (x - end).norm();
        if (dist >= best || s < w.t0 - snap || s > w.t1 + snap) continue;
        // Never flip or halve the segment.
        const double len = e == 0 ? p.t1 - t : t - p.t0;
        if (len < 0.5 * p.length()) continue;
        best = dist;
        best_t = t;
        found = true;
      }
      if (found) moves.push_back({&p, e == 1, best_t});
    }
  };
  for (std::size_t k = 0; k < walls.size(); ++k) consider(walls[k], true, k);
  for (Piece& g : glass) consider(g, false, 0);
  for (const Move& m : moves) {
    (m.end ? m.piece->t1 : m.piece->t0) = m.t;
    ++ctx.stats.corners;
  }
}

// A wall seen from one side: cells beyond its surface get hits from beams whose pose or range error
// carried them past it, and few beams pass there to clear them, so the band of wall cells spreads
// away from the observer (by the pose's heading error times the range: tens of cm at 20 m). The
// surface is where observed free space ends: the line moves to the median offset of the cells that
// touch free space on the free side. Walls with free space on both sides keep their centre line.
void alignOneSidedWalls(std::vector<Piece>& walls, const CellCloud& cloud, const Context& ctx) {
  const LabelGrid& grid = ctx.grid;
  const double res = grid.resolution;
  const auto freeAt = [&](const Vec2& p) {
    const int x = static_cast<int>(std::floor((p.x() - grid.origin.x()) / res));
    const int y = static_cast<int>(std::floor((p.y() - grid.origin.y()) / res));
    return x >= 0 && y >= 0 && x < grid.width && y < grid.height && grid.code(x, y) == kCodeEmpty;
  };
  for (Piece& p : walls) {
    const Vec2 n = p.normal();
    // Free samples on each side, just beyond the band: 3 depths x up to 16 stations along the wall.
    int free_pos = 0, free_neg = 0;
    const int stations = std::clamp(static_cast<int>(p.length() / res), 2, 16);
    const double half = 0.5 * p.thickness;
    for (int k = 0; k < stations; ++k) {
      const Vec2 on = p.c + (p.t0 + (p.t1 - p.t0) * (k + 0.5) / stations) * p.d;
      for (int depth = 1; depth <= 3; ++depth) {
        const double off = half + depth * res;
        free_pos += freeAt(on + off * n);
        free_neg += freeAt(on - off * n);
      }
    }
    const int hi = std::max(free_pos, free_neg), lo = std::min(free_pos, free_neg);
    if (hi < stations || 4 * lo > hi) continue;  // unseen, or free on both sides
    const Vec2 toward_free = free_pos > free_neg ? n : Vec2(-n);
    // Offsets (toward free space) of the piece's cells that touch free space on that side.
    std::vector<double> offsets;
    for (const std::uint32_t i : p.ids) {
      const Vec2& q = cloud.points[i];
      if (freeAt(q + res * toward_free) || freeAt(q + res * toward_free + 0.5 * res * p.d) ||
          freeAt(q + res * toward_free - 0.5 * res * p.d))
        offsets.push_back(toward_free.dot(q - p.c));
    }
    if (offsets.size() < 3) continue;
    auto mid = offsets.begin() + static_cast<std::ptrdiff_t>(offsets.size() / 2);
    std::nth_element(offsets.begin(), mid, offsets.end());
    const double shift = *mid;
    if (std::abs(shift) < 0.25 * res || std::abs(shift) > p.thickness) continue;
    p.c += shift * toward_free;
    ++ctx.stats.face_aligned;
  }
}

MapSegment toSegment(const Piece& p, Material material, const CellCloud& cloud, const LabelGrid& grid,
                     const MaterialOptions& mo) {
  MapSegment s;
  s.a = p.a();
  s.b = p.b();
  s.material = material;
  s.thickness = material == Material::Glass ? mo.thickness : p.thickness;
  s.pane_angle = material == Material::Glass ? wrapHalfTurn(std::atan2(p.d.y(), p.d.x()) + 0.5 * kPi) : 0.0;
  s.support = static_cast<std::uint32_t>(p.ids.size());
  if (!grid.evidence.empty()) {
    double sum = 0;
    for (const std::uint32_t i : p.ids) sum += grid.evidence[static_cast<std::size_t>(cloud.cell[i])];
    s.evidence = p.ids.empty() ? 0.0 : sum / static_cast<double>(p.ids.size());
  }
  return s;
}

}  // namespace

VectorizeResult vectorize(const LabelGrid& grid, const VectorizeOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  grid.validate();
  VectorizeResult result;
  VectorizeStats& stats = result.stats;
  const double floor_m = options.noise_floor * grid.resolution;
  const Context ctx{grid, options, stats, floor_m * floor_m};

  const CellCloud glass_cloud = makeCloud(grid, Material::Glass, options.glass);
  const CellCloud wall_cloud = makeCloud(grid, Material::Wall, options.wall);
  stats.glass_cells = glass_cloud.points.size();
  stats.wall_cells = wall_cloud.points.size();
  std::vector<Piece> glass, walls;
  if (options.glass_segments) glass = fitMaterial(glass_cloud, Material::Glass, options.glass, ctx);
  if (options.walls) walls = fitMaterial(wall_cloud, Material::Wall, options.wall, ctx);

  if (options.face_align) alignOneSidedWalls(walls, wall_cloud, ctx);
  if (options.regularize && !walls.empty()) {
    const double axis = dominantAxis(walls);
    stats.dominant_axis_deg = rad2deg(std::fmod(axis + kPi, 0.5 * kPi));
    regularize(walls, axis, ctx);
    regularize(glass, axis, ctx);
  }
  if (options.corner_snap > 0) snapCorners(glass, walls, ctx);

  result.map.segments.reserve(glass.size() + walls.size());
  for (const Piece& p : glass)
    result.map.segments.push_back(toSegment(p, Material::Glass, glass_cloud, grid, options.glass));
  for (const Piece& p : walls)
    result.map.segments.push_back(toSegment(p, Material::Wall, wall_cloud, grid, options.wall));
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace glassmap::vector
