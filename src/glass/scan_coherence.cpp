#include "glassmap/glass/scan_coherence.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include <boost/math/distributions/normal.hpp>

namespace glassmap::glass::sparse {

std::vector<ScanCoherence> scanCoherence(std::vector<NearNormalBeam>& beams, std::size_t runs, double bin_width) {
  // A total order (the threads that collected the beams hand them over in any order): the sums
  // below, and so the figures, do not depend on it.
  std::sort(beams.begin(), beams.end(), [](const NearNormalBeam& a, const NearNormalBeam& b) {
    if (a.run != b.run) return a.run < b.run;
    if (a.scan != b.scan) return a.scan < b.scan;
    if (a.incidence != b.incidence) return a.incidence < b.incidence;
    return a.returned < b.returned;
  });
  std::vector<ScanCoherence> out(runs);
  std::size_t begin = 0;
  while (begin < beams.size()) {
    const std::uint32_t run = beams[begin].run;
    std::size_t end = begin;
    while (end < beams.size() && beams[end].run == run) ++end;
    // The run's return rate per incidence bin (a Jeffreys prior keeps an empty bin's rate off 0 and
    // 1). Not per place along the run as well: a person's run is as short as its places are few,
    // and rates per place would absorb its scans.
    std::map<std::uint32_t, std::pair<double, double>> counts;  // returned, met
    auto binOf = [&](const NearNormalBeam& b) { return static_cast<std::uint32_t>(b.incidence / bin_width); };
    for (std::size_t i = begin; i < end; ++i) {
      auto& c = counts[binOf(beams[i])];
      c.first += beams[i].returned;
      c.second += 1.0;
    }
    auto rateOf = [&](const NearNormalBeam& b) {
      const auto& c = counts.at(binOf(b));
      return (c.first + 0.5) / (c.second + 1.0);
    };
    // Per scan: T_s = (sum of residuals)^2 - sum of variances = sum over pairs i != j of the product
    // of residuals, mean 0 and variance 2 ((sum v)^2 - sum v^2) for independent beams.
    double t = 0.0, var = 0.0, scale = 0.0;
    ScanCoherence& c = out[run];
    c.beams = end - begin;
    for (std::size_t s = begin; s < end;) {
      std::size_t e = s;
      double residual = 0.0, v = 0.0, v2 = 0.0, sd = 0.0;
      for (; e < end && beams[e].scan == beams[s].scan; ++e) {
        const double q = rateOf(beams[e]);
        residual += (beams[e].returned ? 1.0 : 0.0) - q;
        v += q * (1.0 - q);
        v2 += q * q * (1.0 - q) * (1.0 - q);
        sd += std::sqrt(q * (1.0 - q));
      }
      if (e - s >= 2) {
        ++c.scans;
        t += residual * residual - v;
        var += 2.0 * (v * v - v2);
        scale += sd * sd - v;  // sum over pairs i != j of sqrt(v_i v_j)
      }
      s = e;
    }
    c.z = var > 0.0 ? t / std::sqrt(var) : 0.0;
    c.correlation = scale > 0.0 ? t / scale : 0.0;
    begin = end;
  }
  return out;
}

std::vector<ScanCoherence> visitCoherence(std::vector<NearNormalBeam> beams, std::size_t runs, double bin_width,
                                          double max_gap_s) {
  std::sort(beams.begin(), beams.end(), [](const NearNormalBeam& a, const NearNormalBeam& b) {
    if (a.run != b.run) return a.run < b.run;
    if (a.time != b.time) return a.time < b.time;
    if (a.scan != b.scan) return a.scan < b.scan;
    if (a.incidence != b.incidence) return a.incidence < b.incidence;
    return a.returned < b.returned;
  });
  std::uint32_t visit = 0;
  for (std::size_t i = 0; i < beams.size(); ++i) {
    const bool next = i > 0 && (beams[i].run != beams[i - 1].run || beams[i].time - beams[i - 1].time > max_gap_s);
    visit += next ? 1 : 0;
    beams[i].scan = visit;
  }
  return scanCoherence(beams, runs, bin_width);
}

bool isTransient(const ScanCoherence& c, double max_p, double min_correlation) {
  if (!(max_p > 0.0) || c.correlation < min_correlation) return false;
  // The z a static surface exceeds with probability max_p.
  return c.z > -boost::math::quantile(boost::math::normal(), max_p);
}

}  // namespace glassmap::glass::sparse
