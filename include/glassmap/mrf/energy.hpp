#pragma once
/// Pairwise MRF energy over a grid of cells (paper section 2.5.5): integer unary costs per cell
/// and label, one label-pair cost table on the 8-neighbourhood (unit edge weights).
///
/// E(f) = sum_c unary[c][f_c] + sum_{c~d, 8-neighbours, each pair once} pairwise[f_c][f_d]
///
/// Costs are int32 in units of 1/kCostScale (a unary of 1 nat = kCostScale): max-flow on integer
/// capacities is exact, so move energies and solver results are deterministic and comparable.

#include <cstdint>
#include <string>
#include <vector>

#include "glassmap/core/labels.hpp"

namespace glassmap::mrf {

/// Integer cost units per unit of real cost (nats for unaries, Psi units for pairwise).
inline constexpr double kCostScale = 1000.0;

// Labels: glassmap/core/labels.hpp (0 EMP, 1 OCC, 2 + k GLS_k).

/// The energy of one labelling problem.
struct LabelEnergy {
  int width = 0;                  ///< cells along x
  int height = 0;                 ///< cells along y
  int num_labels = 0;             ///< labels per cell
  std::vector<int32_t> unary;     ///< [cell * num_labels + label], cell = y * width + x
  std::vector<int32_t> pairwise;  ///< [a * num_labels + b], symmetric, per 8-neighbour pair
  /// Optional [cls * L * L + a * L + b]: a table per edge direction class (edgeClass), each
  /// symmetric; when set, pairwise must hold their elementwise maximum (the bound that candidate
  /// pruning uses). Empty: pairwise for every edge.
  std::vector<int32_t> pairwise_dir;
  /// Optional [cell]: 1 = solve this cell, 0 = keep its input label fixed. Empty = all active.
  std::vector<uint8_t> active;
  /// Optional [cell]: bit l set = label l is a candidate there (needs num_labels <= 64).
  /// Solvers never move a cell to a label outside its set. Empty = every label everywhere.
  std::vector<uint64_t> candidates;

  std::size_t cells() const { return static_cast<std::size_t>(width) * height; }
  int32_t u(std::size_t cell, int label) const { return unary[cell * num_labels + label]; }
  int32_t psi(int a, int b) const { return pairwise[a * num_labels + b]; }
  /// The pair cost across an edge of direction class cls (edgeClass).
  int32_t psi(int a, int b, int cls) const {
    return pairwise_dir.empty() ? pairwise[a * num_labels + b]
                                : pairwise_dir[(static_cast<std::size_t>(cls) * num_labels + a) * num_labels + b];
  }
  bool isActive(std::size_t cell) const { return active.empty() || active[cell] != 0; }
  bool isCandidate(std::size_t cell, int label) const {
    return candidates.empty() || ((candidates[cell] >> label) & 1U) != 0;
  }
};

/// Direction class of the 8-neighbour offset (dx, dy): 0 horizontal, 1 the (-1, 1) diagonal,
/// 2 vertical, 3 the (1, 1) diagonal (an edge and its reverse share a class).
inline int edgeClass(int dx, int dy) { return dy == 0 ? 0 : dx == 0 ? 2 : (dx == dy ? 3 : 1); }
/// Direction of class cls [rad]: 0, 135, 90, 45 deg.
double edgeClassAngle(int cls);

/// Weights of the glass pairwise table, in Psi units (scaled by kCostScale).
struct PsiWeights {
  double glass_glass = 3.0;  ///< two glass labels of different angle (paper: 3)
  double glass_empty = 0.6;  ///< glass next to empty (paper: 0.6)
  double glass_occ = 0.0;    ///< glass next to occupied (paper: 0, the "free buffer")
  double empty_occ = 0.0;    ///< empty next to occupied (paper: 0)
  /// Pane Psi: the share of glass_empty charged in every direction; the rest is charged by
  /// cos^2 of the angle between the edge and the pane, so empty space across a pane (what glass
  /// looks like) costs nothing and only a pane's ends and gaps pay [-].
  double pane_isotropic = 0.0;
  /// Pane Psi: glass labels whose normals differ by d cost glass_glass * min(1, d / this) (a
  /// truncated linear, hence metric, cost), so neighbours of one pane whose normal estimates fall
  /// into adjacent bins (a wide lobe spreads them) are not charged as two panes meeting [deg].
  double pane_angle_full_deg = 30.0;
};

/// Psi over {EMP, OCC, GLS_0..GLS_{bins-1}} from weights; symmetric, zero diagonal.
std::vector<int32_t> makePsi(int num_glass_bins, const PsiWeights& w);

/// The paper's Psi (section 2.5.5): w_diff between glass labels of different angle, w_glass_empty
/// between glass and empty, 0 otherwise (OCC is free next to anything).
std::vector<int32_t> paperPsi(int num_glass_bins, double w_diff = 3.0, double w_glass_empty = 0.6);

/// Psi variants: Paper (as above); Closed (glass next to OCC costs as much as glass next to EMP,
/// 0.6, so OCC is no longer a free buffer for doubtful glass; best glass F1 on the synthetic
/// floor, see `glassmap bench mrf`); Neutral (EMP next to OCC also costs 0.6, so walls and glass
/// pay the same boundary cost).
///
/// Pane: knows the pane direction of a glass label (normal at k * 180/bins deg, pane direction
/// 90 deg from it). Glass next to empty or occupied costs w (i + (1 - i) cos^2 a), i =
/// pane_isotropic (0), a the angle between the edge and the pane direction: nothing where empty
/// space lies across the pane (what glass looks like), the full w where the pane would go on (a
/// gap or an end). Glass labels of different angle: 3 from 30 deg apart, less below
/// (pane_angle_full_deg). The default of glassmap map. Not storable in the instance file.
enum class PsiKind { Paper, Closed, Neutral, Pane };

/// "paper" / "closed" / "neutral" / "pane".
const char* toString(PsiKind kind);
/// Parses "paper" / "closed" / "neutral" / "pane"; throws glassmap::Error naming the field "psi" otherwise.
PsiKind parsePsi(const std::string& name);

/// The Psi table of a variant over {EMP, OCC, GLS_0..GLS_{bins-1}} (for Pane: the elementwise
/// maximum over the edge directions).
std::vector<int32_t> psiTable(PsiKind kind, int num_glass_bins, const PsiWeights& pane_weights = {});

/// The per-direction tables of a variant ([cls][a][b], 4 classes); empty for the variants whose
/// cost does not depend on the edge direction.
std::vector<int32_t> psiDirectionTables(PsiKind kind, int num_glass_bins, const PsiWeights& w = {});

/// Sets e.pairwise (and e.pairwise_dir for a direction-dependent variant).
void setPsi(LabelEnergy& e, PsiKind kind, int num_glass_bins, const PsiWeights& pane_weights = {});

/// Checks sizes and symmetry; throws glassmap::Error naming the field otherwise.
void validate(const LabelEnergy& e);

/// E(labels), straightforward sum over every cell and every 8-neighbour pair.
int64_t energy(const LabelEnergy& e, const std::vector<uint16_t>& labels);

/// Per cell the label of least unary cost (ties: lowest label).
std::vector<uint16_t> argminLabels(const LabelEnergy& e);

/// Fills e.candidates. margin < 0: lossless pruning, a label is dropped only where some other label
/// beats it whatever the neighbours are (unary gap > 8 * max_n Psi gap), so no minimiser uses it.
/// margin >= 0: keep labels whose unary is within margin of the cell's best (lossy if small).
/// Returns the number of (cell, label) candidate pairs kept.
std::size_t restrictCandidates(LabelEnergy& e, int64_t margin = -1);

/// The lossless pruning's table for e's Psi: gaps[m * L + l] = 8 max_n (Psi(m, n) - Psi(l, n)), the
/// most the neighbours can favour l over m (O(L^3) of Psi; a function of Psi alone).
std::vector<int64_t> candidateGaps(const LabelEnergy& e);

/// restrictCandidates(e) with the table of candidateGaps for e's Psi, made once for instances
/// that share their Psi (the MRF's tiles): the same candidates.
std::size_t restrictCandidates(LabelEnergy& e, const std::vector<int64_t>& gaps);

/// Writes the binary instance: uint32 width, height, labels; int32 unary[cells x labels];
/// int32 pairwise[labels x labels]; little-endian, 8-neighbourhood, unit edge weights.
/// Atomic (temporary name, then rename). Mask and candidate sets are not stored.
void writeInstance(const std::string& path, const LabelEnergy& e);

/// Reads a file written by writeInstance; throws glassmap::Error on a short or malformed file.
LabelEnergy readInstance(const std::string& path);

}  // namespace glassmap::mrf
