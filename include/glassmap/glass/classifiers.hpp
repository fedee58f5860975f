#pragma once
/// The paper's two cell classifiers (section 2.5.3 core heuristic, 2.5.4 direct reflection).

#include <cstdint>
#include <vector>

#include "glassmap/glass/evidence.hpp"
#include "glassmap/grid/angle_histograms.hpp"
#include "glassmap/grid/hit_miss_grid.hpp"
#include "glassmap/grid/scan_integration.hpp"

namespace glassmap::glass {

/// Core heuristic (paper 2.5.3): a cell hit from one angle window and missed from the others is
/// glass at that angle: the bin with the most hits is mostly hit, the bins outside it and its two
/// neighbours (the lobe) are mostly missed.
struct HeuristicOptions {
  int min_hits = 2;                   ///< hits in the best bin needed for glass
  double min_window_hit_ratio = 0.3;  ///< hits / (hits + misses) in the best bin
  int min_other_misses = 3;           ///< misses outside the lobe needed for glass
  double max_other_hit_ratio = 0.1;   ///< hits / (hits + misses) outside the lobe
  double occupied_hit_ratio = 0.3;    ///< a non-glass candidate with this hit ratio is OCC, else EMP
  double cost_other = 3.0;            ///< cost [nats] given to every label but the chosen one
  bool operator==(const HeuristicOptions&) const = default;
};

/// Direct-reflection formulation (paper 2.5.4) as a Bayes classifier over the cell's beams:
/// per beam t ending in the cell, P_occ^t = 1 / (1 + exp((d_real - d_range) / res - delta))
/// (the paper's sigmoid, its margin read as cells); GLS_k explains a hit by a direct reflection
/// (lobe exp(-theta^2 / 2 sigma^2), theta the incidence on a pane of normal k) or a spurious
/// return as in EMP, times (1 - P_occ^t), a miss by the complement; OCC a hit by p_hit_occ * P_occ^t, a miss by 1 - p_hit_occ;
/// EMP a hit by p_hit_emp (spurious returns). Sums of logs, normalised over all labels.
struct DirectOptions {
  double sigmoid_margin = 5.0;    ///< delta of the sigmoid [cells] (paper: 5)
  double direct_sigma_deg = 2.0;  ///< angular sigma of the direct-reflection lobe [deg]
  double direct_peak = 0.9;       ///< P(return from the pane) at normal incidence
  double lobe_floor = 1e-3;       ///< least P(hit | glass) far off the lobe
  double direct_floor = 0.0;      ///< the sensor's P(direct return) at any angle (sensor profile);
                                  ///< off the lobe a glass cell returns max(direct_floor, p_hit_emp)
  double p_hit_occ = 0.7;         ///< P(a beam reaching an occupied cell ends there)
  double p_hit_emp = 0.02;        ///< P(a beam through an empty cell ends there): noise, people
  /// Take p_hit_emp from the log (glass::mapLog): the hit rate of the cells a classification with
  /// the value above calls empty, away from the surfaces (emptyHitRate), by Laplace's rule
  /// ((hits + 1) / (beams + 2)). Off by default: tried over 39 random lasers without people it
  /// finds faint panes the fixed 0.02 misses, but people walking leave hits in a few empty cells
  /// that a rate of all empty space makes glass (docs/calibration.md: "The spurious rate from the log").
  bool p_hit_emp_from_log = false;
  double occ_hit_floor = 1e-3;    ///< added to p_hit_occ * P_occ^t (a bounded penalty per beam)
  double prior_glass = 0.05;      ///< prior of glass (all angles) for a candidate cell
  double prior_occupied = 0.35;   ///< prior of OCC for a candidate cell (EMP gets the rest)
  int min_glass_hits = 2;         ///< fewer hits than this: glass labels cost kMaxCost
  double search_cells = 40.0;     ///< d_real is searched this far past the reading [cells]
  double range_sigma = 0.0;       ///< range noise of the readings [m]: spreads a pane's returns (PaneLanding)
  bool operator==(const DirectOptions&) const = default;
};

/// Per-candidate sums of the sigmoid terms over the beams ending in the cell (filled by the
/// direct pass): sum of log(p_hit_occ * P_occ^t + floor) and of log(1 - P_occ^t).
struct SigmoidSums {
  std::vector<float> log_occ;    ///< [candidate]
  std::vector<float> log_glass;  ///< [candidate]
};

/// The second pass of the direct method, one walk per beam: fills the per-angle histograms of the
/// candidates (as grid::integrateAngles) and, for every beam ending in a candidate, finds d_real by
/// continuing the beam through the occupancy map past its reading (first cell with
/// l > l_occupied, at most search_cells past the reading).
SigmoidSums integrateSigmoid(const LaserLog& log, const grid::BeamOptions& beams, const grid::HitMissGrid& counts,
                             const grid::OccupancyModel& occupancy, grid::AngleHistograms& histograms,
                             const DirectOptions& options, grid::IntegrationStats* stats = nullptr,
                             const grid::Progress& progress = {});

/// The fields of `options` that integrateSigmoid reads, every other one at its default: options
/// with equal sigmoidInputs give equal sums (what a later pass may reuse, glass::BeamPasses).
DirectOptions sigmoidInputs(const DirectOptions& options);

/// Labels every observed cell; candidates by the heuristic, with costs.
CellEvidence classifyHeuristic(const grid::HitMissGrid& counts, const grid::AngleHistograms& histograms,
                               const HeuristicOptions& options);

/// How the per-cell counts see a pane's returns. A beam that a pane returns leaves one hit, in the
/// cell its reading falls in (the crossing moved along the beam by the range noise); a beam that
/// passes leaves a miss in every cell of the pane it enters: more than one when it crosses the
/// pane's cells obliquely, or the pane runs diagonally through the grid. So a cell on a pane sees
/// fewer hits per beam than the pane returns. For the cells a pane's line crosses, by the pane's
/// normal bin k and the beams' bin distance d from it: hit(k, d) the hits and miss(k, d) the misses
/// (cells entered more than the miss margin before the reading) that a returned beam leaves there,
/// both per cell a passing beam enters. A pane returning a fraction Q of the beams then shows a
/// cell Q hit / (Q (hit + miss) + 1 - Q) of its beams as hits (cellRate). Estimated by walking
/// sample beams through the grid as the passes do (Amanatides-Woo, a fixed seed: the same table
/// on every machine), readings Gaussian about the crossing.
class PaneLanding {
 public:
  PaneLanding(int bins, double resolution, double range_sigma, double miss_margin);
  int bins() const { return bins_; }
  double hit(int k, int d) const { return hit_[index(k, d)]; }
  double miss(int k, int d) const { return miss_[index(k, d)]; }
  /// P(hit | the cell counted the beam) for a pane cell of normal bin k, beams d bins off, when
  /// the pane returns a fraction q of them.
  double cellRate(int k, int d, double q) const {
    const double h = hit(k, d);
    return q * h / (q * (h + miss(k, d)) + (1.0 - q));
  }

 private:
  std::size_t index(int k, int d) const {
    return static_cast<std::size_t>(k) * static_cast<std::size_t>(bins_ / 2 + 1) + static_cast<std::size_t>(d);
  }
  int bins_;
  std::vector<double> hit_, miss_;
};

/// Labels every observed cell; candidates by the direct-reflection posterior, costs = -log posterior.
/// A pane's returns are expected per cell as the grid and the range noise spread them (PaneLanding
/// with the beams' miss_margin and options.range_sigma: the profile's noise at the log's typical
/// range, set by pipeline::applyProfile; 0 without a profile). With the noise, a noisy laser's
/// panes are glass where the grid alone expected more hits per cell than they get (random:4,
/// 2.7 cm + 1.1% of range, with the fitted lobe: glass room cell F1@2 0.69 without the noise, in
/// a build not kept, 1.00 with it in tools/sensor_sweep.py); before
/// the mirror-image test (opaque_glass.hpp) the same noise let mirror images of walls pass for
/// glass (random:7: precision 0.44), which that test now rejects.
CellEvidence classifyDirect(const grid::HitMissGrid& counts, const grid::AngleHistograms& histograms,
                            const SigmoidSums& sums, const DirectOptions& options,
                            double miss_margin = grid::BeamOptions{}.miss_margin);

/// Hits and misses of the cells a labelling calls empty, away from every surface: what a beam
/// through empty space leaves there (spurious short readings, people walking, dust).
struct EmptyHitRate {
  std::uint64_t hits = 0, misses = 0;  ///< summed over the cells used
  std::size_t cells = 0;               ///< EMP cells farther than the clearance from OCC and glass
  /// hits / (hits + misses); 0 without a beam.
  double rate() const { return hits + misses ? static_cast<double>(hits) / static_cast<double>(hits + misses) : 0.0; }
  /// The rate by Laplace's rule, (hits + 1) / (hits + misses + 2): above 0 when no hit was seen.
  double laplaceRate() const {
    return (static_cast<double>(hits) + 1.0) / (static_cast<double>(hits) + static_cast<double>(misses) + 2.0);
  }
};

/// Sums the counts of the cells `evidence` labels EMP that lie more than `clearance_cells`
/// (Chebyshev distance) from every OCC and glass cell, so that range noise about the surfaces
/// and a pane's returns stay out.
EmptyHitRate emptyHitRate(const grid::HitMissGrid& counts, const CellEvidence& evidence, int clearance_cells);

/// Bin-averaged direct-reflection lobe: P(hit | GLS at bin distance d) for d = 0 .. bins / 2.
std::vector<double> directLobe(int bins, const DirectOptions& options);

}  // namespace glassmap::glass
