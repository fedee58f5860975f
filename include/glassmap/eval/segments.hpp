#pragma once
/// Segment-level evaluation of a vector floorplan against the true one: length-weighted precision,
/// recall and F1 of glass and of walls, pane-angle error, and over-segmentation of glass.

#include <cstddef>

#include "glassmap/geometry/vector_map.hpp"

namespace glassmap::eval {

/// Options of the comparison.
struct SegmentEvalOptions {
  double tolerance = 0.10;    ///< a sample matches within this distance of a same-material segment [m]
  double sample_step = 0.02;  ///< samples along every segment at most this far apart [m]
};

/// Length-weighted detection scores of one material.
///
/// Every segment is sampled every sample_step; a predicted sample is correct when a true segment of
/// the same material lies within the tolerance, a true sample is found when a predicted one does.
/// precision = correct predicted length / predicted length (1 when nothing is predicted),
/// recall = found true length / true length (1 when there is no truth), F1 their harmonic mean.
struct MaterialScores {
  double truth_length = 0.0;    ///< [m]
  double pred_length = 0.0;     ///< [m]
  double found_length = 0.0;    ///< true length within tolerance of a prediction [m]
  double correct_length = 0.0;  ///< predicted length within tolerance of the truth [m]
  double precision = 0.0;
  double recall = 0.0;
  double f1 = 0.0;
  std::size_t truth_segments = 0;
  std::size_t pred_segments = 0;
};

/// Scores of a predicted floorplan.
struct SegmentEvalResult {
  double tolerance = 0.10;  ///< [m]
  MaterialScores glass;
  MaterialScores wall;
  double glass_angle_error_deg =
      0.0;  ///< mean direction error of correct predicted glass against the nearest true pane, length-weighted [deg]
  double oversegmentation = 0.0;         ///< predicted glass segments / true glass segments (0 if no truth)
  std::size_t panes_found = 0;           ///< true glass segments with some length found
  double segments_per_found_pane = 0.0;  ///< mean number of predicted glass segments matching a found true pane
  double longest_false_glass = 0.0;      ///< longest stretch of predicted glass matching no true glass [m]
};

/// Compares pred against truth. Brute force over segment pairs with box culling: fine for floorplans
/// of up to a few thousand segments.
SegmentEvalResult evaluateSegments(const VectorMap& truth, const VectorMap& pred,
                                   const SegmentEvalOptions& options = {});

}  // namespace glassmap::eval
