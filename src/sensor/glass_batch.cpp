// GlassModel::logLikelihoods: the beams of many particles at once. The rays go to
// RayCaster::castGroups in rounds (first surfaces; then the mirrored and the transmitted rays of
// the beams that met a pane; then the transmitted rays that met another pane), and every
// probability is made of the same pieces as the one-ray path (weights, mirrored, transmitted,
// goesOn, fromModes, Mixture). Where the CPU has SIMD lanes, the walls' mixture, the pane hits'
// weights and their modes' densities run on them (mixture_lanes.hpp: the same formulas, libmvec's
// atan, exp and expm1 within 4 ulp of the scalar ones), each ray's result independent of the rays
// that come with it, so the one-pose call is this call for one pose, bit for bit.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "glassmap/sensor/glass_model.hpp"
#include "mixture_pick.hpp"

namespace glassmap::sensor {
namespace {

constexpr double kNegligible = 1e-4;  // as in glass_model.cpp: a mode below it casts no ray
constexpr std::size_t kBlock = 256;   // poses per round of casts (a beam of them: one coherent group)
constexpr double kInf = std::numeric_limits<double>::infinity();

// Rays for castGroups, structure of arrays, with the results; filled up to a capacity set once
// per round (no push_back in the loops).
struct Rays {
  std::vector<double> ox, oy, ux, uy, max_range, range;
  std::vector<std::int32_t> skip, segment;
  std::vector<std::uint32_t> owner;  // the pane hit (index into Hits) a ray belongs to
  std::vector<std::uint32_t> group;  // its beam index: rays of one beam and pane form a group
  std::vector<std::size_t> ends;
  std::size_t n = 0;
  void reset(std::size_t capacity) {
    n = 0;
    if (ox.size() >= capacity) return;
    for (auto* v : {&ox, &oy, &ux, &uy, &max_range, &range}) v->resize(capacity);
    for (auto* v : {&skip, &segment}) v->resize(capacity);
    owner.resize(capacity);
    group.resize(capacity);
  }
  void add(const Vec2& o, const Vec2& d, double m, std::int32_t s, std::uint32_t who, std::uint32_t beam) {
    ox[n] = o.x();
    oy[n] = o.y();
    ux[n] = d.x();
    uy[n] = d.y();
    max_range[n] = m;
    skip[n] = s;
    owner[n] = who;
    group[n] = beam;
    ++n;
  }
  std::size_t size() const { return n; }
  // Casts them in coherent groups: consecutive rays of one beam that start on the same pane (skip).
  void cast(const RayCaster& caster) {
    ends.clear();
    for (std::size_t r = 1; r < n; ++r)
      if (group[r] != group[r - 1] || skip[r] != skip[r - 1]) ends.push_back(r);
    if (n > 0) ends.push_back(n);
    RayBatch b;
    b.ox = ox.data();
    b.oy = oy.data();
    b.ux = ux.data();
    b.uy = uy.data();
    b.max_range = max_range.data();
    b.skip = skip.data();
    b.size = n;
    caster.castGroups(b, ends.data(), ends.size(), range.data(), segment.data());
  }
};

// The rays that met a pane first, beam by beam and within a beam pane by pane, structure of
// arrays padded for the lanes (detail::kGlassPad).
struct Hits {
  std::vector<std::uint32_t> ray;  // index of the first-round ray
  std::vector<std::int32_t> pane;
  std::vector<double> ux, uy, dx, dy, dg, theta, wd, wn, wr, en, er, p;
  std::vector<std::uint8_t> fix;
  std::vector<std::size_t> beam_start;  // hits of beam i: [beam_start[i], beam_start[i + 1])
  std::size_t n = 0;
  void reset(std::size_t capacity) {
    n = 0;
    const std::size_t padded = capacity + detail::kGlassPad;
    if (ray.size() >= padded) return;
    ray.resize(padded);
    pane.resize(padded);
    for (auto* v : {&ux, &uy, &dx, &dy, &dg, &theta, &wd, &wn, &wr, &en, &er, &p}) v->resize(padded);
    fix.resize(padded);
  }
  // Finite numbers in the padding after the last hit (the lanes read it; results ignored).
  void pad() {
    for (std::size_t g = n; g < n + detail::kGlassPad; ++g) {
      ux[g] = dy[g] = dg[g] = wd[g] = 1.0;
      uy[g] = dx[g] = wn[g] = wr[g] = 0.0;
      en[g] = er[g] = kInf;
    }
  }
};

struct Scratch {
  std::vector<double> ox, oy, ux, uy, range, p, short_num, sum, block;
  std::vector<std::size_t> ends;
  std::vector<std::uint8_t> fix, on_pane;  // per first-round ray: mixture left to the scalar path; met a pane
  std::vector<std::int32_t> segment;
  std::vector<std::uint32_t> order;  // one beam's rays that met a pane, by pane
  Hits hits;
  Rays mirror, through, next;
};

}  // namespace

void GlassModel::logLikelihoods(std::span<const Pose2> poses, const BeamSet& beams, double* out) const {
  thread_local Scratch s;
  thread_local std::vector<Transmitted> walks, going;  // aligned with s.through / s.next
  const std::size_t nb = beams.size();
  const double max_range = beams.max_range;
  static const detail::MixtureLanesFn lanes_fn = detail::mixtureLanes();
  static const detail::GlassWeightsFn weights_fn = detail::glassWeightsLanes();
  static const detail::GlassModesFn modes_fn = detail::glassModesLanes();
  detail::GlassWeightLanes wl;
  wl.two_sigma2 = 2.0 * params_.direct_sigma_deg * params_.direct_sigma_deg;
  wl.direct_floor = params_.direct_floor;
  wl.direct_span = params_.direct_peak - params_.direct_floor;
  wl.normal_floor = params_.normal_floor;
  wl.lambda = params_.lambda_normal;
  s.short_num.resize(nb);
  for (std::size_t i = 0; i < nb; ++i)
    s.short_num[i] = beams.ranges[i] < max_range ? mix_.shortNumerator(beams.ranges[i]) : 0.0;
  Hits& h = s.hits;
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
    s.on_pane.resize(nr);
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

    // The rays that met a pane, beam by beam, pane by pane within a beam (the secondary rays of
    // one pane and beam form a coherent group: origins along the pane, nearly one direction).
    h.reset(nr);
    h.beam_start.resize(nb + 1);
    for (std::size_t i = 0; i < nb; ++i) {
      h.beam_start[i] = h.n;
      s.order.clear();
      for (std::size_t k = i * n; k < (i + 1) * n; ++k) {
        const std::int32_t seg = s.segment[k];
        s.on_pane[k] = seg >= 0 && materials_[static_cast<std::size_t>(seg)] == Material::Glass;
        if (s.on_pane[k]) s.order.push_back(static_cast<std::uint32_t>(k));
      }
      const auto by_pane = [&](std::uint32_t a, std::uint32_t b) { return s.segment[a] < s.segment[b]; };
      if (!std::is_sorted(s.order.begin(), s.order.end(), by_pane))
        std::stable_sort(s.order.begin(), s.order.end(), by_pane);
      for (const std::uint32_t k : s.order) {
        const std::size_t g = h.n++;
        const std::int32_t seg = s.segment[k];
        const Pane& pane = panes_[static_cast<std::size_t>(seg)];
        h.ray[g] = k;
        h.pane[g] = seg;
        h.ux[g] = s.ux[k];
        h.uy[g] = s.uy[k];
        h.dx[g] = pane.d.x();
        h.dy[g] = pane.d.y();
        h.dg[g] = s.range[k];
        h.en[g] = h.er[g] = kInf;
      }
    }
    h.beam_start[nb] = h.n;
    h.pad();
    // Their weights: on lanes, or GlassModel::weights one by one.
    if (weights_fn) {
      detail::GlassWeightRays wr;
      wr.ux = h.ux.data();
      wr.uy = h.uy.data();
      wr.dx = h.dx.data();
      wr.dy = h.dy.data();
      wr.theta = h.theta.data();
      wr.wd = h.wd.data();
      wr.wn = h.wn.data();
      wr.wr = h.wr.data();
      weights_fn(wl, wr, (h.n + detail::kGlassPad - 1) / detail::kGlassPad * detail::kGlassPad);
    } else {
      for (std::size_t g = 0; g < h.n; ++g) {
        RayHit hit;
        hit.range = h.dg[g];
        hit.segment = h.pane[g];
        hit.material = Material::Glass;
        hit.incidence = caster_.incidence(h.pane[g], Vec2(h.ux[g], h.uy[g]));
        const GlassModes m = weights(hit);
        h.theta[g] = m.theta_deg;
        h.wd[g] = m.w_direct;
        h.wn[g] = m.w_normal;
        h.wr[g] = m.w_refract;
      }
    }
    // The mirrored and transmitted rays the modes need.
    s.mirror.reset(h.n);
    s.through.reset(h.n);
    walks.clear();
    for (std::size_t i = 0; i < nb; ++i) {
      const auto beam = static_cast<std::uint32_t>(i);
      // The mirrored mode's expected range is d_g + d_o, d_o > 0: for a reading z < z_max only
      // d_o up to z - d_g + kHitReach sigma can make its density non-zero (Mixture::hitDensity
      // is exactly 0 beyond), so the mirrored ray goes no further, and not at all when that is
      // not ahead: the same p as the full cast, bit for bit. (The paper variant's Gaussians have
      // no cutoff; the transmitted ray's elongation can be negative: both cast in full.)
      const double z = beams.ranges[i];
      const double reach =
          variant_ == Variant::Mixture && z < max_range ? z + Mixture::kHitReach * mix_.at(z).sigma : kInf;
      for (std::size_t g = h.beam_start[i]; g < h.beam_start[i + 1]; ++g) {
        const std::int32_t seg = h.pane[g];
        const Vec2 dir(h.ux[g], h.uy[g]);
        const std::uint32_t k = h.ray[g];
        const Vec2 p = Vec2(s.ox[k], s.oy[k]) + h.dg[g] * dir;
        const auto who = static_cast<std::uint32_t>(g);
        const double mirror_range = std::min(max_range, reach) - h.dg[g];
        if (h.wn[g] > kNegligible && mirror_range > 0)
          s.mirror.add(p, mirrored(seg, dir), mirror_range, seg, who, beam);
        if (h.wr[g] > kNegligible && params_.max_panes >= 1) {
          RayHit hit;
          hit.range = h.dg[g];
          hit.segment = seg;
          walks.push_back(transmitted(GlassModes{}, hit, p, dir));
          s.through.add(walks.back().o, dir, max_range - walks.back().travelled, walks.back().skip, who, beam);
        }
      }
    }
    s.mirror.cast(caster_);
    for (std::size_t r = 0; r < s.mirror.size(); ++r) {
      const std::uint32_t g = s.mirror.owner[r];
      h.en[g] = h.dg[g] + s.mirror.range[r];  // +inf when the mirrored ray meets nothing
    }
    // The transmitted rays, one pane further per round.
    while (s.through.size() > 0) {
      s.through.cast(caster_);
      s.next.reset(s.through.size());
      going.clear();
      for (std::size_t r = 0; r < s.through.size(); ++r) {
        const std::uint32_t g = s.through.owner[r];
        const Vec2 dir(h.ux[g], h.uy[g]);
        RayHit next;
        next.range = s.through.range[r];
        next.segment = s.through.segment[r];
        if (next.segment >= 0) next.material = materials_[static_cast<std::size_t>(next.segment)];
        Transmitted& t = walks[r];
        if (goesOn(t, next, dir, h.er[g])) {
          s.next.add(t.o, dir, max_range - t.travelled, t.skip, g, s.through.group[r]);
          going.push_back(t);
        }
      }
      std::swap(s.through, s.next);
      walks.swap(going);
    }

    // Probabilities (on lanes where the CPU has them: a beam's wall and no-hit rays, and for the
    // mixture variant its pane hits), then each pose's sum of logs as sumLogProbabilities forms it.
    s.fix.resize(nr);
    for (std::size_t i = 0; i < nb; ++i) {
      const double z = beams.ranges[i], short_num = s.short_num[i];
      const Mixture mix = mix_.at(z);
      const bool lanes = lanes_fn && z < max_range;
      if (lanes) {
        const detail::MixtureLanes ml = detail::lanesFor(mix, z, max_range, short_num);
        lanes_fn(ml, &s.range[i * n], &s.p[i * n], &s.fix[i * n], n);
        const std::size_t g0 = h.beam_start[i], count = h.beam_start[i + 1] - g0;
        if (modes_fn && variant_ == Variant::Mixture && count > 0) {
          detail::GlassModeRays mr;
          mr.dg = &h.dg[g0];
          mr.en = &h.en[g0];
          mr.er = &h.er[g0];
          mr.wd = &h.wd[g0];
          mr.wn = &h.wn[g0];
          mr.wr = &h.wr[g0];
          mr.p = &h.p[g0];
          mr.fix = &h.fix[g0];
          // Padded up: the lanes past this beam's hits write entries the next beam rewrites.
          modes_fn(ml, mr, (count + detail::kGlassPad - 1) / detail::kGlassPad * detail::kGlassPad);
        } else {
          std::fill(h.fix.begin() + static_cast<std::ptrdiff_t>(g0),
                    h.fix.begin() + static_cast<std::ptrdiff_t>(g0 + count), std::uint8_t{1});
        }
      } else {
        for (std::size_t g = h.beam_start[i]; g < h.beam_start[i + 1]; ++g) h.fix[g] = 1;
      }
      for (std::size_t k = i * n; k < (i + 1) * n; ++k) {
        if (!s.on_pane[k] && (!lanes || s.fix[k])) s.p[k] = mix.probability(z, s.range[k], max_range, short_num);
      }
      for (std::size_t g = h.beam_start[i]; g < h.beam_start[i + 1]; ++g) {
        if (!h.fix[g]) {
          s.p[h.ray[g]] = h.p[g];
          continue;
        }
        GlassModes m;
        m.d_g = h.dg[g];
        m.theta_deg = h.theta[g];
        m.w_direct = h.wd[g];
        m.w_normal = h.wn[g];
        m.w_refract = h.wr[g];
        m.e_normal = h.en[g];
        m.e_refract = h.er[g];
        s.p[h.ray[g]] = fromModes(mix, m, z, max_range, short_num);
      }
    }
    // (beam by beam over the poses: the same products and sums per pose, on vector registers)
    s.sum.assign(n, 0.0);
    s.block.assign(n, 1.0);
    double* sum = s.sum.data();
    double* block = s.block.data();
    for (std::size_t i = 0; i < nb; ++i) {
      const double* p = &s.p[i * n];
      for (std::size_t j = 0; j < n; ++j) block[j] *= p[j];
      if ((i & 7) == 7) {
        for (std::size_t j = 0; j < n; ++j) {
          sum[j] += std::log(block[j]);
          block[j] = 1.0;
        }
      }
    }
    for (std::size_t j = 0; j < n; ++j) out[j0 + j] = sum[j] + std::log(block[j]);
  }
}

}  // namespace glassmap::sensor
