#pragma once
/// MRF refinement of a mapped grid's cell evidence (paper 2.5.5), tile by tile so that memory
/// stays bounded on large floors.

#include <string>

#include "glassmap/glass/evidence.hpp"
#include "glassmap/mrf/solver.hpp"

namespace glassmap::mrf {

/// Settings of the refinement.
struct RefineOptions {
  SolverKind solver = SolverKind::Expansion;                      ///< graph-cut moves or ICM
  PsiKind psi = PsiKind::Pane;                                    ///< pairwise table (see PsiKind)
  double pane_angle_full_deg = PsiWeights{}.pane_angle_full_deg;  ///< pane Psi: see PsiWeights [deg]
  double unary_weight = 2.0;  ///< scale of the -log posteriors against Psi [-] (see docs/calibration.md)
  int tile = 256;             ///< tile side [cells]; each tile is solved with its border fixed
  int sweeps = 2;             ///< passes over all tiles (later passes see updated borders)
  /// Cells no beam ended in (only passed through) and unseen cells border glass at no cost: they
  /// may be glass that no beam met near its normal (a pane hit in one cell of three leaves its
  /// other cells looking empty), so a sparsely seen pane is not charged for its gaps. They still
  /// count as EMP next to EMP and OCC. false: they count as EMP everywhere (the paper's grid).
  bool unseen_glass_neutral = true;
  /// With unseen_glass_neutral, candidate cells may take the neutral label too, at the cost the
  /// classifier gives it (CellEvidence::neutral_cost): a pane met near its normal in one cell of
  /// three leaves its other cells with hits from any angle (a sensor's floor of direct returns,
  /// spurious readings), which makes them candidates without telling glass from empty. They come
  /// out EMP.
  bool candidates_neutral = true;
  MrfOptions solve;  ///< stopping rules per tile
};

/// What the refinement did.
struct RefineResult {
  int tiles = 0;                   ///< tiles solved (with candidate cells), summed over sweeps
  std::size_t active_cells = 0;    ///< candidate cells in the energy (first sweep)
  std::size_t changed = 0;         ///< cells whose label the MRF changed
  std::int64_t energy_before = 0;  ///< summed tile energies before (first sweep) [1/kCostScale]
  std::int64_t energy_after = 0;   ///< summed tile energies after (last sweep)
  double seconds = 0.0;
};

/// Relabels the candidate cells of `evidence` by minimising unary (weighted costs) + Psi over the
/// 8-neighbourhood. Non-candidate cells keep their label and act as fixed neighbours (unknown
/// cells count as empty). Deterministic.
RefineResult refine(glass::CellEvidence& evidence, const RefineOptions& options = {});

}  // namespace glassmap::mrf
