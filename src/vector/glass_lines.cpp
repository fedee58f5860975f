// Step 2 of vectorize() for glass: glass cells -> pane pieces by voting for lines.
//
// A pane is seen only where beams meet it near its normal, so the glass cells of a pane are often
// sparse: a laser with a narrow direct-return lobe, coarse beams or long range leaves one cell in
// three or four along the pane, and region growing over neighbouring cells finds no region at all.
// Each glass cell knows its pane normal (its angle label), so cells vote for lines: a Hough
// accumulator over (normal angle, offset), each cell voting only near its own normal. The
// strongest line takes the cells within max_distance of it, its line is refitted, and it is cut
// where a gap is longer than its own density of cells makes likely: a pane seen in one cell of q
// leaves a gap of g cells with probability (1 - q)^g. The cells are then removed from the
// accumulator and the next line is taken, until no line holds min_cells. A piece is kept only
// when so many cells on one line could not come from the glass cells around it by chance (an a
// contrario test: passers-by and clutter leave glass-like cells that line up now and then).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <boost/math/distributions/binomial.hpp>
#include <boost/math/special_functions/gamma.hpp>

#include "glassmap/core/angles.hpp"
#include "piece.hpp"

namespace glassmap::vector::detail {
namespace {

constexpr int kAngleSamples = 180;  // 1 degree steps over [0, 180)

struct Accumulator {
  int rho_bins = 0;
  double rho_step = 0, rho_min = 0;
  std::vector<Vec2> normals;    // [angle sample]
  std::vector<std::int32_t> v;  // [angle * rho_bins + rho]
  int spread = 0;               // angle samples either side of a cell's label a cell votes for

  int rhoBin(double rho) const { return static_cast<int>(std::floor((rho - rho_min) / rho_step)); }
  // Votes of cell p with label normal angle `phi` [rad], added with sign s.
  void vote(const Vec2& p, double phi, int s) {
    const int centre = static_cast<int>(std::lround(rad2deg(phi))) % kAngleSamples;
    for (int k = -spread; k <= spread; ++k) {
      const int a = (centre + k + kAngleSamples) % kAngleSamples;
      const int r = rhoBin(p.dot(normals[static_cast<std::size_t>(a)]));
      if (r >= 0 && r < rho_bins) v[static_cast<std::size_t>(a) * rho_bins + r] += s;
    }
  }
  // The strongest line: (angle sample, rho bin) maximising the votes of three adjacent rho bins.
  std::int32_t best(int& angle, int& rho) const {
    std::int32_t top = 0;
    for (int a = 0; a < kAngleSamples; ++a) {
      const std::int32_t* row = v.data() + static_cast<std::size_t>(a) * rho_bins;
      for (int r = 1; r + 1 < rho_bins; ++r) {
        const std::int32_t s = row[r - 1] + row[r] + row[r + 1];
        if (s > top) top = s, angle = a, rho = r;
      }
    }
    return top;
  }
};

// Label normal angle of a cloud point in [0, pi).
double normalAngle(const CellCloud& cloud, std::uint32_t i) {
  const Vec2& n = cloud.normals[i];
  double a = std::atan2(n.y(), n.x());
  if (a < 0) a += kPi;
  if (a >= kPi) a -= kPi;
  return a;
}

// Splits cells sorted along a line (positions t [m]) at gaps their own density makes unlikely:
// with q = cells / length in cells, a gap of g empty cells has probability (1 - q)^g, and the
// widest of the m gaps (stretches of empty cells between the cells) is that wide with probability
// about m (1 - q)^g; where that is below alpha the run splits there, largest first (a sparse
// pane's cells leave a wide gap somewhere by chance: the longer the pane, the wider). Gaps up to
// always_join [m] never split.
void splitAtGaps(const std::vector<std::pair<double, std::uint32_t>>& along, std::size_t lo, std::size_t hi, double res,
                 double alpha, double always_join, double never_join,
                 std::vector<std::pair<std::size_t, std::size_t>>& runs) {
  if (hi - lo < 2) {
    runs.push_back({lo, hi});
    return;
  }
  const double length_cells = (along[hi - 1].first - along[lo].first) / res + 1.0;
  const double q = std::min(1.0, static_cast<double>(hi - lo) / length_cells);
  std::size_t cut = 0, gaps = 0;
  double widest = 0;
  for (std::size_t k = lo + 1; k < hi; ++k) {
    const double gap = along[k].first - along[k - 1].first - res;
    gaps += gap > 0.5 * res;
    if (gap > widest) widest = gap, cut = k;
  }
  // The widest of m draws, unless the cells clump (far fewer stretches of empty cells than cells
  // placed independently would leave: P(at most m | n - 1 pairs, 1 - q) < alpha), as blobs on a
  // line do: then the gap is judged alone.
  double draws = 1.0;
  if (q < 1.0 && gaps > 1) {
    const boost::math::binomial_distribution<double> independent(static_cast<double>(hi - lo - 1), 1.0 - q);
    if (boost::math::cdf(independent, static_cast<double>(gaps)) >= alpha) draws = static_cast<double>(gaps);
  }
  const double empty_cells = widest / res;
  const double log_p = std::log(draws) + empty_cells * std::log1p(-q);
  const bool split = widest > never_join || (widest > always_join && (q >= 1.0 || log_p < std::log(alpha)));
  if (!split) {
    runs.push_back({lo, hi});
    return;
  }
  splitAtGaps(along, lo, cut, res, alpha, always_join, never_join, runs);
  splitAtGaps(along, cut, hi, res, alpha, always_join, never_join, runs);
}

// log P(X >= n) for X ~ Poisson(mu): the chance of n or more cells in a band where mu are expected
// (the regularised lower incomplete gamma function P(n, mu); -inf where it underflows).
double logPoissonTail(std::size_t n, double mu) {
  if (n == 0) return 0.0;
  return std::log(boost::math::gamma_p(static_cast<double>(n), mu));
}

// log10 of the number of false alarms of a piece (Desolneux, Moisan and Morel's a contrario
// test): how many lines this well supported the glass cells around it would draw by chance. The
// background is the density of glass cells of a compatible angle in a ring beside the piece
// (beyond the band it claims, out to ring [m]), so a line through a cloud of noise or through a
// passer-by's arc counts only what stands out of its own neighbourhood.
double log10FalseAlarms(const Piece& p, const CellCloud& cloud, double band, double ring, double cos_max,
                        double log10_tests) {
  const double res = cloud.resolution;
  const Vec2 n = p.normal();
  std::size_t in_ring = 0, ring_cells = 0;
  for (double t = p.t0 + 0.5 * res; t < p.t1; t += res) {
    for (double u = 2.0 * band + 0.5 * res; u <= ring; u += res) {
      for (const double side : {-1.0, 1.0}) {
        const Vec2 q = p.at(t) + side * u * n;
        const int x = static_cast<int>(std::floor(q.x() / res)), y = static_cast<int>(std::floor(q.y() / res));
        ++ring_cells;
        if (x < 0 || y < 0 || x >= cloud.width || y >= cloud.height) continue;
        const std::int32_t i = cloud.index[static_cast<std::size_t>(y) * cloud.width + x];
        if (i >= 0 && std::abs(cloud.normals[static_cast<std::size_t>(i)].dot(n)) >= cos_max) ++in_ring;
      }
    }
  }
  const double band_cells = std::max(1.0, p.length() / res) * (2.0 * band / res);
  const double density = (static_cast<double>(in_ring) + 1.0) / (static_cast<double>(ring_cells) + 1.0);
  return log10_tests + logPoissonTail(p.ids.size(), density * band_cells) / std::log(10.0);
}

// A run too short to stand out alone may continue a pane already accepted: the cells of a pane
// that is not aligned with the 1-degree vote lines, or whose normals a wide lobe biases, fall to
// several lines, and a short tail of it is then tested alone against every line the grid could
// hold. Where it lies on an accepted piece's line (every cell in the piece's band, normals
// compatible) and continues it (across at most merge_gap, or up to max_bridge not seen free), it
// is tested again as what it is, one of the few continuations of the accepted pieces: the same
// tail probability, counted over (rejected runs x accepted pieces) tests instead of the whole
// grid's lines; a run that passes joins the piece.
void acceptContinuations(std::vector<Piece>& rejected, std::size_t first, const CellCloud& cloud,
                         const MaterialOptions& mo, const Context& ctx, std::vector<Piece>& out) {
  const double band = 2.0 * mo.max_distance;  // the band a piece claims, its shadow included
  // A run's normal labels may all be biased alike (a wide lobe returns off the normal, and the MRF
  // makes neighbouring labels agree): twice the vote's angle tolerance, still far from a corner's.
  const double cos_join = std::cos(deg2rad(std::min(45.0, 2.0 * mo.max_angle_deg)));
  const double cos_max = std::cos(deg2rad(mo.max_angle_deg));
  const double log10_tests =
      std::log10(static_cast<double>(std::max<std::size_t>(1, rejected.size() * (out.size() - first))));
  // r lies on a's line within max_bridge of its end, across a gap not seen free (a door stays open).
  auto continues = [&](const Piece& r, const Piece& a) {
    const Vec2 n = a.normal();
    for (const std::uint32_t i : r.ids)
      if (std::abs((cloud.points[i] - a.c).dot(n)) > band || std::abs(cloud.normals[i].dot(n)) < cos_join) return false;
    const double r0 = std::min((r.a() - a.c).dot(a.d), (r.b() - a.c).dot(a.d));
    const double r1 = std::max((r.a() - a.c).dot(a.d), (r.b() - a.c).dot(a.d));
    const double gap = std::max(r0 - a.t1, a.t0 - r1);
    return gap <= mo.merge_gap || (gap <= mo.max_bridge && unseenGap(a, r0 > a.t1 ? a.t1 : r1, gap, ctx));
  };
  for (bool grew = true; grew;) {
    grew = false;
    for (Piece& r : rejected) {
      if (r.ids.empty()) continue;
      std::size_t k = first;
      while (k < out.size() && !continues(r, out[k])) ++k;
      if (k == out.size() || log10FalseAlarms(r, cloud, mo.max_distance, ctx.opt.glass_background_ring, cos_max,
                                              log10_tests) >= ctx.opt.glass_log10_false_alarms)
        continue;
      // One pane: its cells join the piece it continues (their own short line is too uncertain
      // in direction to be merged later).
      out[k].ids.insert(out[k].ids.end(), r.ids.begin(), r.ids.end());
      refit(out[k], cloud, Material::Glass, ctx);
      r.ids.clear();
      ++ctx.stats.continued;
      grew = true;
    }
  }
  for (const Piece& r : rejected) ctx.stats.dropped += !r.ids.empty();
}

}  // namespace

void glassPiecesByVoting(const CellCloud& cloud, const MaterialOptions& mo, const Context& ctx,
                         std::vector<Piece>& out) {
  const std::size_t n = cloud.points.size();
  if (n < mo.min_cells) return;
  const double res = cloud.resolution;
  Accumulator acc;
  acc.rho_step = 0.5 * res;
  const double diag = std::hypot(cloud.width * res, cloud.height * res);
  acc.rho_min = -diag - res;
  acc.rho_bins = static_cast<int>(std::ceil(2.0 * (diag + res) / acc.rho_step)) + 1;
  acc.normals.resize(kAngleSamples);
  for (int a = 0; a < kAngleSamples; ++a)
    acc.normals[static_cast<std::size_t>(a)] = {std::cos(deg2rad(a)), std::sin(deg2rad(a))};
  // A label stands for its bin (+- half a bin) and may be one bin off: vote that far either side.
  acc.spread = static_cast<int>(std::ceil(1.5 * ctx.grid.angle_bin_deg));
  acc.v.assign(static_cast<std::size_t>(kAngleSamples) * acc.rho_bins, 0);
  std::vector<double> phi(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    phi[i] = normalAngle(cloud, i);
    acc.vote(cloud.points[i], phi[i], +1);
  }
  std::vector<bool> used(n, false);
  // Tests made: as for line segments in an image (Desolneux, Moisan, Morel: (W H)^(5/2)), over the
  // cells that were observed at all.
  std::size_t observed = 0;
  for (const std::uint8_t c : ctx.grid.codes) observed += c != kCodeUnknown;
  const double log10_tests = 2.5 * std::log10(static_cast<double>(std::max<std::size_t>(observed, 1)));
  const double cos_max = std::cos(deg2rad(mo.max_angle_deg));
  const auto minCells = static_cast<std::int32_t>(mo.min_cells);
  const std::size_t first = out.size();
  std::vector<Piece> rejected;  // runs that did not stand out alone
  for (;;) {
    int a = 0, r = 0;
    if (acc.best(a, r) < minCells) break;
    // The line's cells: unused, within max_distance, label within max_angle of the line's normal.
    Vec2 normal = acc.normals[static_cast<std::size_t>(a)];
    double rho = acc.rho_min + (r + 0.5) * acc.rho_step;
    auto gather = [&] {
      std::vector<std::uint32_t> near;
      for (std::uint32_t i = 0; i < n; ++i)
        if (!used[i] && std::abs(cloud.points[i].dot(normal) - rho) <= mo.max_distance &&
            std::abs(cloud.normals[i].dot(normal)) >= cos_max)
          near.push_back(i);
      return near;
    };
    std::vector<std::uint32_t> ids = gather();
    if (ids.size() >= 2) {
      // Refit: the cells' own line when they spread along it, the vote's line otherwise.
      Piece p;
      p.ids = ids;
      refit(p, cloud, Material::Glass, ctx);
      if (p.length() > 4.0 * mo.max_distance) {
        normal = p.normal();
        rho = p.c.dot(normal);
      }
      ids = gather();
    }
    // However the refit moved, the cells the vote counted leave the accumulator, so the loop ends.
    for (std::uint32_t i = 0; i < n; ++i) {
      if (used[i] || std::abs(acc.rhoBin(cloud.points[i].dot(acc.normals[static_cast<std::size_t>(a)])) - r) > 1)
        continue;
      const int centre = static_cast<int>(std::lround(rad2deg(phi[i]))) % kAngleSamples;
      int diff = std::abs(centre - a);
      diff = std::min(diff, kAngleSamples - diff);
      if (diff > acc.spread) continue;
      ids.push_back(i);
    }
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    for (const std::uint32_t i : ids) {
      used[i] = true;
      acc.vote(cloud.points[i], phi[i], -1);
    }
    // Cells along the line, cut at unlikely gaps.
    const Vec2 d(-normal.y(), normal.x());
    std::vector<std::pair<double, std::uint32_t>> along;
    along.reserve(ids.size());
    for (const std::uint32_t i : ids)
      if (std::abs(cloud.points[i].dot(normal) - rho) <= mo.max_distance) along.push_back({d.dot(cloud.points[i]), i});
    std::sort(along.begin(), along.end());
    std::vector<std::pair<std::size_t, std::size_t>> runs;
    if (!along.empty())
      splitAtGaps(along, 0, along.size(), res, ctx.opt.glass_gap_alpha, mo.max_gap, mo.max_bridge, runs);
    ++ctx.stats.regions;
    for (const auto& [lo, hi] : runs) {
      if (hi - lo < 2) continue;
      Piece p;
      for (std::size_t k = lo; k < hi; ++k) p.ids.push_back(along[k].second);
      refit(p, cloud, Material::Glass, ctx);
      // A pane seen at a slant or by a noisy laser is a band a few cells thick: the cells just
      // outside the fitted band belong to it too and must not vote for a parallel twin; a blob
      // that a line was drawn through shows its width here.
      const double shadow = 2.0 * mo.max_distance;
      for (std::uint32_t i = 0; i < n; ++i) {
        if (used[i]) continue;
        const Vec2 q = cloud.points[i] - p.c;
        const double t = q.dot(p.d);
        if (t < p.t0 || t > p.t1 || std::abs(q.dot(p.normal())) > shadow) continue;
        if (std::abs(cloud.normals[i].dot(p.normal())) < cos_max) continue;
        used[i] = true;
        acc.vote(cloud.points[i], phi[i], -1);
        p.ids.push_back(i);
      }
      // Its thickness (and so its elongation, which tells a pane from a blob) counts them too, and
      // so does the test below: a short pane beyond a long one on nearly the same line gives the
      // long line only the cells its band reaches, and the others fall in its shadow.
      refit(p, cloud, Material::Glass, ctx);
      // Fewer than one such line expected by chance in a hundred maps, or dropped.
      const bool meaningful = log10FalseAlarms(p, cloud, mo.max_distance, ctx.opt.glass_background_ring, cos_max,
                                               log10_tests) < ctx.opt.glass_log10_false_alarms;
      if (meaningful) {
        out.push_back(std::move(p));
      } else {
        rejected.push_back(std::move(p));
      }
    }
  }
  acceptContinuations(rejected, first, cloud, mo, ctx, out);
}

}  // namespace glassmap::vector::detail
