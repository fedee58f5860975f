// RayCaster::castBatch: picks the SIMD kernel the CPU runs (ray_batch_avx2.cpp,
// ray_batch_avx512.cpp) or the scalar walk.
#include "ray_batch.hpp"

#include <cstdlib>
#include <cstring>
#include <limits>

#include "glassmap/geometry/ray_caster.hpp"

namespace glassmap {

namespace {

bool cpuHas(RayIsa isa) {
#if defined(GLASSMAP_RAY_SIMD) && (defined(__x86_64__) || defined(__i386__))
  if (isa == RayIsa::Avx2) return __builtin_cpu_supports("avx2");
  if (isa == RayIsa::Avx512) return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq");
#endif
  return isa == RayIsa::Scalar;
}

RayIsa detect() {
  RayIsa best = cpuHas(RayIsa::Avx512) ? RayIsa::Avx512 : cpuHas(RayIsa::Avx2) ? RayIsa::Avx2 : RayIsa::Scalar;
  if (const char* env = std::getenv("GLASSMAP_RAY_ISA")) {
    RayIsa want = best;
    if (std::strcmp(env, "scalar") == 0) want = RayIsa::Scalar;
    if (std::strcmp(env, "avx2") == 0) want = RayIsa::Avx2;
    if (std::strcmp(env, "avx512") == 0) want = RayIsa::Avx512;
    if (cpuHas(want)) best = want;
  }
  return best;
}

}  // namespace

RayIsa RayCaster::bestIsa() {
  static const RayIsa isa = detect();
  return isa;
}

bool RayCaster::isaAvailable(RayIsa isa) { return isa == RayIsa::Auto || cpuHas(isa); }

const char* RayCaster::isaName(RayIsa isa) {
  switch (isa) {
    case RayIsa::Auto: return "auto";
    case RayIsa::Scalar: return "scalar";
    case RayIsa::Avx2: return "avx2";
    case RayIsa::Avx512: return "avx512";
  }
  return "?";
}

void RayCaster::castBatch(const RayBatch& rays, double* range, std::int32_t* segment, RayIsa isa) const {
  if (isa == RayIsa::Auto || !cpuHas(isa)) isa = bestIsa();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (nx_ == 0) {  // an empty index: nothing is hit
    for (std::size_t i = 0; i < rays.size; ++i) {
      range[i] = kInf;
      if (segment) segment[i] = -1;
    }
    return;
  }
#if defined(GLASSMAP_RAY_SIMD)
  if (isa != RayIsa::Scalar) {
    detail::PacketGrid g;
    g.x0 = origin_.x();
    g.y0 = origin_.y();
    g.x1 = top_.x();
    g.y1 = top_.y();
    g.cell = cell_;
    g.inv_cell = inv_cell_;
    g.nx = nx_;
    g.ny = ny_;
    g.spans = spans_.data();
    g.segs = &flat_.data()->ax;
    g.ids = flat_ids_.data();
    detail::PacketRays r;
    r.ox = rays.ox;
    r.oy = rays.oy;
    r.ux = rays.ux;
    r.uy = rays.uy;
    r.max_range = rays.max_range;
    r.range = rays.range;
    r.skip = rays.skip;
    r.n = rays.size;
    if (isa == RayIsa::Avx512)
      detail::castPacketsAvx512(g, r, range, segment);
    else
      detail::castPacketsAvx2(g, r, range, segment);
    return;
  }
#endif
  for (std::size_t i = 0; i < rays.size; ++i) {
    const double mr = rays.max_range ? rays.max_range[i] : rays.range;
    const std::int32_t skip = rays.skip ? rays.skip[i] : -1;
    const Best best = walk(rays.ox[i], rays.oy[i], rays.ux[i], rays.uy[i], mr, skip);
    const bool hit = best.id != std::numeric_limits<std::int32_t>::max();
    range[i] = hit ? best.t : kInf;
    if (segment) segment[i] = hit ? best.id : -1;
  }
}

}  // namespace glassmap
