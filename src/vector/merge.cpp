// Step 3 of vectorize(): collinear neighbours merge across small gaps when one line explains both
// at a lower BIC; the two faces of a wall seen from both sides merge into its centre line.
#include "piece.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "box_pairs.hpp"
#include "glassmap/core/angles.hpp"

namespace glassmap::vector::detail {

namespace {
// The building's thick walls: separations within this many cells (or a tenth) of the most common.
constexpr double kThicknessWindowCells = 1.5;
// ... holding at least this many times structure.max_furniture_length of wall.
constexpr double kThickWallEvidence = 2.0;
}  // namespace

// Interval of q's extent projected on p's line.
std::pair<double, double> projectedExtent(const Piece& p, const Piece& q) {
  const double u = p.d.dot(q.a() - p.c), v = p.d.dot(q.b() - p.c);
  return {std::min(u, v), std::max(u, v)};
}

// Signed distance from p's point at t (along p.d from p.c) to q's line, along p's normal.
double gapAt(const Piece& p, const Piece& q, double t) {
  const Vec2 on_p = p.at(t);
  return p.normal().dot(q.foot(on_p) - on_p);
}

// Calls f(i, j), i < j, in increasing order, for the alive pieces whose bounding boxes, grown by
// margin, overlap (CGAL's box intersection: large maps do not cost a full pairwise pass).
template <typename F>
void forNearbyPairs(const std::vector<Piece>& pieces, double margin, F&& f) {
  std::vector<Eigen::AlignedBox2d> boxes(pieces.size());  // empty for dead pieces
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    if (!pieces[i].alive) continue;
    boxes[i].extend(pieces[i].a());
    boxes[i].extend(pieces[i].b());
    boxes[i].min() -= Vec2::Constant(margin);
    boxes[i].max() += Vec2::Constant(margin);
  }
  for (const auto& [i, j] : overlappingPairs(boxes)) f(i, j);
}

// True when no stretch of the gap [t, t + len] along p's line was seen free: at most
// max_unseen_free_fraction of its samples have free space on the line and on both sides (a door or
// an opening is seen free; a wall that was hit sparsely, or not seen, is not).
bool unseenGap(const Piece& p, double t, double len, const Context& ctx) {
  const double res = ctx.grid.resolution;
  const Vec2 n = p.normal();
  int samples = 0, free = 0;
  for (double s = 0.5 * res; s < len; s += res) {
    const Vec2 q = p.c + (t + s) * p.d;
    ++samples;
    if (ctx.isFree(q) && ctx.isFree(q + res * n) && ctx.isFree(q - res * n)) ++free;
  }
  return free <= ctx.opt.max_unseen_free_fraction * samples;
}

// Greedy merging of collinear neighbours across gaps up to merge_gap, each merge accepted only when
// one line explains both cell sets at a lower BIC than two.
void mergeCollinear(std::vector<Piece>& pieces, const CellCloud& cloud, Material material, const MaterialOptions& mo,
                    const Context& ctx) {
  const double cos_max = std::cos(deg2rad(mo.merge_angle_deg));
  for (bool changed = true; changed;) {
    changed = false;
    struct Candidate {
      double gain;
      std::size_t i, j;
    };
    std::vector<Candidate> candidates;
    forNearbyPairs(
        pieces, 0.5 * std::max(mo.merge_gap, mo.max_bridge) + mo.merge_offset, [&](std::size_t i, std::size_t j) {
          const Piece& p = pieces[i];
          const Piece& q = pieces[j];
          {
            if (std::abs(p.d.dot(q.d)) < cos_max) return;
            const auto [u0, u1] = projectedExtent(p, q);
            const double gap = std::max(u0 - p.t1, p.t0 - u1);
            if (gap > mo.max_bridge || (gap > mo.merge_gap && !unseenGap(p, u0 > p.t1 ? p.t1 : u1, gap, ctx))) return;
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
      refit(p, cloud, material, ctx);
      if (faced) p.thickness = thick, p.faces_merged = true;
      q.alive = false;
      ++ctx.stats.merges;
      changed = true;
    }
  }
}

namespace {

// Two near-parallel wall faces as one wall's candidates: where they overlap, how far apart.
struct FacePair {
  double sep;      ///< the larger separation at the overlap's two ends [m]
  double lo, hi;   ///< the overlap along p [m]
  double overlap;  ///< [m]
};

// p and q as the two faces of one wall no thicker than `thickness` (solid between them), or up to
// max_two_sided_thickness with free space outside both and as long as structure.
// max_furniture_length at least (a thick wall seen from both sides); std::nullopt for anything
// else (furniture against a wall, a corridor).
std::optional<FacePair> facePair(const Piece& p, const Piece& q, double thickness, const Context& ctx) {
  const double cos_max = std::cos(deg2rad(ctx.opt.wall.merge_angle_deg));
  const double reach = std::max(thickness, ctx.opt.max_two_sided_thickness);
  const double res = ctx.grid.resolution;
  // Free space outside a face: from one and a half cells past its line, away from the other face,
  // out to face_outside_reach (furniture standing against the face hides the room behind it).
  const double outside_reach = std::max(2.5 * res, ctx.opt.face_outside_reach);
  const auto freeOutside = [&](const Vec2& on, const Vec2& away) {
    for (double k = 1.5 * res; k <= outside_reach; k += res)
      if (ctx.isFree(on + k * away)) return true;
    return false;
  };
  if (std::abs(p.d.dot(q.d)) < cos_max) return std::nullopt;
  const auto [u0, u1] = projectedExtent(p, q);
  const double lo = std::max(u0, p.t0), hi = std::min(u1, p.t1);
  const double overlap = hi - lo;
  const double longer = std::max(p.length(), q.length());
  if (overlap < ctx.opt.face_min_overlap * longer) return std::nullopt;
  // The separation where the faces overlap, the larger of its two ends (two lines a few degrees
  // apart are as far apart as they are there, not at some point of q's line).
  const double side = gapAt(p, q, 0.5 * (lo + hi));
  const double sep = std::max(std::abs(gapAt(p, q, lo)), std::abs(gapAt(p, q, hi)));
  if (sep > reach) return std::nullopt;
  const bool thick = sep > thickness;
  // A thick pair as long as furniture is furniture against a wall (its front and the wall's other
  // face, free outside both); a thick wall runs on.
  if (thick && overlap < ctx.opt.structure.max_furniture_length) return std::nullopt;
  // Free cells between the faces: a corridor or a gap, not one wall.
  int free = 0, outside = 0;
  constexpr int kSamples = 9;
  const Vec2 away = side > 0 ? Vec2(-p.normal()) : Vec2(p.normal());  // from q's side to p's
  for (int k = 0; k < kSamples; ++k) {
    const double t = lo + (hi - lo) * (k + 0.5) / kSamples;
    const Vec2 on_p = p.at(t);
    const Vec2 foot = q.foot(on_p);
    if (ctx.isFree(0.5 * (on_p + foot))) ++free;
    if (thick && freeOutside(on_p, away) && freeOutside(foot, -away)) ++outside;
  }
  if (free > ctx.opt.face_max_free_fraction * kSamples) return std::nullopt;
  // At most that share of the samples without free space outside (counted as such, so that 6 of 9
  // is two thirds exactly, not a rounding below it).
  if (thick && kSamples - outside > ctx.opt.face_max_free_fraction * kSamples) return std::nullopt;
  return FacePair{sep, lo, hi, overlap};
}

}  // namespace

double buildingWallThickness(const std::vector<Piece>& pieces, const Context& ctx) {
  const double given = ctx.opt.max_wall_thickness;
  if (ctx.opt.max_two_sided_thickness <= given) return given;
  // The long thick walls seen from both sides, as mergeFaces takes them: separation and overlap.
  std::vector<std::pair<double, double>> walls;
  forNearbyPairs(pieces, ctx.opt.max_two_sided_thickness, [&](std::size_t i, std::size_t j) {
    const std::optional<FacePair> f = facePair(pieces[i], pieces[j], given, ctx);
    if (f && f->sep > given) walls.emplace_back(f->sep, f->overlap);
  });
  if (walls.empty()) return given;
  // Their most common separation (the window holding the most metres of wall), and the walls in
  // that window: the building's thick walls, if they are enough of its walls.
  const auto window = [&](double t) { return std::max(kThicknessWindowCells * ctx.grid.resolution, 0.1 * t); };
  double best = 0.0, best_len = 0.0;
  for (const auto& [t, unused] : walls) {
    double len = 0.0;
    for (const auto& [s, l] : walls)
      if (std::abs(s - t) <= window(t)) len += l;
    if (len > best_len) best = t, best_len = len;
  }
  if (best_len < kThickWallEvidence * ctx.opt.structure.max_furniture_length) return given;
  double thickest = given;
  for (const auto& [s, l] : walls)
    if (std::abs(s - best) <= window(best)) thickest = std::max(thickest, s + ctx.grid.resolution);
  return std::min(thickest, ctx.opt.max_two_sided_thickness);
}

// Wall faces: two near-parallel wall pieces no farther apart than the building's wall thickness
// (ctx.wall_thickness), overlapping over half the longer one, with no free space between them,
// become one centre line, however short (a wall stub between two rooms); up to
// max_two_sided_thickness apart when free space also lies outside both (seen from both sides) and
// they are long.
void mergeFaces(std::vector<Piece>& pieces, const CellCloud& cloud, const Context& ctx) {
  const double wall_thickness = ctx.wall_thickness;
  const double reach = std::max(wall_thickness, ctx.opt.max_two_sided_thickness);
  const double res = ctx.grid.resolution;
  for (bool changed = true; changed;) {
    changed = false;
    struct Candidate {
      double sep;  ///< the larger separation at the overlap's two ends [m]
      double mid;  ///< the overlap's middle along the first piece [m]
      std::size_t i, j;
    };
    std::vector<Candidate> candidates;
    forNearbyPairs(pieces, reach, [&](std::size_t i, std::size_t j) {
      const std::optional<FacePair> f = facePair(pieces[i], pieces[j], wall_thickness, ctx);
      if (f) candidates.push_back({f->sep, 0.5 * (f->lo + f->hi), i, j});
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
      // A face within the band of a wall whose faces merged already (a later pass: the lines
      // joined one face's pieces that the merge left) is part of it: the wall keeps its centre
      // line and thickness and reaches over both.
      const Piece* wall = p.faces_merged != q.faces_merged ? (p.faces_merged ? &p : &q) : nullptr;
      const Piece* face = wall == &p ? &q : &p;
      const bool within = wall && std::abs(wall->normal().dot(face->c - wall->c)) <= 0.5 * (wall->thickness + res);
      Vec2 dq = q.d;
      if (dq.dot(p.d) < 0) dq = -dq;
      const Vec2 d = within ? wall->d : Vec2((p.length() * p.d + q.length() * dq).normalized());
      const Vec2 n(-d.y(), d.x());
      // Midline between the two face lines, through the middle of their overlap, equally weighted
      // whatever their cell counts (or the merged wall's own line).
      const Vec2 on_p = p.at(c.mid);
      const double off = within ? n.dot(wall->c) : 0.5 * n.dot(on_p + q.foot(on_p));
      const double t_lo = std::min({d.dot(p.a()), d.dot(p.b()), d.dot(q.a()), d.dot(q.b())});
      const double t_hi = std::max({d.dot(p.a()), d.dot(p.b()), d.dot(q.a()), d.dot(q.b())});
      const double cap = c.sep > wall_thickness ? reach : wall_thickness;
      const double thickness =
          within ? wall->thickness : std::min(cap, std::max(p.thickness, c.sep + cloud.resolution));
      p.ids.insert(p.ids.end(), q.ids.begin(), q.ids.end());
      p.moments += q.moments;
      p.c = off * n;
      p.d = d;
      p.t0 = t_lo;
      p.t1 = t_hi;
      p.thickness = thickness;
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

}  // namespace glassmap::vector::detail
