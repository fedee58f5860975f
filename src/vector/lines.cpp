// Structure step 2: collinear pieces become wall lines (ROSE^2's idea: a wall runs on through
// rooms and behind furniture), and each gap along a line is bridged or kept open by what it
// costs to claim it as wall: cells seen free cost much (a door, a passage), cells hidden behind
// clutter little, cells hit nothing. A gap is bridged when that costs less than the segment it
// saves (0.5 ln N per parameter, N wall cells): a plan-wide description length, not a per-piece rule.
#include <algorithm>
#include <cmath>
#include <limits>

#include "glassmap/core/angles.hpp"
#include "structure.hpp"

namespace glassmap::vector::detail {

Seen seenAt(const Vec2& p, const Vec2& n, const Context& ctx) {
  const double res = ctx.grid.resolution;
  const std::uint8_t c0 = ctx.codeAt(p), c1 = ctx.codeAt(p + res * n), c2 = ctx.codeAt(p - res * n);
  if (isGlassCode(c0) || isGlassCode(c1) || isGlassCode(c2)) return Seen::Glass;
  if (isWallCode(c0) || isWallCode(c1) || isWallCode(c2)) return Seen::Hit;
  if (c1 == kCodeEmpty && c2 == kCodeEmpty) return Seen::Free;
  const double depth = ctx.opt.structure.occlusion_depth;
  for (double s = res; s <= depth; s += res)
    if (ctx.isFree(p + s * n) || ctx.isFree(p - s * n)) return Seen::Occluded;
  return Seen::Unseen;
}

namespace {

double axialAngle(const Vec2& d) {
  double a = std::atan2(d.y(), d.x());
  return a < 0 ? a + kPi : a;
}

}  // namespace

std::vector<WallLine> groupLines(const std::vector<Piece>& walls, const std::vector<int>& direction,
                                 const std::vector<double>& directions, const Context& ctx) {
  const double tol = ctx.opt.structure.line_tolerance;
  std::vector<std::size_t> order(walls.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return walls[a].length() > walls[b].length(); });
  std::vector<WallLine> lines;
  for (const std::size_t i : order) {
    const Piece& p = walls[i];
    const int k = direction[i];
    const Vec2 d = k >= 0 ? Vec2(std::cos(directions[static_cast<std::size_t>(k)]),
                                 std::sin(directions[static_cast<std::size_t>(k)]))
                          : p.d;
    WallLine* best = nullptr;
    double best_off = tol;
    for (WallLine& l : lines) {
      if (l.direction != k) continue;
      if (k < 0 && std::abs(std::remainder(axialAngle(l.d) - axialAngle(p.d), kPi)) > deg2rad(2.0)) continue;
      const Vec2 mid = 0.5 * (p.a() + p.b());
      const double off = std::abs(l.normal().dot(mid) - l.offset);
      if (off <= best_off) best_off = off, best = &l;
    }
    const Vec2 mid = 0.5 * (p.a() + p.b());
    if (!best) {
      WallLine l;
      l.d = d.x() < -1e-12 || (std::abs(d.x()) <= 1e-12 && d.y() < 0) ? Vec2(-d) : d;
      l.direction = k;
      l.offset = l.normal().dot(mid);
      lines.push_back(l);
      best = &lines.back();
    } else {
      best->offset =
          (best->support * best->offset + p.length() * best->normal().dot(mid)) / (best->support + p.length());
    }
    best->members.push_back(i);
    best->support += p.length();
  }
  return lines;
}

namespace {

// A run of the gap's samples [first, last) of one kind.
struct Interval {
  double t0, t1;
  std::vector<std::size_t> members;
};

double sampleCost(Seen s, const StructureOptions& o) {
  switch (s) {
    case Seen::Hit: return -o.hit_gain;
    case Seen::Glass: return std::numeric_limits<double>::infinity();
    case Seen::Free: return o.free_cost;
    case Seen::Occluded: return o.occluded_cost;
    case Seen::Unseen: return o.unseen_cost;
  }
  return 0.0;
}

// A door: free space on both sides of the opening, beyond the wall's half thickness, at most
// samples along it.
bool isPassage(const WallLine& l, double t0, double t1, double half_thickness, const Context& ctx) {
  const Vec2 n = l.normal();
  int both = 0, samples = 0;
  for (double t = t0 + 0.1; t < t1 - 0.1 + 1e-9; t += ctx.grid.resolution) {
    const Vec2 p = l.offset * n + t * l.d;
    const double depth = half_thickness + 0.3;
    ++samples;
    both += ctx.isFree(p + depth * n) && ctx.isFree(p - depth * n);
  }
  return samples > 0 && 2 * both >= samples;
}

// Positions along l, strictly between t0 and t1, where a wall piece runs through the line: it
// crosses it at corner_min_angle_deg or more with both ends at least 0.2 m off it.
std::vector<double> crossingsOf(const WallLine& l, double t0, double t1, const std::vector<Piece>& walls) {
  std::vector<double> out;
  const Vec2 n = l.normal();
  for (const Piece& q : walls) {
    if (std::abs(q.d.dot(l.d)) > std::cos(deg2rad(30.0))) continue;
    const double sa = n.dot(q.a()) - l.offset, sb = n.dot(q.b()) - l.offset;
    if (sa * sb >= 0 || std::min(std::abs(sa), std::abs(sb)) < 0.2) continue;
    const Vec2 x = q.a() + sa / (sa - sb) * (q.b() - q.a());
    const double t = l.d.dot(x);
    if (t > t0 && t < t1) out.push_back(t);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// The ends (along l, within t0 .. t1) of panes lying on the line (within 0.2 m of it, at most
// 10 degrees off it): a pane fills that part of a gap, so it is neither bridged nor left open.
std::vector<double> panesOn(const WallLine& l, double t0, double t1, const std::vector<Piece>& glass) {
  std::vector<double> out;
  const Vec2 n = l.normal();
  for (const Piece& g : glass) {
    if (std::abs(g.d.dot(l.d)) < std::cos(deg2rad(10.0))) continue;
    if (std::abs(n.dot(g.a()) - l.offset) > 0.2 || std::abs(n.dot(g.b()) - l.offset) > 0.2) continue;
    const double u = l.d.dot(g.a()), v = l.d.dot(g.b());
    if (std::max(u, v) <= t0 || std::min(u, v) >= t1) continue;
    out.push_back(std::clamp(std::min(u, v), t0, t1));
    out.push_back(std::clamp(std::max(u, v), t0, t1));
  }
  return out;
}

}  // namespace

std::vector<Piece> joinLines(const std::vector<WallLine>& lines, const std::vector<Piece>& walls,
                             const std::vector<Piece>& glass, const CellCloud& cloud, const Context& ctx,
                             std::vector<std::size_t>& line_of, Structure& out) {
  const StructureOptions& o = ctx.opt.structure;
  const double res = ctx.grid.resolution;
  const double segment_cost = std::log(std::max<double>(2.0, static_cast<double>(cloud.points.size())));
  std::vector<Piece> joined;
  line_of.clear();
  for (std::size_t li = 0; li < lines.size(); ++li) {
    const WallLine& l = lines[li];
    const Vec2 n = l.normal();
    std::vector<Interval> iv;
    double half_thickness = 0.0;
    for (const std::size_t m : l.members) {
      const Piece& p = walls[m];
      const double u = l.d.dot(p.a()), v = l.d.dot(p.b());
      iv.push_back({std::min(u, v), std::max(u, v), {m}});
      half_thickness = std::max(half_thickness, 0.5 * p.thickness);
    }
    std::sort(iv.begin(), iv.end(), [](const Interval& a, const Interval& b) { return a.t0 < b.t0; });
    std::vector<Interval> merged;
    for (Interval& i : iv) {
      if (!merged.empty() && i.t0 <= merged.back().t1 + res) {
        merged.back().t1 = std::max(merged.back().t1, i.t1);
        merged.back().members.insert(merged.back().members.end(), i.members.begin(), i.members.end());
      } else {
        merged.push_back(std::move(i));
      }
    }
    // Gaps, left to right: bridge, or keep open (recording the openings), extending the walls to
    // the jambs where the stretch up to them is cheap to claim.
    std::vector<Interval> final;
    for (Interval& next : merged) {
      if (final.empty()) {
        final.push_back(std::move(next));
        continue;
      }
      Interval& cur = final.back();
      const double gap = next.t0 - cur.t1;
      const int count = std::max(0, static_cast<int>(std::floor(gap / res)));
      std::vector<Seen> seen(static_cast<std::size_t>(count));
      for (int j = 0; j < count; ++j)
        seen[static_cast<std::size_t>(j)] = seenAt(l.offset * n + (cur.t1 + (j + 0.5) * gap / count) * l.d, n, ctx);
      if (count == 0) {  // less than a cell apart: one wall
        cur.t1 = std::max(cur.t1, next.t1);
        cur.members.insert(cur.members.end(), next.members.begin(), next.members.end());
        continue;
      }
      const double step = gap / count;
      const auto cost = [&](int a, int b) {
        double c = 0;
        for (int j = a; j < b; ++j) c += sampleCost(seen[static_cast<std::size_t>(j)], o);
        return c;
      };
      // Runs seen free in samples [a, b), at least two samples long.
      const auto freeRuns = [&](int a, int b) {
        std::vector<std::pair<int, int>> runs;
        for (int j = a; j < b;) {
          if (seen[static_cast<std::size_t>(j)] != Seen::Free) {
            ++j;
            continue;
          }
          int e = j;
          while (e < b && seen[static_cast<std::size_t>(e)] == Seen::Free) ++e;
          if (e - j >= 2) runs.push_back({j, e});
          j = e;
        }
        return runs;
      };
      // Walls running through the gap (a corridor's walls where this line crosses it): the gap is a
      // junction, never bridged; only its stretches up to the first and from the last crossing
      // belong to this line's walls.
      std::vector<double> crossings = crossingsOf(l, cur.t1, next.t0, walls);
      for (const double t : panesOn(l, cur.t1, next.t0, glass)) crossings.push_back(t);
      std::sort(crossings.begin(), crossings.end());
      const int left_end =
          crossings.empty() ? count : std::clamp(static_cast<int>((crossings.front() - cur.t1) / step), 0, count);
      const int right_begin =
          crossings.empty() ? count
                            : std::clamp(static_cast<int>(std::ceil((crossings.back() - cur.t1) / step)), 0, count);
      if (crossings.empty() && freeRuns(0, count).empty() && cost(0, count) < segment_cost) {
        cur.t1 = next.t1;
        cur.members.insert(cur.members.end(), next.members.begin(), next.members.end());
        ++out.bridged;
        continue;
      }
      const double g0 = cur.t1;
      std::vector<std::pair<int, int>> runs = freeRuns(0, left_end);
      if (!crossings.empty())
        for (const auto& r : freeRuns(right_begin, count)) runs.push_back(r);
      // The walls reach on to the first opening (or crossing) and back from the last when the
      // stretch is cheap to claim.
      const int first = runs.empty() || runs.front().first >= left_end ? left_end : runs.front().first;
      int last = crossings.empty() ? count : right_begin;
      if (!runs.empty() && runs.back().second > (crossings.empty() ? 0 : right_begin)) last = runs.back().second;
      if (cost(0, first) < segment_cost) cur.t1 = g0 + first * step;
      if (last < count && cost(last, count) < segment_cost) next.t0 = g0 + last * step;
      for (const auto& [a, b] : runs) {
        const double t0 = g0 + a * step, t1 = g0 + b * step;
        Opening op;
        op.a = l.offset * n + t0 * l.d;
        op.b = l.offset * n + t1 * l.d;
        const double w = t1 - t0;
        op.door = w >= o.door_min && w <= o.door_max && isPassage(l, t0, t1, half_thickness, ctx);
        op.left = joined.size() + final.size() - 1;  // cur, once the line's pieces are appended
        op.right = op.left + 1;
        out.openings.push_back(op);
      }
      final.push_back(std::move(next));
    }
    for (Interval& i : final) {
      Piece p;
      p.d = l.d;
      p.c = l.offset * n;
      p.t0 = i.t0;
      p.t1 = i.t1;
      for (const std::size_t m : i.members) {
        const Piece& q = walls[m];
        p.parts.push_back(static_cast<std::uint32_t>(m));
        p.ids.insert(p.ids.end(), q.ids.begin(), q.ids.end());
        p.moments += q.moments;
        p.thickness = std::max(p.thickness, q.thickness);
        p.faces_merged = p.faces_merged || q.faces_merged;
      }
      joined.push_back(std::move(p));
      line_of.push_back(li);
    }
  }
  out.lines = lines.size();
  return joined;
}

}  // namespace glassmap::vector::detail
