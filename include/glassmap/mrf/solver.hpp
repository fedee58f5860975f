#pragma once
/// MRF solvers behind one interface: alpha-beta swap and alpha-expansion by graph cuts
/// (Boost.Graph boykov_kolmogorov_max_flow) and ICM as the baseline.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "glassmap/mrf/energy.hpp"

namespace glassmap::mrf {

/// Stopping rules shared by all solvers.
struct MrfOptions {
  int max_cycles = 100;          ///< upper bound on cycles (a cycle visits every move once)
  double min_cycle_gain = 1e-4;  ///< stop when a cycle lowers E by less than this fraction of |E|
};

/// What a solve did.
struct MrfResult {
  int64_t initial_energy = 0;   ///< E of the input labelling
  int64_t energy = 0;           ///< E of the output labelling, tracked move by move (see solver)
  int cycles = 0;               ///< cycles run
  int64_t moves = 0;            ///< moves that lowered the energy
  int64_t truncated_terms = 0;  ///< expansion: pairwise terms raised to make a move submodular
  double seconds = 0.0;         ///< wall time of solve() [s]
  double cpu_seconds = 0.0;     ///< processor time of solve() [s] (one thread; robust on a busy host)
  bool converged = false;       ///< true if a cycle gained less than min_cycle_gain (not max_cycles)
};

/// A local minimiser of LabelEnergy. labels holds the start labelling on input (inactive cells
/// keep theirs) and the result on output; every solver only ever lowers E.
class MrfSolver {
 public:
  virtual ~MrfSolver() = default;
  virtual MrfResult solve(const LabelEnergy& e, std::vector<uint16_t>& labels) = 0;
  virtual std::string name() const = 0;
};

/// The solvers: ICM (the baseline), alpha-beta swap, alpha-expansion (non-submodular terms
/// truncated so the current labelling keeps its exact energy).
enum class SolverKind { Icm, Swap, Expansion };

/// "icm" / "swap" / "expansion".
const char* toString(SolverKind kind);
/// Parses "icm" / "swap" / "expansion"; throws glassmap::Error naming the field "solver" otherwise.
SolverKind parseSolver(const std::string& name);
/// Every solver, in the order icm, swap, expansion.
std::vector<SolverKind> allSolvers();

/// A solver of the given kind.
std::unique_ptr<MrfSolver> makeSolver(SolverKind kind, const MrfOptions& options = {});

}  // namespace glassmap::mrf
