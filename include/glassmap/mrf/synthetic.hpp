#pragma once
/// Synthetic 38-label benchmark instance: a floor of rooms (walls, a third of wall runs with a
/// glass section, diagonal glass panes, clutter) and noisy unary costs that imitate the
/// direct-reflection classifier's confusions, with the ground-truth labelling.

#include <cstdint>
#include <vector>

#include "glassmap/mrf/energy.hpp"

namespace glassmap::mrf {

/// Shape of the synthetic floor and of its unary noise.
struct SyntheticOptions {
  int width = 1000;                   ///< cells along x
  int height = 1000;                  ///< cells along y
  uint64_t seed = 1;                  ///< random seed (same seed, same instance)
  int max_room = 140;                 ///< rooms are split until no side exceeds this [cells]
  int min_room = 40;                  ///< no room side below this [cells]
  double glass_fraction = 1.0 / 3.0;  ///< share of wall runs with a glass section
  double diagonal_fraction = 0.3;     ///< share of rooms with a diagonal pane inside
  double noise = 0.7;                 ///< std-dev of unary noise near structure [nats]
  double salt = 0.05;                 ///< chance a cell near structure gets a spurious favourite label
  double unary_scale = 3.0;           ///< classifier confidence: all unary costs [nats] times this
  int band = 3;                       ///< cells within this distance of structure are uncertain [cells]
};

/// A generated instance and the labelling it was generated from.
struct SyntheticInstance {
  LabelEnergy energy;           ///< unary from the noise model, pairwise = the given Psi
  std::vector<uint16_t> truth;  ///< ground-truth label per cell
};

/// Builds the instance with pairwise table `psi` (numLabels() x numLabels()).
SyntheticInstance makeSyntheticInstance(const SyntheticOptions& o, const std::vector<int32_t>& psi);

/// Glass scores of a labelling against the truth: a cell counts as found when both are glass;
/// angle_correct additionally needs the same angle label.
struct GlassScore {
  int64_t truth_glass = 0;    ///< glass cells in the truth
  int64_t found_glass = 0;    ///< glass cells in the labelling
  int64_t true_positive = 0;  ///< glass in both
  int64_t angle_correct = 0;  ///< same glass label in both
  int64_t glass_to_occ = 0;   ///< true glass labelled OCC (the "free buffer" effect)
  int64_t glass_to_emp = 0;   ///< true glass labelled EMP
  int64_t wrong_cells = 0;    ///< cells whose label differs from the truth
  double f1() const;          ///< 2 TP / (truth + found), glass vs non-glass
};

/// Scores labels against truth (same size).
GlassScore scoreGlass(const std::vector<uint16_t>& truth, const std::vector<uint16_t>& labels);

}  // namespace glassmap::mrf
