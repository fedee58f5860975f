#include "glassmap/pipeline/map_log.hpp"

#include <chrono>

#include "glassmap/core/error.hpp"
#include "glassmap/vector/from_evidence.hpp"

namespace glassmap::pipeline {
namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Where the map is computed: logs in absolute coordinates (UTM, a building's survey grid: 10^5 to
// 10^7 m) are mapped in a frame re-centred on their poses, so that no result depends on where the
// frame's origin lies (single-precision values and squared distances lose centimetres out there).
// Logs within 1 km of their origin are mapped where they are. The offset is a multiple of 64 m.
Vec2 localOffset(const LaserLog& log) {
  Eigen::AlignedBox2d box;
  for (const LaserScan& s : log.scans)
    if (s.laser_pose.t.allFinite()) box.extend(s.laser_pose.t);
  if (box.isEmpty()) return Vec2::Zero();
  const Vec2 centre = box.center();
  if (centre.cwiseAbs().maxCoeff() < 1000.0) return Vec2::Zero();
  return (centre / 64.0).array().round().matrix() * 64.0;
}

}  // namespace

const char* toString(MapMethod method) {
  switch (method) {
    case MapMethod::Heuristic: return "heuristic";
    case MapMethod::Direct: return "direct";
    case MapMethod::Mrf: return "mrf";
  }
  return "?";
}

MapMethod parseMapMethod(const std::string& name) {
  for (MapMethod m : {MapMethod::Heuristic, MapMethod::Direct, MapMethod::Mrf})
    if (name == toString(m)) return m;
  throw Error("unknown mapping method '" + name + "' (expected heuristic, direct or mrf)", {}, 0, "method");
}

MapResult mapLog(const LaserLog& input, const MapOptions& options, const Progress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  const Vec2 offset = localOffset(input);
  LaserLog shifted;
  if (!offset.isZero()) {
    shifted.scans = input.scans;
    for (LaserScan& s : shifted.scans) s.laser_pose.t -= offset;
  }
  const LaserLog& log = offset.isZero() ? input : shifted;
  auto report = [&](const char* stage, double f) {
    if (progress) progress(stage, f);
  };
  MapResult out;

  // Cell classifier (paper 2.5.3 heuristic, 2.5.4 direct reflection); the MRF refines Direct's
  // evidence.
  glass::MappingOptions mapping = options.mapping;
  mapping.method = options.method == MapMethod::Heuristic ? glass::Method::Heuristic : glass::Method::Direct;
  glass::MappingResult classified = glass::mapLog(log, mapping, progress);
  out.evidence = std::move(classified.evidence);
  out.stats = classified.stats;
  out.seconds.counts = out.stats.seconds_counts;
  out.seconds.angles = out.stats.seconds_angles;
  out.seconds.classify = out.stats.seconds_classify;

  // MRF over the grid (paper 2.5.5).
  if (options.method == MapMethod::Mrf) {
    report("mrf", 0.0);
    out.mrf = mrf::refine(out.evidence, options.mrf);
    out.seconds.mrf = out.mrf.seconds;
    report("mrf", 1.0);
  }

  // Mirror phantoms: cells drawn by beams a pane folded.
  if (options.phantoms) {
    report("phantoms", 0.0);
    const auto tp = std::chrono::steady_clock::now();
    out.phantoms = glass::suppressMirrorPhantoms(log, mapping.beams, options.phantom, out.evidence);
    out.seconds.phantoms = secondsSince(tp);
    report("phantoms", 1.0);
  }

  // Vector floorplan, then the pane fit of the cells against it.
  if (options.fit_floorplan || options.prune_unfitted_glass) {
    report("vectorize", 0.0);
    out.floorplan = vector::vectorize(vector::toLabelGrid(out.evidence), options.vectorize);
    out.has_floorplan = true;
    out.seconds.vectorize = out.floorplan.stats.seconds;
    report("vectorize", 1.0);
  }
  if (options.prune_unfitted_glass)
    out.pruned_glass = vector::pruneUnfittedGlass(out.evidence, out.floorplan.map, options.prune_tolerance);

  // Back to the log's frame.
  if (!offset.isZero()) {
    out.evidence.geometry.origin += offset;
    for (MapSegment& seg : out.floorplan.map.segments) {
      seg.a += offset;
      seg.b += offset;
    }
  }

  // The later steps relabel cells: count what comes out.
  out.stats.glass_cells = out.evidence.countGlass();
  out.stats.occupied_cells = out.evidence.countOccupied();
  out.seconds.total = secondsSince(t0);
  return out;
}

}  // namespace glassmap::pipeline
