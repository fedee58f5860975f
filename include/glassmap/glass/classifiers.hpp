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
  double occ_hit_floor = 1e-3;    ///< added to p_hit_occ * P_occ^t (a bounded penalty per beam)
  double prior_glass = 0.05;      ///< prior of glass (all angles) for a candidate cell
  double prior_occupied = 0.35;   ///< prior of OCC for a candidate cell (EMP gets the rest)
  int min_glass_hits = 2;         ///< fewer hits than this: glass labels cost kMaxCost
  double search_cells = 40.0;     ///< d_real is searched this far past the reading [cells]
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

/// Labels every observed cell; candidates by the heuristic, with costs.
CellEvidence classifyHeuristic(const grid::HitMissGrid& counts, const grid::AngleHistograms& histograms,
                               const HeuristicOptions& options);

/// Labels every observed cell; candidates by the direct-reflection posterior, costs = -log posterior.
CellEvidence classifyDirect(const grid::HitMissGrid& counts, const grid::AngleHistograms& histograms,
                            const SigmoidSums& sums, const DirectOptions& options);

/// Bin-averaged direct-reflection lobe: P(hit | GLS at bin distance d) for d = 0 .. bins / 2.
std::vector<double> directLobe(int bins, const DirectOptions& options);

}  // namespace glassmap::glass
