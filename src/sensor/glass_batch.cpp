// GlassModel::logLikelihoods: the beams of many particles at once. The rays go to
// RayCaster::castBatch in rounds (first surfaces; then the mirrored and the transmitted rays of
// the beams that met a pane; then the transmitted rays that met another pane), and every
// probability is made of the same pieces as the one-ray path (weights, mirrored, transmitted,
// goesOn, fromModes, Mixture; the walls' mixture on SIMD lanes, equal up to float rounding), and the
// one-pose call is this call for one pose.
#include <algorithm>
#include <cmath>
#include <vector>

#include "glassmap/sensor/glass_model.hpp"
#include "mixture_pick.hpp"

namespace glassmap::sensor {
namespace {

constexpr double kNegligible = 1e-4;  // as in glass_model.cpp: a mode below it casts no ray
constexpr std::size_t kBlock = 256;   // poses per round of casts (a beam of them: one coherent group)

// Rays for castBatch, structure of arrays, with the results.
struct Rays {
  std::vector<double> ox, oy, ux, uy, max_range, range;
  std::vector<std::int32_t> skip, segment;
  std::vector<std::uint32_t> owner;  // the beam (ray of the first round) a ray belongs to
  std::vector<std::uint32_t> group;  // its beam index: rays of one beam and pane form a group
  void clear() {
    ox.clear();
    oy.clear();
    ux.clear();
    uy.clear();
    max_range.clear();
    skip.clear();
    owner.clear();
    group.clear();
  }
  void add(const Vec2& o, const Vec2& d, double m, std::int32_t s, std::uint32_t who, std::uint32_t beam) {
    group.push_back(beam);
    ox.push_back(o.x());
    oy.push_back(o.y());
    ux.push_back(d.x());
    uy.push_back(d.y());
    max_range.push_back(m);
    skip.push_back(s);
    owner.push_back(who);
  }
  std::size_t size() const { return ox.size(); }
  // Casts them in coherent groups: consecutive rays of one beam that start on the same pane (skip).
  void cast(const RayCaster& caster) {
    range.resize(size());
    segment.resize(size());
    ends.clear();
    for (std::size_t r = 1; r < size(); ++r)
      if (group[r] != group[r - 1] || skip[r] != skip[r - 1]) ends.push_back(r);
    if (size() > 0) ends.push_back(size());
    RayBatch b;
    b.ox = ox.data();
    b.oy = oy.data();
    b.ux = ux.data();
    b.uy = uy.data();
    b.max_range = max_range.data();
    b.skip = skip.data();
    b.size = size();
    caster.castGroups(b, ends.data(), ends.size(), range.data(), segment.data());
  }
  std::vector<std::size_t> ends;
};

struct Scratch {
  std::vector<double> ox, oy, ux, uy, range, p, short_num;
  std::vector<std::size_t> ends;
  std::vector<std::uint8_t> fix;
  std::vector<std::int32_t> segment;
  std::vector<GlassModes> modes;
  std::vector<std::uint32_t> glass;  // beams whose first surface is a pane
  std::vector<std::uint32_t> order;  // one beam's rays that met a pane, by pane
  Rays mirror, through, next;
};

}  // namespace

void GlassModel::logLikelihoods(std::span<const Pose2> poses, const BeamSet& beams, double* out) const {
  thread_local Scratch s;
  thread_local std::vector<Transmitted> walks, going;  // aligned with s.through / s.next
  const std::size_t nb = beams.size();
  const double max_range = beams.max_range;
  const auto& segments = caster_.map().segments;
  static const detail::MixtureLanesFn lanes_fn = detail::mixtureLanes();
  s.short_num.resize(nb);
  for (std::size_t i = 0; i < nb; ++i)
    s.short_num[i] = beams.ranges[i] < max_range ? mix_.shortNumerator(beams.ranges[i]) : 0.0;
  for (std::size_t j0 = 0; j0 < poses.size(); j0 += kBlock) {
    const std::size_t n = std::min(kBlock, poses.size() - j0);
    const std::size_t nr = n * nb;  // ray k = i * n + j: beam i, pose j0 + j (one beam's rays together)
    s.ox.resize(nr);
    s.oy.resize(nr);
    s.ux.resize(nr);
    s.uy.resize(nr);
    s.range.resize(nr);
    s.segment.resize(nr);
    s.p.resize(nr);
    s.ends.resize(nb);
    for (std::size_t j = 0; j < n; ++j) {
      const Pose2& T = poses[j0 + j];
      const Eigen::Matrix2d R = T.rotation();
      for (std::size_t i = 0; i < nb; ++i) {
        const Vec2 dir(R * beams.dirs[i]);  // as sumLogProbabilities computes it
        const std::size_t k = i * n + j;
        s.ox[k] = T.t.x();
        s.oy[k] = T.t.y();
        s.ux[k] = dir.x();
        s.uy[k] = dir.y();
      }
    }
    for (std::size_t i = 0; i < nb; ++i) s.ends[i] = (i + 1) * n;
    RayBatch first;
    first.ox = s.ox.data();
    first.oy = s.oy.data();
    first.ux = s.ux.data();
    first.uy = s.uy.data();
    first.range = max_range;
    first.size = nr;
    // One beam of a particle cloud: a coherent group, one sweep of the grid for all its rays.
    caster_.castGroups(first, s.ends.data(), nb, s.range.data(), s.segment.data());

    // Beams that met a pane: their modes, and the mirrored and transmitted rays they need.
    s.glass.clear();
    s.modes.resize(nr);
    s.mirror.clear();
    s.through.clear();
    walks.clear();
    for (std::size_t i = 0; i < nb; ++i) {
      // This beam's rays that met a pane, pane by pane (the secondary rays of one pane and beam
      // form a coherent group: origins along the pane, nearly one direction).
      s.order.clear();
      for (std::size_t k = i * n; k < (i + 1) * n; ++k) {
        const std::int32_t seg = s.segment[k];
        if (seg >= 0 && segments[static_cast<std::size_t>(seg)].material == Material::Glass)
          s.order.push_back(static_cast<std::uint32_t>(k));
      }
      std::stable_sort(s.order.begin(), s.order.end(),
                       [&](std::uint32_t a, std::uint32_t b) { return s.segment[a] < s.segment[b]; });
      for (const std::uint32_t k : s.order) {
        const std::int32_t seg = s.segment[k];
        const Vec2 o(s.ox[k], s.oy[k]), dir(s.ux[k], s.uy[k]);
        RayHit hit;
        hit.range = s.range[k];
        hit.segment = seg;
        hit.material = Material::Glass;
        hit.incidence = caster_.incidence(seg, dir);
        GlassModes& m = s.modes[k];
        m = weights(hit);
        const Vec2 p = o + hit.range * dir;
        const auto who = static_cast<std::uint32_t>(k);
        if (m.w_normal > kNegligible)
          s.mirror.add(p, mirrored(seg, dir), max_range - m.d_g, seg, who, static_cast<std::uint32_t>(i));
        if (m.w_refract > kNegligible && params_.max_panes >= 1) {
          walks.push_back(transmitted(m, hit, p, dir));
          s.through.add(walks.back().o, dir, max_range - walks.back().travelled, walks.back().skip, who,
                        static_cast<std::uint32_t>(i));
        }
        s.glass.push_back(who);
      }
    }
    s.mirror.cast(caster_);
    for (std::size_t r = 0; r < s.mirror.size(); ++r) {
      GlassModes& m = s.modes[s.mirror.owner[r]];
      m.e_normal = m.d_g + s.mirror.range[r];  // +inf when the mirrored ray meets nothing
    }
    // The transmitted rays, one pane further per round.
    while (s.through.size() > 0) {
      s.through.cast(caster_);
      s.next.clear();
      going.clear();
      for (std::size_t r = 0; r < s.through.size(); ++r) {
        const std::uint32_t k = s.through.owner[r];
        const Vec2 dir(s.ux[k], s.uy[k]);
        RayHit next;
        next.range = s.through.range[r];
        next.segment = s.through.segment[r];
        if (next.segment >= 0) next.material = segments[static_cast<std::size_t>(next.segment)].material;
        Transmitted& t = walks[r];
        if (goesOn(t, next, dir, s.modes[k].e_refract)) {
          s.next.add(t.o, dir, max_range - t.travelled, t.skip, k, s.through.group[r]);
          going.push_back(t);
        }
      }
      std::swap(s.through, s.next);
      walks.swap(going);
    }

    // Probabilities (a beam's wall and no-hit rays on SIMD lanes when the CPU has them), then
    // each pose's sum of logs as sumLogProbabilities forms it.
    s.fix.resize(nr);
    for (std::size_t i = 0; i < nb; ++i) {
      const double z = beams.ranges[i], short_num = s.short_num[i];
      const bool lanes = lanes_fn && z < max_range;
      if (lanes)
        lanes_fn(detail::lanesFor(mix_, z, max_range, short_num), &s.range[i * n], &s.p[i * n], &s.fix[i * n], n);
      for (std::size_t k = i * n; k < (i + 1) * n; ++k) {
        const std::int32_t seg = s.segment[k];
        if (seg >= 0 && segments[static_cast<std::size_t>(seg)].material == Material::Glass)
          s.p[k] = fromModes(s.modes[k], z, max_range, short_num);
        else if (!lanes || s.fix[k])
          s.p[k] = mix_.probability(z, s.range[k], max_range, short_num);
      }
    }
    for (std::size_t j = 0; j < n; ++j) {
      double sum = 0.0, block = 1.0;
      for (std::size_t i = 0; i < nb; ++i) {
        block *= s.p[i * n + j];
        if ((i & 7) == 7) {
          sum += std::log(block);
          block = 1.0;
        }
      }
      out[j0 + j] = sum + std::log(block);
    }
  }
}

}  // namespace glassmap::sensor
