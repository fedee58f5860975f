#include "glassmap/glass/scan_coherence.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include <boost/math/distributions/normal.hpp>

namespace glassmap::glass::sparse {

namespace {

// A run's return rate per incidence bin, from its beams (a Jeffreys prior keeps an empty bin's rate
// off 0 and 1). Not per place along the run as well: a person's run is as short as its places are
// few, and rates per place would absorb its scans.
class BinRates {
 public:
  BinRates(const NearNormalBeam* first, const NearNormalBeam* last, double bin_width) : width_(bin_width) {
    for (const NearNormalBeam* b = first; b != last; ++b) {
      auto& c = counts_[binOf(*b)];
      c.first += b->returned;
      c.second += 1.0;
    }
  }
  double operator()(const NearNormalBeam& b) const {
    const auto& c = counts_.at(binOf(b));
    return (c.first + 0.5) / (c.second + 1.0);
  }

 private:
  std::uint32_t binOf(const NearNormalBeam& b) const { return static_cast<std::uint32_t>(b.incidence / width_); }
  double width_;
  std::map<std::uint32_t, std::pair<double, double>> counts_;  // returned, met
};

// Calls f(begin, end) for each run's beams [begin, end) of `beams`, sorted by run.
template <class F>
void forEachRun(const std::vector<NearNormalBeam>& beams, F&& f) {
  for (std::size_t begin = 0, end = 0; begin < beams.size(); begin = end) {
    end = begin;
    while (end < beams.size() && beams[end].run == beams[begin].run) ++end;
    f(begin, end);
  }
}

}  // namespace

std::vector<ScanCoherence> scanCoherence(std::vector<NearNormalBeam>& beams, std::size_t runs, double bin_width) {
  // A total order (the threads that collected the beams hand them over in any order): the sums
  // below, and so the figures, do not depend on it.
  std::sort(beams.begin(), beams.end(), [](const NearNormalBeam& a, const NearNormalBeam& b) {
    if (a.run != b.run) return a.run < b.run;
    if (a.scan != b.scan) return a.scan < b.scan;
    if (a.incidence != b.incidence) return a.incidence < b.incidence;
    if (a.returned != b.returned) return a.returned < b.returned;
    return a.along < b.along;
  });
  std::vector<ScanCoherence> out(runs);
  forEachRun(beams, [&](std::size_t begin, std::size_t end) {
    const BinRates rateOf(beams.data() + begin, beams.data() + end, bin_width);
    // Per scan: T_s = (sum of residuals)^2 - sum of variances = sum over pairs i != j of the product
    // of residuals, mean 0 and variance 2 ((sum v)^2 - sum v^2) for independent beams.
    double t = 0.0, var = 0.0, scale = 0.0;
    ScanCoherence& c = out[beams[begin].run];
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
  });
  return out;
}

std::vector<ScanCoherence> placeCoherence(std::vector<NearNormalBeam> beams, std::size_t runs, double bin_width,
                                          double max_dt_s, double max_ds) {
  std::sort(beams.begin(), beams.end(), [](const NearNormalBeam& a, const NearNormalBeam& b) {
    if (a.run != b.run) return a.run < b.run;
    if (a.time != b.time) return a.time < b.time;
    if (a.scan != b.scan) return a.scan < b.scan;
    if (a.along != b.along) return a.along < b.along;
    if (a.incidence != b.incidence) return a.incidence < b.incidence;
    return a.returned < b.returned;
  });
  std::vector<ScanCoherence> out(runs);
  forEachRun(beams, [&](std::size_t begin, std::size_t end) {
    const BinRates rateOf(beams.data() + begin, beams.data() + end, bin_width);
    std::vector<double> residual(end - begin), v(end - begin);
    for (std::size_t i = begin; i < end; ++i) {
      const double q = rateOf(beams[i]);
      residual[i - begin] = (beams[i].returned ? 1.0 : 0.0) - q;
      v[i - begin] = q * (1.0 - q);
    }
    // T = sum over the pairs of the product of residuals: mean 0 and variance sum of v_i v_j for
    // independent beams (the products of two pairs are uncorrelated).
    double t = 0.0, var = 0.0, scale = 0.0;
    ScanCoherence& c = out[beams[begin].run];
    c.beams = end - begin;
    for (std::size_t i = begin; i < end; ++i)
      for (std::size_t j = i + 1; j < end && beams[j].time - beams[i].time <= max_dt_s; ++j) {
        // Scans stamped alike (a log without times) are not known to be moments apart.
        if (!(beams[j].time > beams[i].time) || std::abs(beams[j].along - beams[i].along) > max_ds) continue;
        const double vi = v[i - begin], vj = v[j - begin];
        t += residual[i - begin] * residual[j - begin];
        var += vi * vj;
        scale += std::sqrt(vi * vj);
        ++c.scans;
      }
    c.z = var > 0.0 ? t / std::sqrt(var) : 0.0;
    c.correlation = scale > 0.0 ? t / scale : 0.0;
  });
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
