#pragma once
/// Mirror phantoms: a pane reflects a few beams specularly (paper 2.2, "normal reflection"), and
/// the sensor reports the folded path as if it ran straight on. The returns then draw a mirror
/// image of the room behind the pane: walls where there are none. Where transmitted beams can reach
/// that image they clear it, but an image that falls behind an opaque wall is never cleared.
///
/// Physics gives the test: a beam's return cannot come from straight ahead if its straight path
/// went through a pane and then through a wall well before the reading. Such a beam was folded by
/// the pane. A cell most of whose returns are of that kind was never seen directly: it is a phantom
/// and becomes unknown. Cells reached directly by enough beams keep their label, so a real wall
/// behind glass stays.

#include <cstddef>

#include "glassmap/glass/evidence.hpp"
#include "glassmap/grid/scan_integration.hpp"

namespace glassmap::glass {

/// Parameters of the phantom test.
struct PhantomOptions {
  double glass_margin = 0.15;        ///< the pane must be crossed at least this far before the reading [m]
  double block_margin = 0.30;        ///< ...and then a wall whose line lies at least this far from the
                                     ///< reading [m] (a grazed frame or corner does not block)
  double min_folded_fraction = 0.5;  ///< a cell is a phantom when at least this share of its returns
                                     ///< is folded
};

/// What the phantom test did.
struct PhantomStats {
  std::size_t beams_through_glass = 0;  ///< returned beams whose straight path crossed a pane
  std::size_t folded_beams = 0;         ///< ...and then a wall: impossible as direct returns
  std::size_t cells_cleared = 0;        ///< wall or glass cells relabelled unknown
};

/// Relabels as kUnknown the wall and glass cells of `evidence` whose returns are mostly folded
/// (see above), using the beams of `log` as the mapping used them. Works on any labelling (after
/// the classifier or after the MRF); does nothing when the map holds no glass.
PhantomStats suppressMirrorPhantoms(const LaserLog& log, const grid::BeamOptions& beams, const PhantomOptions& options,
                                    CellEvidence& evidence);

}  // namespace glassmap::glass
