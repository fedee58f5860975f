#pragma once
// Helpers of the particle filter's hypotheses (module-internal).

#include <cstdint>
#include <span>
#include <vector>

#include "glassmap/localize/particle_filter.hpp"

namespace glassmap::localize::detail {

/// log(sum exp(v)); -inf for an empty or all -inf input.
double logSumExp(std::span<const double> v);

/// Key of the (x, y, theta) bin of a pose.
std::int64_t binKey(const Pose2& p, double bin_xy, double bin_theta);

/// Weighted mean of the particles near the heaviest 1 m cell, and their weighted RMS distance
/// from it (all particles) into h.estimate and h.spread.
void summarise(Hypothesis& h);

/// The particles of `h` grouped into modes: connected components of the (x, y, heading) cells
/// whose weight is at least 5% of the mean weight per occupied cell (8-neighbours in position,
/// +-1 in heading, headings wrapping: stragglers between two places do not join them), heaviest
/// first, with each group's share of the weight. Particles in lighter cells belong to no mode.
struct Mode {
  std::vector<std::size_t> members;
  double weight = 0.0;
};
std::vector<Mode> modesOf(const Hypothesis& h, double cell, double heading_bin);

}  // namespace glassmap::localize::detail
