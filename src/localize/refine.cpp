// Mode seeking for competing hypotheses: a local search of the scan's likelihood moves a
// hypothesis's cloud, or a broad hypothesis's best particles, onto the nearest optimum.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "glassmap/localize/particle_filter.hpp"
#include "hypotheses.hpp"

namespace glassmap::localize {

double ParticleFilter::climb(Pose2& x, const sensor::BeamSet& beams) const {
  // Pattern search over x, y, heading with halving steps; a few moves per level keep it local.
  double f = model_.logLikelihood(x, beams);
  double step = opt_.refine_step, turn = opt_.refine_turn;
  for (int level = 0; level < opt_.refine_levels; ++level, step /= 2, turn /= 2) {
    for (int iter = 0; iter < 3; ++iter) {
      bool moved = false;
      const Pose2 trials[6] = {{x.t + Vec2(step, 0), x.theta}, {x.t - Vec2(step, 0), x.theta},
                               {x.t + Vec2(0, step), x.theta}, {x.t - Vec2(0, step), x.theta},
                               {x.t, x.theta + turn},          {x.t, x.theta - turn}};
      for (const Pose2& t : trials) {
        const double v = model_.logLikelihood(t, beams);
        if (v > f) {
          f = v;
          x = t;
          moved = true;
        }
      }
      if (!moved) break;
    }
  }
  return f;
}

void ParticleFilter::refine(Hypothesis& h, const sensor::BeamSet& beams) {
  if (h.particles.empty() || opt_.refine_levels <= 0) return;
  if (h.broad) {
    // The heaviest particle of each of the best places climbs on its own (one per place, so that a
    // leading place does not take every climb); its weight gains what its likelihood gained
    // (annealed as the hypothesis is): random particles near the robot rarely land within a few
    // centimetres of it, but often within the reach of a climb.
    std::vector<std::size_t> order;
    for (const detail::Mode& m : detail::modesOf(h, opt_.cluster_cell, opt_.cluster_heading))
      order.push_back(*std::max_element(m.members.begin(), m.members.end(), [&](std::size_t a, std::size_t b) {
        return h.particles[a].log_w < h.particles[b].log_w;
      }));
    const std::size_t k = std::min<std::size_t>(order.size(), static_cast<std::size_t>(opt_.refine_broad));
    std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(k), order.end(),
                      [&](std::size_t a, std::size_t b) { return h.particles[a].log_w > h.particles[b].log_w; });
    const double inv_t = opt_.global_temperature > 1.0 ? 1.0 / opt_.global_temperature : 1.0;
    std::vector<double> gain(k);
    tbb::parallel_for(std::size_t{0}, k, [&](std::size_t j) {
      Particle& p = h.particles[order[j]];
      const double before = model_.logLikelihood(p.pose, beams);
      gain[j] = climb(p.pose, beams) - before;
    });
    for (std::size_t j = 0; j < k; ++j) {
      h.particles[order[j]].log_w += inv_t * gain[j];
      if (h.log_ratio.size() == h.particles.size()) h.log_ratio[order[j]] += (1.0 - inv_t) * gain[j];
      if (h.last_ll.size() == h.particles.size()) h.last_ll[order[j]] += gain[j];
    }
    std::vector<double> lw(h.particles.size());
    for (std::size_t i = 0; i < lw.size(); ++i) lw[i] = h.particles[i].log_w;
    const double norm = detail::logSumExp(lw);
    for (Particle& p : h.particles) p.log_w -= norm;
    detail::summarise(h);
    return;
  }
  // From the heaviest particle; then the cloud moves rigidly so that it lands on the optimum.
  const auto top = std::max_element(h.particles.begin(), h.particles.end(),
                                    [](const Particle& a, const Particle& b) { return a.log_w < b.log_w; });
  Pose2 x = top->pose;
  climb(x, beams);
  if (x.t == top->pose.t && x.theta == top->pose.theta) return;
  const Pose2 shift = x * top->pose.inverse();
  for (Particle& p : h.particles) p.pose = shift * p.pose;
  h.estimate = shift * h.estimate;
}

}  // namespace glassmap::localize
