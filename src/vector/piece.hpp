#pragma once
// Private to vector/: the segment under construction (Piece), the shared context of one run, and
// the steps of vectorize(), one file each:
//   cloud.cpp    cells of one material -> a point cloud with normals and seed scores
//   pieces.cpp   regions -> pieces: line fits, cuts at gaps, BIC splits
//   glass_lines.cpp  glass cells -> pieces by voting for lines (sparse panes)
//   merge.cpp    collinear merges across gaps, wall faces -> centre lines
//   filter.cpp   pieces the evidence does not support are dropped
//   cleanup.cpp  one-sided walls onto their face, dominant axes, corners
//   vectorize.cpp  the order of the steps, and pieces -> MapSegments

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "fitting.hpp"
#include "glassmap/vector/vectorize.hpp"

namespace glassmap::vector::detail {

/// A segment under construction: its cells, line and extent along the line.
struct Piece {
  std::vector<std::uint32_t> ids;  ///< points of the material's cloud
  Moments moments;
  Vec2 c = Vec2::Zero();   ///< a point of the line
  Vec2 d = Vec2::UnitX();  ///< unit direction
  double t0 = 0, t1 = 0;   ///< extent along d from c [m]
  double thickness = 0;    ///< measured or merged thickness [m]
  bool faces_merged = false;
  bool alive = true;
  std::vector<std::uint32_t> parts;  ///< structure step: the fitted pieces a wall line joined into this one

  Vec2 at(double t) const { return c + t * d; }  ///< the line's point t along d from c
  Vec2 a() const { return at(t0); }
  Vec2 b() const { return at(t1); }
  /// The foot of x on the line.
  Vec2 foot(const Vec2& x) const { return c + d * d.dot(x - c); }
  double length() const { return t1 - t0; }
  Vec2 normal() const { return {-d.y(), d.x()}; }
};

/// What every step of one run reads: the grid, the options, the statistics being filled.
/// Every step works in the grid's own frame (origin at its lower-left corner): the result does not
/// depend on where the map frame puts the grid (UTM coordinates lose nothing). vectorize() moves
/// the segments back into the map frame at the end.
struct Context {
  const LabelGrid& grid;
  const VectorizeOptions& opt;
  VectorizeStats& stats;
  double sigma0_sq;  ///< BIC noise floor [m^2]
  /// Two wall faces this far apart or closer (solid between) are one wall: opt.max_wall_thickness,
  /// or the building's own thicker walls (buildingWallThickness) once the faces were fitted [m].
  double wall_thickness;
  /// Bayesian information criterion of `segments` lines explaining n cells with residual rss.
  double bic(double rss, double n, double segments) const {
    return n * std::log(std::max(rss / n, sigma0_sq)) + segments * opt.params_per_segment * std::log(n);
  }
  /// Code of the cell under p (grid frame); unknown outside the grid.
  std::uint8_t codeAt(const Vec2& p) const {
    const int x = static_cast<int>(std::floor(p.x() / grid.resolution));
    const int y = static_cast<int>(std::floor(p.y() / grid.resolution));
    return x >= 0 && y >= 0 && x < grid.width && y < grid.height ? grid.code(x, y) : kCodeUnknown;
  }
  /// How far a pane's end moves onto a wall (glass_corner_snap, never less than a wall end's
  /// corner_snap) [m].
  double glassCornerSnap() const { return std::max(opt.corner_snap, opt.glass_corner_snap); }
  /// True when the cell under p (grid frame) is free space.
  bool isFree(const Vec2& p) const {
    const int x = static_cast<int>(std::floor(p.x() / grid.resolution));
    const int y = static_cast<int>(std::floor(p.y() / grid.resolution));
    return x >= 0 && y >= 0 && x < grid.width && y < grid.height && grid.code(x, y) == kCodeEmpty;
  }
};

// cloud.cpp
CellCloud makeCloud(const LabelGrid& grid, Material material, const MaterialOptions& mo);
// pieces.cpp
void refit(Piece& p, const CellCloud& cloud, Material material, const Context& ctx);
void piecesOfRegion(const std::vector<std::uint32_t>& region, const CellCloud& cloud, Material material,
                    const MaterialOptions& mo, const Context& ctx, std::vector<Piece>& out);
// glass_lines.cpp
void glassPiecesByVoting(const CellCloud& cloud, const MaterialOptions& mo, const Context& ctx,
                         std::vector<Piece>& out);
// merge.cpp
void mergeCollinear(std::vector<Piece>& pieces, const CellCloud& cloud, Material material, const MaterialOptions& mo,
                    const Context& ctx);
bool unseenGap(const Piece& p, double t, double len, const Context& ctx);
/// The thickest pair of faces that is one wall in this building: opt.max_wall_thickness, or more
/// when the building's long walls seen from both sides are thicker: at least
/// 2 x structure.max_furniture_length of them within a cell and a half (or a tenth) of one
/// separation, then the thickest of those plus a cell (at most opt.max_two_sided_thickness).
double buildingWallThickness(const std::vector<Piece>& pieces, const Context& ctx);
void mergeFaces(std::vector<Piece>& pieces, const CellCloud& cloud, const Context& ctx);
void compact(std::vector<Piece>& pieces);
// filter.cpp
void filterPieces(std::vector<Piece>& pieces, Material material, const MaterialOptions& mo, const CellCloud& cloud,
                  const Context& ctx);
// cleanup.cpp
void alignOneSidedWalls(std::vector<Piece>& walls, const CellCloud& cloud, const Context& ctx);
double dominantAxis(const std::vector<Piece>& walls, const Context& ctx);
void regularize(std::vector<Piece>& pieces, double axis, const Context& ctx);
void snapCorners(std::vector<Piece>& glass, std::vector<Piece>& walls, const Context& ctx);

}  // namespace glassmap::vector::detail
