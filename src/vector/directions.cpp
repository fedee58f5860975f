// Structure step 1: the building's wall directions, found in the data (any number, at any angle:
// a pentagon has five), and the pieces near one snapped onto it.
#include <algorithm>
#include <cmath>
#include <complex>

#include "glassmap/core/angles.hpp"
#include "structure.hpp"

namespace glassmap::vector::detail {

namespace {

double axial(const Vec2& d) {  // direction of a line in [0, pi)
  double a = std::atan2(d.y(), d.x());
  if (a < 0) a += kPi;
  if (a >= kPi) a -= kPi;
  return a;
}

}  // namespace

// Peaks of the length-weighted histogram of directions (0.5 degree bins on the half circle,
// smoothed with a 1.5 degree Gaussian); a peak needs peak_share of the total and must stand
// direction_separation_deg from a stronger one; each is refined by the circular mean of the pieces
// within a degree of it. Two directions within 2 degrees of a right angle are made exactly
// perpendicular (a building's right angles; the rest is fitting noise), weighted by their length.
std::vector<double> dominantDirections(const std::vector<Piece>& walls, const std::vector<Piece>& glass,
                                       const Context& ctx) {
  const StructureOptions& o = ctx.opt.structure;
  constexpr int kBins = 360;
  const double bin = kPi / kBins;
  std::vector<double> hist(kBins, 0.0), smooth(kBins, 0.0);
  double total = 0.0;
  const auto add = [&](const Piece& p) {
    const double len = p.length();
    hist[static_cast<std::size_t>(std::min(kBins - 1, static_cast<int>(axial(p.d) / bin)))] += len;
    total += len;
  };
  for (const Piece& p : walls) add(p);
  for (const Piece& p : glass) add(p);
  if (total <= 0) return {};
  const double sigma = deg2rad(1.5) / bin;
  const int reach = static_cast<int>(std::ceil(3 * sigma));
  for (int i = 0; i < kBins; ++i)
    for (int k = -reach; k <= reach; ++k)
      smooth[i] +=
          hist[static_cast<std::size_t>(((i + k) % kBins + kBins) % kBins)] * std::exp(-0.5 * k * k / (sigma * sigma));
  std::vector<std::pair<double, int>> peaks;
  for (int i = 0; i < kBins; ++i) {
    const double v = smooth[i], l = smooth[(i + kBins - 1) % kBins], r = smooth[(i + 1) % kBins];
    if (v > l && v >= r) peaks.push_back({v, i});
  }
  std::sort(peaks.rbegin(), peaks.rend());
  // A single piece's weight stays whole at its peak (the kernel is 1 at its centre): the peak's
  // height over the total is the share of the wall length in that direction.
  std::vector<double> out, weight;
  for (const auto& [v, i] : peaks) {
    if (v / total < o.peak_share) break;
    const double a = (i + 0.5) * bin;
    bool near = false;
    for (const double b : out)
      near = near || std::abs(std::remainder(a - b, kPi)) < deg2rad(o.direction_separation_deg);
    if (near) continue;
    // The mode near the peak: the piece direction with the most length within a degree of it
    // (within half the separation of the peak), then the circular mean of those pieces.
    const auto lengthNear = [&](double dir, double window) {
      std::complex<double> sum = 0;
      for (const std::vector<Piece>* set : {&walls, &glass})
        for (const Piece& p : *set)
          if (std::abs(std::remainder(axial(p.d) - dir, kPi)) <= window)
            sum += p.length() * std::polar(1.0, 2 * axial(p.d));
      return sum;
    };
    double mode = a, mode_len = -1;
    for (const std::vector<Piece>* set : {&walls, &glass})
      for (const Piece& p : *set) {
        if (std::abs(std::remainder(axial(p.d) - a, kPi)) > 0.5 * deg2rad(o.direction_separation_deg)) continue;
        double len = 0;
        for (const std::vector<Piece>* other : {&walls, &glass})
          for (const Piece& q : *other)
            if (std::abs(std::remainder(axial(q.d) - axial(p.d), kPi)) <= deg2rad(1.0)) len += q.length();
        if (len > mode_len) mode_len = len, mode = axial(p.d);
      }
    const std::complex<double> s = lengthNear(mode, deg2rad(1.0));
    double refined = std::abs(s) > 0 ? 0.5 * std::arg(s) : mode;
    if (refined < 0) refined += kPi;
    out.push_back(refined);
    weight.push_back(v);
  }
  for (std::size_t i = 0; i < out.size(); ++i)
    for (std::size_t j = i + 1; j < out.size(); ++j) {
      const double off = std::remainder(out[j] - out[i] - 0.5 * kPi, kPi);  // j - (i + 90 deg)
      if (std::abs(off) > deg2rad(2.0)) continue;
      const double wi = weight[i], wj = weight[j];
      out[i] += off * wj / (wi + wj);
      out[j] -= off * wi / (wi + wj);
      for (double* d : {&out[i], &out[j]}) *d = std::fmod(std::fmod(*d, kPi) + kPi, kPi);
    }
  return out;
}

std::vector<int> snapToDirections(std::vector<Piece>& pieces, const std::vector<double>& directions,
                                  const Context& ctx) {
  const StructureOptions& o = ctx.opt.structure;
  std::vector<int> which(pieces.size(), -1);
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    Piece& p = pieces[k];
    const double a = axial(p.d);
    const double len = std::max(p.length(), ctx.grid.resolution);
    const double tol = std::clamp(std::atan(2.0 * ctx.grid.resolution / len), deg2rad(2.0), deg2rad(o.snap_max_deg));
    double best = tol;
    for (std::size_t i = 0; i < directions.size(); ++i) {
      const double delta = std::abs(std::remainder(a - directions[i], kPi));
      if (delta <= best) best = delta, which[k] = static_cast<int>(i);
    }
    if (which[k] < 0) continue;
    const double target = directions[static_cast<std::size_t>(which[k])];
    const Vec2 mid = 0.5 * (p.a() + p.b());
    const double half = 0.5 * p.length();
    p.d = Vec2(std::cos(target), std::sin(target));
    p.c = mid;
    p.t0 = -half;
    p.t1 = half;
  }
  return which;
}

}  // namespace glassmap::vector::detail
