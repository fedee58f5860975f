#include "glassmap/sim/simulator.hpp"

#include <tbb/parallel_for.h>

#include <cmath>
#include <random>

#include "glassmap/core/error.hpp"
#include "glassmap/core/split_mix.hpp"
#include "glassmap/geometry/optics.hpp"
#include "glassmap/geometry/ray_caster.hpp"
#include "glassmap/sim/sensor_profile.hpp"
#include "trajectory.hpp"

namespace glassmap::sim {
namespace {

constexpr std::size_t kOutcomes = static_cast<std::size_t>(BeamOutcome::kCount);

// A group of people walking in a straight line, bouncing off the floor's bounding box.
struct Walker {
  Vec2 start;
  Vec2 velocity;
  std::vector<Vec2> offsets;  // members around the group centre
};

Vec2 bounce(const Vec2& p, const Eigen::AlignedBox2d& box) {
  Vec2 out;
  for (int i = 0; i < 2; ++i) {
    const double lo = box.min()[i], span = box.max()[i] - box.min()[i];
    if (span <= 0) {
      out[i] = lo;
      continue;
    }
    double u = std::fmod(p[i] - lo, 2 * span);
    if (u < 0) u += 2 * span;
    out[i] = lo + (u <= span ? u : 2 * span - u);
  }
  return out;
}

std::vector<Walker> makeWalkers(const PeopleSpec& spec, const Eigen::AlignedBox2d& box, std::mt19937_64& rng) {
  std::vector<Walker> walkers;
  if (spec.density <= 0 || box.isEmpty()) return walkers;
  const Vec2 size = box.max() - box.min();
  const double people = spec.density * size.x() * size.y() / 100.0;
  const int groups = static_cast<int>(std::lround(people / spec.group_size));
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int g = 0; g < groups; ++g) {
    Walker w;
    w.start = box.min() + Vec2(u(rng) * size.x(), u(rng) * size.y());
    const double heading = 2 * kPi * u(rng);
    w.velocity = spec.speed * Vec2(std::cos(heading), std::sin(heading));
    const Vec2 side(-std::sin(heading), std::cos(heading));
    for (int m = 0; m < spec.group_size; ++m)
      w.offsets.push_back(side * (m - 0.5 * (spec.group_size - 1)) * (2.4 * spec.radius));
    walkers.push_back(std::move(w));
  }
  return walkers;
}

// Distance along the ray (o, d) to the first crossing of a disc, +inf if none.
double rayDisc(const Vec2& o, const Vec2& d, const Vec2& c, double r) {
  const Vec2 oc = o - c;
  const double b = oc.dot(d);
  const double q = oc.squaredNorm() - r * r;
  const double disc = b * b - q;
  if (disc < 0) return std::numeric_limits<double>::infinity();
  const double t = -b - std::sqrt(disc);
  return t > 0 ? t : std::numeric_limits<double>::infinity();
}

struct BeamResult {
  double range;
  BeamOutcome outcome;
};

// Follows one beam through glass: direct return, specular reflection or transmission at each pane.
BeamResult traceBeam(const RayCaster& caster, const Scene& scene, Vec2 origin, Vec2 dir,
                     const std::vector<Vec2>& people, std::mt19937_64& rng) {
  const GlassPhysics& glass = scene.glass;
  const double max_range = scene.laser.max_range;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  double path = 0.0;        // geometric length travelled so far [m]
  double elongation = 0.0;  // extra time-of-flight range from glass crossed [m]
  bool reflected = false, transmitted = false;
  std::int32_t skip = -1;
  for (int bounce = 0; bounce <= glass.max_bounces; ++bounce) {
    const double remaining = max_range - path - elongation;
    if (remaining <= 0) break;
    const RayHit hit = caster.cast(origin, dir, remaining, skip);
    double person = std::numeric_limits<double>::infinity();
    for (const Vec2& c : people) person = std::min(person, rayDisc(origin, dir, c, scene.people.radius));
    if (person < remaining && (!hit.hit() || person < hit.range))
      return {path + person + elongation, BeamOutcome::Person};
    if (!hit.hit()) break;
    path += hit.range;
    const auto classify = [&] {
      return reflected ? BeamOutcome::GlassReflected
                       : (transmitted ? BeamOutcome::GlassTransmitted : BeamOutcome::Wall);
    };
    if (hit.material == Material::Wall) return {path + elongation, classify()};

    // Glass. Direct return: the specular echo re-enters the receiver mostly near normal incidence,
    // with a floor at any angle (scatter from dirt and coatings).
    const double theta = hit.incidence;
    const double sigma = deg2rad(glass.direct_sigma_deg);
    const double p_direct =
        glass.direct_floor + (glass.direct_peak - glass.direct_floor) * std::exp(-theta * theta / (2 * sigma * sigma));
    if (uniform(rng) < p_direct) return {path + elongation, BeamOutcome::GlassDirect};
    const Vec2 point = origin + hit.range * dir;
    const MapSegment& pane = caster.map().segments[static_cast<std::size_t>(hit.segment)];
    const double p_reflect =
        std::max(glass.reflection_floor, std::min(1.0, glass.reflection_gain * reflectance(theta, 1.0, glass.n_glass)));
    if (uniform(rng) < p_reflect) {
      // Specular reflection: mirror the direction about the pane; the reading is the whole path.
      const Vec2 t = pane.direction();
      dir = (2.0 * dir.dot(t) * t - dir).normalized();
      reflected = true;
    } else {
      // Transmission: the beam goes on (lateral shift neglected), slowed inside the pane.
      const double thickness = glass.pane_thickness > 0 ? glass.pane_thickness : pane.thickness;
      elongation += paneRangeElongation(thickness, theta, glass.n_glass);
      transmitted = true;
    }
    origin = point;
    skip = hit.segment;
  }
  return {max_range, BeamOutcome::MaxRange};
}

// Replaces the traced reading by a spurious one with the laser's rates (Probabilistic Robotics
// 6.3: max, random, short); true if it did. Draws nothing when all rates are 0, so a laser without
// spurious readings sees the same random numbers as before they existed.
bool spuriousReading(BeamResult& beam, const LaserSpec& laser, std::mt19937_64& rng) {
  if (laser.dropout_rate <= 0 && laser.random_rate <= 0 && laser.short_rate <= 0) return false;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double u = uniform(rng);
  double cut = laser.dropout_rate;
  if (u < cut) {
    if (beam.outcome == BeamOutcome::MaxRange) return false;  // nothing there to drop
    beam = {laser.max_range, BeamOutcome::Dropout};
    return true;
  }
  if (u < (cut += laser.random_rate)) {
    beam = {laser.max_range * uniform(rng), BeamOutcome::Random};
    return true;
  }
  if (u < cut + laser.short_rate) {
    // Density ~ exp(-lambda z) truncated to [0, z_true], sampled by inverting its CDF.
    const double z_true =
        beam.outcome == BeamOutcome::MaxRange ? laser.max_range : std::min(beam.range, laser.max_range);
    const double v = uniform(rng);
    const double l = laser.short_lambda;
    const double z = l > 0 ? -std::log1p(-v * -std::expm1(-l * z_true)) / l : v * z_true;
    beam = {std::min(z, z_true), BeamOutcome::Short};
    return true;
  }
  return false;
}

}  // namespace

const char* toString(BeamOutcome o) {
  switch (o) {
    case BeamOutcome::Wall: return "wall";
    case BeamOutcome::GlassDirect: return "glass_direct";
    case BeamOutcome::GlassReflected: return "glass_reflected";
    case BeamOutcome::GlassTransmitted: return "glass_transmitted";
    case BeamOutcome::Person: return "person";
    case BeamOutcome::MaxRange: return "max_range";
    case BeamOutcome::Dropout: return "dropout";
    case BeamOutcome::Short: return "short";
    case BeamOutcome::Random: return "random";
    case BeamOutcome::kCount: break;
  }
  return "?";
}

SimResult simulate(const Scene& scene, const SimOptions& options) {
  const LaserSpec& laser = scene.laser;
  validateSensor(laser, scene.glass);
  const double dt = 1.0 / laser.rate;
  std::vector<Pose2> truth = sampleTrajectory(scene.trajectory, dt, options.duration_limit, options.repeat_until_limit);
  const std::vector<Pose2> untouched = options.kidnap.time >= 0 ? truth : std::vector<Pose2>{};
  const std::size_t kidnapped = applyKidnap(truth, dt, options.kidnap, [&](double seconds) {
    return sampleTrajectory(scene.trajectory, dt, seconds, options.repeat_until_limit);
  });
  std::mt19937_64 odom_rng(splitMix64(options.seed ^ 0x0d0d0d0dULL));
  const std::vector<Pose2> odom = simulateOdometry(truth, scene.motion, odom_rng, kidnapped);
  std::mt19937_64 people_rng(splitMix64(options.seed ^ 0x9e0b1eULL));
  const Eigen::AlignedBox2d box = scene.map.bounds();
  const std::vector<Walker> walkers = makeWalkers(scene.people, box, people_rng);

  const RayCaster caster(scene.map);
  const std::size_t beams = static_cast<std::size_t>(std::lround(laser.fov / laser.resolution)) + 1;
  const std::size_t n = truth.size();

  SimResult result;
  result.log.scans.resize(n);
  result.log.odometry.resize(n);
  result.ground_truth.resize(n);
  result.outcomes.assign(n, std::vector<BeamOutcome>(beams, BeamOutcome::MaxRange));

  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t k) {
    std::mt19937_64 rng(splitMix64(options.seed + 0x5ca9ULL * (k + 1)));
    std::normal_distribution<double> gauss(0.0, 1.0);
    const double time = static_cast<double>(k) * dt;
    const Pose2 T_map_laser = truth[k] * laser.T_base_laser;

    std::vector<Vec2> people;
    for (const Walker& w : walkers) {
      const Vec2 centre = bounce(w.start + time * w.velocity, box);
      for (const Vec2& off : w.offsets) {
        const Vec2 c = centre + off;
        const double dist = (c - T_map_laser.t).norm();
        // A person never stands on the robot; far people cannot cut a beam.
        if (dist > scene.people.radius + 0.3 && dist < laser.max_range + scene.people.radius) people.push_back(c);
      }
    }

    LaserScan& scan = result.log.scans[k];
    scan.timestamp = time;
    scan.start_angle = -0.5 * static_cast<double>(beams - 1) * laser.resolution;
    scan.angular_step = laser.resolution;
    scan.max_range = laser.max_range;
    scan.ranges.resize(beams);
    scan.laser_pose = Pose2(T_map_laser.t + scene.motion.slam_sigma_xy * Vec2(gauss(rng), gauss(rng)),
                            T_map_laser.theta + scene.motion.slam_sigma_theta * gauss(rng));
    scan.odom_pose = odom[k];
    scan.has_odom = true;
    for (std::size_t i = 0; i < beams; ++i) {
      const double angle = T_map_laser.theta + scan.beamAngle(i);
      BeamResult beam = traceBeam(caster, scene, T_map_laser.t, Vec2(std::cos(angle), std::sin(angle)), people, rng);
      if (!spuriousReading(beam, laser, rng) && beam.outcome != BeamOutcome::MaxRange) {
        const double sigma = laser.range_sigma_rel > 0
                                 ? std::hypot(laser.range_sigma, laser.range_sigma_rel * beam.range)
                                 : laser.range_sigma;
        beam.range += sigma * gauss(rng);
        if (beam.range >= laser.max_range) beam.outcome = BeamOutcome::MaxRange;
      }
      const bool max_reading = beam.outcome == BeamOutcome::MaxRange || beam.outcome == BeamOutcome::Dropout;
      scan.ranges[i] =
          max_reading ? static_cast<float>(laser.max_range) : static_cast<float>(std::max(0.0, beam.range));
      result.outcomes[k][i] = beam.outcome;
    }
    StampedPose& o = result.log.odometry[k];
    o.timestamp = time;
    o.pose = odom[k];
    result.ground_truth[k] = {time, T_map_laser, 0.0, 0.0};
  });

  for (std::size_t k = 0; k + 1 < n; ++k) {
    const Pose2 d = odom[k].between(odom[k + 1]);
    result.log.odometry[k].tv = d.t.norm() / dt;
    result.log.odometry[k].rv = d.theta / dt;
  }
  if (kidnapped > 0)
    result.kidnap = KidnapEvent{kidnapped, result.ground_truth[kidnapped].timestamp,
                                untouched[kidnapped] * laser.T_base_laser, result.ground_truth[kidnapped].pose};
  for (const auto& scan : result.outcomes)
    for (BeamOutcome o : scan) ++result.counts[static_cast<std::size_t>(o)];
  result.log.stats.scans = n;
  static_assert(kOutcomes == 9);
  return result;
}

}  // namespace glassmap::sim
