#include "glassmap/glass/classifiers.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "glass_tiles.hpp"
#include "glassmap/core/error.hpp"
#include "glassmap/core/split_mix.hpp"
#include "glassmap/grid/parallel_scans.hpp"
#include "glassmap/grid/traversal.hpp"

namespace glassmap::glass {
namespace {

using grid::AngleHistograms;

// log(1 + exp(x)) without overflow.
double softplus(double x) { return x > 30.0 ? x : std::log1p(std::exp(x)); }

// Evidence with labels of all observed cells: EMP where touched, unknown elsewhere.
CellEvidence baseEvidence(const grid::HitMissGrid& counts, const AngleHistograms& hist) {
  CellEvidence e;
  e.geometry = counts.geometry();
  e.bins = hist.bins();
  e.num_labels = numLabels(e.bins);
  e.label.assign(e.geometry.cells(), kUnknown);
  const auto& g = e.geometry;
  constexpr int T = grid::HitMissGrid::kTileSize;
  for (int ty = 0; ty < g.height; ty += T) {
    for (int tx = 0; tx < g.width; tx += T) {
      if (!counts.tileAllocated(tx, ty)) continue;
      for (int y = ty; y < std::min(ty + T, g.height); ++y) {
        for (int x = tx; x < std::min(tx + T, g.width); ++x) {
          const grid::CellCounts c = counts.get(x, y);
          if ((c.hits | c.misses) != 0) e.label[g.index(x, y)] = kEmpty;
        }
      }
    }
  }
  // Candidates in ascending cell order.
  std::vector<std::pair<std::uint32_t, std::int32_t>> order(hist.size());
  for (std::size_t i = 0; i < hist.size(); ++i)
    order[i] = {hist.cell(static_cast<std::int32_t>(i)), static_cast<std::int32_t>(i)};
  std::sort(order.begin(), order.end());
  e.cells.resize(order.size());
  for (std::size_t i = 0; i < order.size(); ++i) e.cells[i] = order[i].first;
  e.cost.assign(order.size() * static_cast<std::size_t>(e.num_labels), 0.0f);
  return e;
}

// Candidate id (histogram index) for each evidence row, in e.cells order.
std::vector<std::int32_t> histogramIds(const CellEvidence& e, const AngleHistograms& hist) {
  std::vector<std::int32_t> ids(e.cells.size());
  for (std::size_t i = 0; i < e.cells.size(); ++i) {
    const auto c = e.geometry.cellOf(e.cells[i]);
    ids[i] = hist.find(c.x, c.y);
  }
  return ids;
}

// Converts log-likelihoods (+ log priors) of one cell into capped negative log posteriors.
void normalise(const std::vector<double>& ll, float* cost) {
  const double mx = *std::max_element(ll.begin(), ll.end());
  double z = 0.0;
  for (double v : ll) z += std::exp(v - mx);
  const double log_z = mx + std::log(z);
  for (std::size_t l = 0; l < ll.size(); ++l) {
    cost[l] = static_cast<float>(std::min<double>(CellEvidence::kMaxCost, log_z - ll[l]));
  }
}

}  // namespace

PaneLanding::PaneLanding(int bins, double resolution, double range_sigma, double miss_margin) : bins_(bins) {
  if (bins < 1 || !(resolution > 0.0) || !(range_sigma >= 0.0) || !(miss_margin >= 0.0)) {
    throw Error("pane landing: bins >= 1, resolution > 0, range_sigma and miss_margin >= 0 expected");
  }
  const int half = bins / 2;
  hit_.assign(static_cast<std::size_t>(bins) * static_cast<std::size_t>(half + 1), 0.0);
  miss_.assign(hit_.size(), 0.0);
  const double width = kPi / bins;  // bin width [rad]
  // The walk: from before the crossing (the miss margin, the noise and 20 cells: a grazing beam
  // runs along a pane's cells for about that) to past it; in a local grid around the origin.
  const double before = miss_margin + 5.0 * range_sigma + 20.0 * resolution;
  const double after = 5.0 * range_sigma + 20.0 * resolution;
  const int span = static_cast<int>(std::ceil((before + after) / resolution)) + 4;
  grid::GridGeometry g;
  g.resolution = resolution;
  g.width = g.height = 2 * span;
  g.origin = Vec2(-span * resolution, -span * resolution);
  // 512 beams per entry at the default 36 bins; finer bins share about the same total.
  const int samples = std::max(64, 512 * 36 / bins);
  // A pane's orientation and its mirror image across the x axis (bins k and bins - k) meet the
  // grid alike: walk k = 0 .. half and copy.
  tbb::parallel_for(0, half + 1, [&](int k) {
    const double nu = k * width;
    const Vec2 n(std::cos(nu), std::sin(nu));
    const double reach = 0.5 * resolution * (std::abs(n.x()) + std::abs(n.y()));
    for (int d = 0; d <= half; ++d) {
      SplitMix draw(0x5eed0000ULL + static_cast<std::uint64_t>(k) * 1000u + static_cast<std::uint64_t>(d));
      double hits = 0.0, misses = 0.0, entered = 0.0;
      for (int s = 0; s < samples; ++s) {
        // The crossing uniform over a cell (the lattice repeats), the incidence uniform over the bin.
        const Vec2 c(draw.uniform() * resolution, draw.uniform() * resolution);
        double theta = (d - 0.5 + draw.uniform()) * width;
        if (d > 0 && draw.uniform() < 0.5) theta = -theta;
        const Vec2 dir(std::cos(nu + theta), std::sin(nu + theta));
        const auto onPane = [&](int x, int y) { return std::abs(n.dot(g.center(x, y) - c)) <= reach; };
        const Vec2 from = c - before * dir;
        // A beam that passes: a miss in every pane cell it enters.
        grid::traverse(g, from, c + after * dir, [&](int x, int y, double, bool) {
          if (onPane(x, y)) entered += 1.0;
        });
        // A beam the pane returns: its reading about the crossing; a hit where it falls, a miss
        // in the pane cells entered more than the margin before it.
        const double range = before + range_sigma * draw.normal();
        if (!(range > 0.0)) continue;
        grid::traverse(g, from, from + range * dir, [&](int x, int y, double t, bool last) {
          if (!onPane(x, y)) return;
          if (last) {
            hits += 1.0;
          } else if (t * range < range - miss_margin) {
            misses += 1.0;
          }
        });
      }
      const std::size_t i = index(k, d), j = index((bins - k) % bins, d);
      hit_[i] = hit_[j] = entered > 0.0 ? hits / entered : 1.0;
      miss_[i] = miss_[j] = entered > 0.0 ? misses / entered : 0.0;
    }
  });
}

std::vector<double> directLobe(int bins, const DirectOptions& o) {
  // Average of peak * exp(-theta^2 / 2 sigma^2) over the bin's incidence range, by quadrature.
  const double width = 180.0 / bins;
  const double s2 = 2.0 * o.direct_sigma_deg * o.direct_sigma_deg;
  std::vector<double> lobe(static_cast<std::size_t>(bins / 2 + 1));
  constexpr int kSamples = 64;
  for (std::size_t d = 0; d < lobe.size(); ++d) {
    double sum = 0.0;
    for (int i = 0; i < kSamples; ++i) {
      const double theta = (static_cast<double>(d) - 0.5 + (i + 0.5) / kSamples) * width;
      sum += std::exp(-theta * theta / s2);
    }
    lobe[d] = std::clamp(o.direct_peak * sum / kSamples, o.lobe_floor, 1.0 - 1e-6);
  }
  return lobe;
}

SigmoidSums integrateSigmoid(const LaserLog& log, const grid::BeamOptions& beams, const grid::HitMissGrid& counts,
                             const grid::OccupancyModel& occ, AngleHistograms& hist, const DirectOptions& o,
                             grid::IntegrationStats* stats, const grid::Progress& progress) {
  SigmoidSums sums;
  sums.log_occ.assign(hist.size(), 0.0f);
  sums.log_glass.assign(hist.size(), 0.0f);
  const grid::GridGeometry& g = counts.geometry();
  const double res = g.resolution;
  const int bins = hist.bins();
  // Occupied cells of the standard map (l > l_occupied) all have hits, so all are candidates:
  // one flag per candidate answers "occupied?" in the hot loop. Tiles of 4 x 4 cells near
  // candidates: the walks skip the open space between them.
  std::vector<std::uint8_t> occupied(hist.size());
  detail::MarkedTiles near_candidates(g, 4);
  for (std::size_t i = 0; i < hist.size(); ++i) {
    const auto c = g.cellOf(hist.cell(static_cast<std::int32_t>(i)));
    occupied[i] = occ.occupied(counts.get(c.x, c.y)) ? 1 : 0;
    near_candidates.mark(c.x, c.y);
  }
  const double search = o.search_cells * res;
  // A thread's part: its histogram counts, its sums in fixed point (exact integer sums, so the
  // total does not depend on how the scans were shared out), its statistics.
  constexpr double kFixed = 4294967296.0;  // 2^32 per nat
  struct Part {
    std::vector<std::uint16_t> counts;
    std::vector<std::int64_t> log_occ, log_glass;
    grid::IntegrationStats stats;
  };
  tbb::enumerable_thread_specific<Part> parts([&] {
    return Part{
        hist.emptyCounts(), std::vector<std::int64_t>(hist.size(), 0), std::vector<std::int64_t>(hist.size(), 0), {}};
  });
  grid::forScansInParallel(log, progress, parts, [&](const LaserScan& scan, std::size_t, Part& part) {
    grid::IntegrationStats& st = part.stats;
    // No-return beams: grid::integrateNoReturns walks them (with beams.deferNoReturns()).
    grid::forEachBeam(
        scan, beams,
        [&](const grid::Beam& beam) {
          ++st.beams;
          const int bin = grid::angleBin(beam.angle, bins);
          const bool end_inside = beam.hit && g.contains(g.cellAt(beam.to));
          // One walk: per-angle hits/misses of candidates and d_real, the distance to the first
          // occupied cell of the standard map along the beam (where glass is mostly invisible).
          double d_real = std::numeric_limits<double>::infinity();
          std::int32_t end_id = AngleHistograms::kNone;
          const grid::MissTest misses(beam, beams.miss_margin);
          st.cells_traversed +=
              detail::traverseMarked(g, near_candidates, beam.from, beam.to, [&](int x, int y, double t, bool last) {
                const std::int32_t id = hist.find(x, y);
                if (id == AngleHistograms::kNone) return;
                if (end_inside && last) {
                  hist.addHit(part.counts, id, bin);
                  end_id = id;
                } else if (misses(t)) {
                  hist.addMiss(part.counts, id, bin);
                }
                if (occupied[static_cast<std::size_t>(id)] && !std::isfinite(d_real)) d_real = t * beam.range;
              });
          if (end_id == AngleHistograms::kNone) return;
          ++st.hit_beams;
          if (!std::isfinite(d_real)) {  // continue the beam past its reading
            const Vec2 far = beam.to + (search / beam.range) * (beam.to - beam.from);
            st.cells_traversed += grid::traverse(g, beam.to, far, [&](int x, int y, double t, bool) {
              if (t == 0.0) return true;  // the reading's own cell, checked above
              const std::int32_t id = hist.find(x, y);
              if (id == AngleHistograms::kNone || !occupied[static_cast<std::size_t>(id)]) return true;
              d_real = beam.range + t * search;
              return false;
            });
            if (!std::isfinite(d_real)) d_real = beam.range + search;
          }
          // Paper 2.5.4: P_occ^t = 1 / (1 + exp(d_real - d_range - delta)), distances in cells.
          const double x = (d_real - beam.range) / res - o.sigmoid_margin;
          const double log_p_occ = -softplus(x);      // log P_occ^t
          const double log_1m_p_occ = -softplus(-x);  // log (1 - P_occ^t)
          const auto k = static_cast<std::size_t>(end_id);
          part.log_occ[k] += std::llround(kFixed * std::log(o.p_hit_occ * std::exp(log_p_occ) + o.occ_hit_floor));
          part.log_glass[k] += std::llround(kFixed * log_1m_p_occ);
        },
        grid::passBeams(beams));
    ++st.scans;
  });
  std::vector<std::int64_t> log_occ(hist.size(), 0), log_glass(hist.size(), 0);
  grid::IntegrationStats st;
  for (Part& part : parts) {
    hist.merge(part.counts);
    for (std::size_t i = 0; i < hist.size(); ++i) {
      log_occ[i] += part.log_occ[i];
      log_glass[i] += part.log_glass[i];
    }
    st += part.stats;
  }
  for (std::size_t i = 0; i < hist.size(); ++i) {
    sums.log_occ[i] = static_cast<float>(static_cast<double>(log_occ[i]) / kFixed);
    sums.log_glass[i] = static_cast<float>(static_cast<double>(log_glass[i]) / kFixed);
  }
  if (stats) *stats = st;
  return sums;
}

DirectOptions sigmoidInputs(const DirectOptions& o) {
  DirectOptions k;
  k.sigmoid_margin = o.sigmoid_margin;
  k.p_hit_occ = o.p_hit_occ;
  k.occ_hit_floor = o.occ_hit_floor;
  k.search_cells = o.search_cells;
  return k;
}

CellEvidence classifyHeuristic(const grid::HitMissGrid& counts, const AngleHistograms& hist,
                               const HeuristicOptions& o) {
  CellEvidence e = baseEvidence(counts, hist);
  const auto ids = histogramIds(e, hist);
  const int bins = e.bins;
  for (std::size_t i = 0; i < e.cells.size(); ++i) {
    const std::uint16_t* h = hist.hits(ids[i]);
    const std::uint16_t* m = hist.misses(ids[i]);
    int total_h = 0, total_m = 0;
    for (int b = 0; b < bins; ++b) {
      total_h += h[b];
      total_m += m[b];
    }
    // The lobe: the bin with the most hits (ties: more hits in its neighbours) and its two
    // neighbours. Glass: the best bin is mostly hit, the bins outside the lobe mostly missed.
    int best = 0;
    auto lobeHits = [&](int k) { return h[(k + bins - 1) % bins] + h[k] + h[(k + 1) % bins]; };
    for (int k = 1; k < bins; ++k) {
      if (h[k] > h[best] || (h[k] == h[best] && lobeHits(k) > lobeHits(best))) best = k;
    }
    const int lobe_h = lobeHits(best);
    const int lobe_m = m[(best + bins - 1) % bins] + m[best] + m[(best + 1) % bins];
    const int oh = total_h - lobe_h, om = total_m - lobe_m;
    const bool glass = h[best] >= o.min_hits && h[best] >= o.min_window_hit_ratio * (h[best] + m[best]) &&
                       om >= o.min_other_misses && oh <= o.max_other_hit_ratio * (oh + om);
    int label = kEmpty;
    if (glass) {
      label = glassLabel(best);
    } else if (total_h >= o.occupied_hit_ratio * (total_h + total_m)) {
      label = kOccupied;
    }
    e.label[e.cells[i]] = static_cast<std::uint8_t>(label);
    float* c = &e.cost[i * static_cast<std::size_t>(e.num_labels)];
    std::fill(c, c + e.num_labels, static_cast<float>(o.cost_other));
    c[label] = 0.0f;
  }
  return e;
}

CellEvidence classifyDirect(const grid::HitMissGrid& counts, const AngleHistograms& hist, const SigmoidSums& sums,
                            const DirectOptions& o, double miss_margin) {
  if (!(o.prior_glass > 0.0 && o.prior_occupied > 0.0 && o.prior_glass + o.prior_occupied < 1.0)) {
    throw Error("priors must be positive and sum below 1", {}, 0, "prior_glass/prior_occupied");
  }
  CellEvidence e = baseEvidence(counts, hist);
  const auto ids = histogramIds(e, hist);
  const int bins = e.bins;
  const std::vector<double> lobe = directLobe(bins, o);
  const PaneLanding landing(bins, e.geometry.resolution, o.range_sigma, miss_margin);
  const std::size_t span = lobe.size();
  std::vector<double> log_hit(static_cast<std::size_t>(bins) * span), log_miss(log_hit.size());
  for (int k = 0; k < bins; ++k) {
    for (std::size_t d = 0; d < span; ++d) {
      // A glass cell returns a beam by direct reflection (the lobe, and the sensor's floor of
      // direct returns at any angle), as a cell of the pane sees them (PaneLanding), or by the
      // same spurious causes as an empty cell: so glass never explains misses better than EMP
      // does off the lobe, and a floor whose cell rate is at or below the spurious rate changes
      // nothing (the larger of the two explains off-lobe hits; they are not added).
      const int di = static_cast<int>(d);
      const double direct = landing.cellRate(k, di, lobe[d] + (1.0 - lobe[d]) * o.direct_floor);
      const double lobe_cell = landing.cellRate(k, di, lobe[d]);
      const double q = std::max(direct, lobe_cell + (1.0 - lobe_cell) * o.p_hit_emp);
      log_hit[static_cast<std::size_t>(k) * span + d] = std::log(q);
      log_miss[static_cast<std::size_t>(k) * span + d] = std::log1p(-q);
    }
  }
  const double lp_glass = std::log(o.prior_glass / bins), lp_occ = std::log(o.prior_occupied);
  const double lp_emp = std::log(1.0 - o.prior_glass - o.prior_occupied);
  const double lh_emp = std::log(o.p_hit_emp), lm_emp = std::log1p(-o.p_hit_emp);
  const double lm_occ = std::log1p(-o.p_hit_occ);
  // Candidates in parallel, each with its thread's scratch.
  struct Scratch {
    std::vector<double> ll;
    std::vector<int> active;
  };
  tbb::enumerable_thread_specific<Scratch> scratch([&] {
    return Scratch{std::vector<double>(static_cast<std::size_t>(e.num_labels)), {}};
  });
  // One candidate's log-likelihoods plus log priors (from its own histogram only).
  auto likelihoods = [&](std::size_t i, std::vector<double>& ll, std::vector<int>& active) {
    const std::int32_t id = ids[i];
    const std::uint16_t* h = hist.hits(id);
    const std::uint16_t* m = hist.misses(id);
    double total_h = 0, total_m = 0;
    active.clear();
    for (int b = 0; b < bins; ++b) {
      total_h += h[b];
      total_m += m[b];
      if (h[b] | m[b]) active.push_back(b);
    }
    ll[kEmpty] = lp_emp + total_h * lh_emp + total_m * lm_emp;
    ll[kOccupied] = lp_occ + sums.log_occ[id] + total_m * lm_occ;
    for (int k = 0; k < bins; ++k) {
      double v = lp_glass + sums.log_glass[id];
      const double* lh = &log_hit[static_cast<std::size_t>(k) * span];
      const double* lm = &log_miss[static_cast<std::size_t>(k) * span];
      for (int b : active) {
        int d = std::abs(b - k);
        d = std::min(d, bins - d);
        v += h[b] * lh[d] + m[b] * lm[d];
      }
      ll[glassLabel(k)] = v;
    }
    return total_h;
  };
  auto row = [&](std::size_t i, std::vector<double>& ll, std::vector<int>& active) {
    if (likelihoods(i, ll, active) < o.min_glass_hits) {  // too little evidence for glass: EMP or OCC only
      for (int k = 0; k < bins; ++k) ll[glassLabel(k)] = -std::numeric_limits<double>::infinity();
    }
    normalise(ll, &e.cost[i * static_cast<std::size_t>(e.num_labels)]);
  };
  // Every candidate in parallel, each with its thread's scratch.
  const auto forEachCandidate = [&](auto&& fn) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, e.cells.size(), 1024),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        Scratch& sc = scratch.local();
                        for (std::size_t i = r.begin(); i != r.end(); ++i) fn(i, sc.ll, sc.active);
                      });
  };
  forEachCandidate(row);
  labelByMinimumCost(e);

  // A pane met near its normal in one cell of three leaves its other cells with the hits of any
  // angle, which tell glass from empty little: the classifier calls them EMP on the prior alone.
  // Such a cell next to glass may stand in for the pane's unseen glass in the MRF at its EMP cost
  // plus the evidence its own beams hold against glass of its glass neighbours' orientations (the
  // log-likelihood ratio without the priors, and without the min_glass_hits rule, which is about
  // labels, not evidence).
  e.neutral_cost.assign(e.cells.size(), std::numeric_limits<float>::infinity());
  const auto& g = e.geometry;
  forEachCandidate([&](std::size_t i, std::vector<double>& ll, std::vector<int>& active) {
    if (isGlass(e.label[e.cells[i]])) return;
    const auto c = g.cellOf(e.cells[i]);
    double against = -1.0;  // below 0: no glass neighbour
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if ((dx | dy) == 0 || !g.contains(c.x + dx, c.y + dy)) continue;
        const std::uint8_t l = e.label[g.index(c.x + dx, c.y + dy)];
        if (!isGlass(l)) continue;
        if (against < 0.0) likelihoods(i, ll, active);
        against = std::max({against, 0.0, (ll[kEmpty] - lp_emp) - (ll[l] - lp_glass)});
      }
    if (against < 0.0) return;
    const float emp = e.cost[i * static_cast<std::size_t>(e.num_labels) + kEmpty];
    e.neutral_cost[i] = std::min(CellEvidence::kMaxCost, static_cast<float>(emp + against));
  });
  return e;
}

EmptyHitRate emptyHitRate(const grid::HitMissGrid& counts, const CellEvidence& e, int clearance_cells) {
  const auto& g = e.geometry;
  const int r = std::max(0, clearance_cells);
  // Surfaces dilated by r cells: a running count of surface cells over each row's window, then
  // over each column's.
  std::vector<std::uint8_t> near(g.cells(), 0);
  std::vector<int> run(static_cast<std::size_t>(std::max(g.width, g.height)) + 1);
  for (int y = 0; y < g.height; ++y) {
    const std::size_t row = static_cast<std::size_t>(y) * static_cast<std::size_t>(g.width);
    run[0] = 0;
    for (int x = 0; x < g.width; ++x) {
      const std::uint8_t l = e.label[row + static_cast<std::size_t>(x)];
      run[static_cast<std::size_t>(x) + 1] = run[static_cast<std::size_t>(x)] + (l == kOccupied || isGlass(l));
    }
    for (int x = 0; x < g.width; ++x) {
      const int lo = std::max(0, x - r), hi = std::min(g.width, x + r + 1);
      near[row + static_cast<std::size_t>(x)] = run[static_cast<std::size_t>(hi)] > run[static_cast<std::size_t>(lo)];
    }
  }
  // Columns: how many of rows y - r .. y + r are near a surface in each column, slid row by row.
  EmptyHitRate out;
  std::vector<int> column(static_cast<std::size_t>(g.width), 0);
  const auto slide = [&](int y, int step) {
    if (y < 0 || y >= g.height) return;
    const std::uint8_t* n = &near[static_cast<std::size_t>(y) * static_cast<std::size_t>(g.width)];
    for (int x = 0; x < g.width; ++x) column[static_cast<std::size_t>(x)] += step * n[x];
  };
  for (int y = 0; y < r; ++y) slide(y, 1);
  for (int y = 0; y < g.height; ++y) {
    slide(y + r, 1);
    slide(y - r - 1, -1);
    for (int x = 0; x < g.width; ++x) {
      if (column[static_cast<std::size_t>(x)] > 0 || e.label[g.index(x, y)] != kEmpty) continue;
      const grid::CellCounts c = counts.get(x, y);
      out.hits += c.hits;
      out.misses += c.misses;
      ++out.cells;
    }
  }
  return out;
}

}  // namespace glassmap::glass
