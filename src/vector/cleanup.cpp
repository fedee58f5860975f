// Step 5 of vectorize(): plan cleanup. One-sided walls move onto their observed face, near-axis
// segments snap to the floor's dominant axes, segment ends close corners and T junctions.
#include "piece.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <vector>

#include "box_pairs.hpp"
#include "glassmap/core/angles.hpp"

namespace glassmap::vector::detail {

// The floor's dominant wall direction modulo 90 degrees: the direction with the most wall length
// within axis_window_deg (1 degree; on the 4-fold circle, so 0 and 90 degrees count together),
// refined by the length-weighted circular mean of those walls.
double dominantAxis(const std::vector<Piece>& walls, const Context& ctx) {
  const double window = deg2rad(ctx.opt.axis_window_deg);
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

// Whether the stretch from a pane's end towards where it would move runs over occupied cells for
// half its length or more (its line runs on as a wall, or into one): the pane then ends there
// already. The stretch stops `short_of` before the target, where the target wall's own band begins.
bool overOccupied(const Vec2& from, const Vec2& to, double short_of, const Context& ctx) {
  const double res = ctx.grid.resolution;
  const double length = (to - from).norm() - short_of;
  if (length <= res) return false;
  const Vec2 d = (to - from).normalized();
  int samples = 0, occupied = 0;
  for (double t = 0.5 * res; t < length; t += 0.5 * res, ++samples)
    occupied += ctx.codeAt(from + t * d) == kCodeOccupied;
  return 2 * occupied >= samples;
}

// Closes corners and T junctions: a segment end within corner_snap of the intersection of its
// line with a wall's line (crossing at corner_min_angle_deg or more, the intersection on or near
// that wall) moves to the intersection. Glass ends snap to walls (within glass_corner_snap), wall
// ends to walls.
void snapCorners(std::vector<Piece>& glass, std::vector<Piece>& walls, const Context& ctx) {
  const double snap = ctx.opt.corner_snap;
  const double glass_snap = ctx.glassCornerSnap();
  const double sin_min = std::sin(deg2rad(ctx.opt.corner_min_angle_deg));
  // Only pieces long enough to be walls (or panes) of the plan take part; clutter stays apart.
  const double min_len = 2.0 * snap;
  struct End {
    Piece* piece;
    bool end;              // false: t0, true: t1
    std::size_t own_wall;  // the piece's own index among the walls, or walls.size() for a pane
  };
  std::vector<End> ends;
  std::vector<Vec2> points;
  auto addEnds = [&](Piece& p, std::size_t own) {
    if (p.length() < min_len) return;
    for (int e = 0; e < 2; ++e) {
      ends.push_back({&p, e == 1, own});
      points.push_back(e == 0 ? p.a() : p.b());
    }
  };
  for (std::size_t k = 0; k < walls.size(); ++k) addEnds(walls[k], k);
  for (Piece& g : glass) addEnds(g, walls.size());
  // A wall whose intersection can move an end lies within the end's snap plus snap of it (the
  // intersection is within the end's snap of the end and within snap of the wall): walls' boxes
  // grown by glass_snap + snap hold those ends.
  std::vector<Eigen::AlignedBox2d> boxes(walls.size());
  for (std::size_t k = 0; k < walls.size(); ++k) {
    if (walls[k].length() < min_len) continue;
    boxes[k].extend(walls[k].a().cwiseMin(walls[k].b()) - Vec2::Constant(glass_snap + snap));
    boxes[k].extend(walls[k].a().cwiseMax(walls[k].b()) + Vec2::Constant(glass_snap + snap));
  }
  struct Move {
    Piece* piece;
    bool end;
    double t;
  };
  std::vector<Move> moves;
  const auto pairs = pointsInBoxes(points, boxes);  // sorted by end, then by wall
  for (std::size_t first = 0; first < pairs.size();) {
    const std::size_t e = pairs[first].first;
    std::size_t last = first;
    while (last < pairs.size() && pairs[last].first == e) ++last;
    const End& end_info = ends[e];
    Piece& p = *end_info.piece;
    const Vec2 end = points[e];
    const bool pane = end_info.own_wall == walls.size();
    double best = pane ? glass_snap : snap, best_t = 0;
    bool found = false;
    for (std::size_t m = first; m < last; ++m) {
      const std::size_t k = pairs[m].second;
      if (k == end_info.own_wall) continue;
      const Piece& w = walls[k];
      const double cross = p.d.x() * w.d.y() - p.d.y() * w.d.x();
      if (std::abs(cross) < sin_min) continue;
      // p.c + t p.d = w.c + s w.d
      const Vec2 diff = w.c - p.c;
      const double t = (diff.x() * w.d.y() - diff.y() * w.d.x()) / cross;
      const double s = (diff.x() * p.d.y() - diff.y() * p.d.x()) / cross;
      const Vec2 x = p.at(t);
      const double dist = (x - end).norm();
      if (dist >= best || s < w.t0 - snap || s > w.t1 + snap) continue;
      // Never flip or halve the segment.
      const double len = end_info.end ? t - p.t0 : p.t1 - t;
      if (len < 0.5 * p.length()) continue;
      // A pane whose line runs on as a wall ends in that wall: it does not grow over it.
      if (pane && overOccupied(end, x, 0.5 * w.thickness / std::abs(cross) + ctx.grid.resolution, ctx)) continue;
      best = dist;
      best_t = t;
      found = true;
    }
    if (found) moves.push_back({&p, end_info.end, best_t});
    first = last;
  }
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
  const double res = ctx.grid.resolution;
  const auto freeAt = [&](const Vec2& p) { return ctx.isFree(p); };
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
    if (hi < stations || lo > ctx.opt.one_sided_max_ratio * hi) continue;  // unseen, or free on both sides
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
}  // namespace glassmap::vector::detail
